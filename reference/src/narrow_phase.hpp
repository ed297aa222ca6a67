// Stages 3-4 of docs/SPEC.md 7.2: contacts against the ground (eq 84), SDF
// volumes (eqs 32-37, 93) and other bodies (eqs 38-43, 85), and waking (eq 81).
#pragma once
#include <vector>

#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/sdf.hpp"
#include "lockstep/physics/sleep.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

namespace narrow {
// eq 84: the contact point is the mean of the sample points whose depth is
// within contact_tolerance of the deepest (face centre, edge midpoint or corner).
template <class T>
struct DeepestPoints {
  T deepest{};
  bool any = false;
  Vec3<T> sum;
  int count = 0;
  // Candidates are offered twice: once to find the deepest, once to average.
  void offer_depth(const T& depth) {
    if (!any || depth > deepest) deepest = depth;
    any = true;
  }
  void offer_point(const T& depth, const Vec3<T>& point, const T& tolerance) {
    if (depth >= deepest - tolerance) { sum += point; ++count; }
  }
  Vec3<T> mean() const {
    const T c = Num<T>::from_int(count);
    return {sum.x / c, sum.y / c, sum.z / c};
  }
};
}  // namespace narrow

template <class T>
void World<T>::narrow_phase() {
  contacts_.clear();
  std::vector<Contact<T>> pair_contacts;
  // Body against body, pairs in ascending (i, j) order.
  for (const auto& [i, j] : pairs_) {
    const Body<T>& A = bodies_[static_cast<std::size_t>(i)];
    const Body<T>& B = bodies_[static_cast<std::size_t>(j)];
    ++counters_.pairs_tested;
    const Overlap<T> o = aabb_overlap(A.p, A.aabb_half, B.p, B.aabb_half);  // eqs 38-43
    if (!o.hit) continue;
    Contact<T> c;
    c.a = i;
    c.b = j;
    c.n = o.normal;
    c.penetration = o.penetration;
    c.point = aabb_contact_point(A.p, A.aabb_half, B.p, B.aabb_half, Num<T>::from_double(0.5));  // eq 85
    pair_contacts.push_back(c);
    ++counters_.body_contacts;
    check_faults(i, "body contact");
  }
  if (scene_.effects.sleep) wake_touched(pair_contacts);

  const T tol = P_.contact_tolerance;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body<T>& b = bodies_[i];
    if (!b.awake()) continue;  // 7.3
    if (scene_.effects.ground && scene_.ground.present) {
      // eqs 44-46 refined by eq 84: every corner below the plane is a contact
      // point (a flat cube gets its 4 bottom corners, an edge 2, a corner 1),
      // in corner order; only the deepest (first on ties) carries the
      // position correction of eq 89, so the body is corrected once.
      int first = static_cast<int>(contacts_.size());
      int deepest = -1;
      for (int k = 0; k < 8; ++k) {
        const Vec3<T> corner = box_corner(b.p, b.R, b.half, k);
        const T depth = ground_y_ - corner.y;
        if (!(depth > T{})) continue;
        Contact<T> c;
        c.a = static_cast<int>(i);
        c.b = -1;
        c.n = Vec3<T>{T{}, Num<T>::from_int(1), T{}};
        c.penetration = depth;
        c.point = corner;
        c.corrects = false;
        if (deepest < 0 || depth > contacts_[static_cast<std::size_t>(deepest)].penetration)
          deepest = static_cast<int>(contacts_.size());
        contacts_.push_back(c);
        ++counters_.ground_contacts;
      }
      if (deepest >= first) contacts_[static_cast<std::size_t>(deepest)].corrects = true;
      check_faults(static_cast<int>(i), "ground contact");
    }
    if (scene_.effects.sdf) {
      for (std::size_t k = 0; k < sdfs_.size(); ++k) {
        const SdfGrid<T>& g = sdfs_[k];
        // eq 93: sample the 8 corners (radius 0) and the centre (radius min h).
        Vec3<T> pts[9];
        T radius[9];
        for (int s = 0; s < 8; ++s) { pts[s] = box_corner(b.p, b.R, b.half, s); radius[s] = T{}; }
        pts[8] = b.p;
        radius[8] = Num<T>::min(b.half.x, Num<T>::min(b.half.y, b.half.z));
        T dist[9], pen[9];
        bool inside[9];
        narrow::DeepestPoints<T> dp;
        int deepest = -1;
        for (int s = 0; s < 9; ++s) {
          inside[s] = sdf_contains(g, pts[s]);
          if (!inside[s]) continue;
          dist[s] = sdf_distance(g, pts[s]);  // eq 33
          pen[s] = radius[s] - dist[s];       // eq 35
          if (!(pen[s] > T{})) { inside[s] = false; continue; }
          if (deepest < 0 || pen[s] > pen[deepest]) deepest = s;
          dp.offer_depth(pen[s]);
        }
        if (deepest < 0) continue;
        const Vec3<T> grad = sdf_gradient(g, pts[deepest]);  // eq 34
        if (length(grad) == T{}) continue;
        const Vec3<T> n = normalize(grad);  // eq 36
        for (int s = 0; s < 9; ++s)
          if (inside[s]) dp.offer_point(pen[s], pts[s] - n * dist[s], tol);  // eq 37
        Contact<T> c;
        c.a = static_cast<int>(i);
        c.b = -2 - static_cast<int>(k);
        c.n = n;
        c.penetration = dp.deepest;
        c.point = dp.mean();
        contacts_.push_back(c);
        ++counters_.sdf_contacts;
        check_faults(static_cast<int>(i), "SDF contact");
      }
    }
  }
  contacts_.insert(contacts_.end(), pair_contacts.begin(), pair_contacts.end());

  // Support contacts (settling, sleep): a normal within acos(support_normal_min) of up.
  std::fill(support_.begin(), support_.end(), -1);
  for (std::size_t ci = 0; ci < contacts_.size(); ++ci) {
    const Contact<T>& c = contacts_[ci];
    if (c.n.y >= P_.support_normal_min && support_[static_cast<std::size_t>(c.a)] < 0)
      support_[static_cast<std::size_t>(c.a)] = static_cast<int>(ci);
    if (c.b >= 0 && -c.n.y >= P_.support_normal_min && support_[static_cast<std::size_t>(c.b)] < 0)
      support_[static_cast<std::size_t>(c.b)] = static_cast<int>(ci);
  }
}

}  // namespace lockstep
