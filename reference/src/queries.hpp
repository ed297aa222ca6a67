// docs/SPEC.md Appendix B: queries. They read the state and change nothing;
// they are evaluated in double (a query's answer is not part of the
// bit-exact state), over every body in ascending index order.
#pragma once
#include <cmath>
#include <vector>

#include "lockstep/world.hpp"

namespace lockstep {

namespace query {
struct BoxD { double p[3], R[3][3], h[3]; };
template <class T>
BoxD box_of(const Body<T>& b) {
  BoxD o;
  for (int i = 0; i < 3; ++i) {
    o.p[i] = Num<T>::to_double(b.p[i]);
    o.h[i] = Num<T>::to_double(b.half[i]);
    for (int j = 0; j < 3; ++j) o.R[i][j] = Num<T>::to_double(b.R.row[i][j]);
  }
  return o;
}
// x in the box frame: R^T (x - p).
inline void to_local(const BoxD& b, const double x[3], double out[3], bool is_direction) {
  double d[3];
  for (int i = 0; i < 3; ++i) d[i] = is_direction ? x[i] : x[i] - b.p[i];
  for (int j = 0; j < 3; ++j) out[j] = b.R[0][j] * d[0] + b.R[1][j] * d[1] + b.R[2][j] * d[2];
}
}  // namespace query

// (B.1) raycast: the first oriented box or ground hit along origin + t dir,
// 0 <= t <= max_distance (dir need not be unit; t is in units of |dir|).
// Ties go to the lowest body index; the ground is body -1.
template <class T>
RayHit<T> World<T>::raycast(const Vec3<T>& origin, const Vec3<T>& dir, const T& max_distance) const {
  const double o[3] = {Num<T>::to_double(origin.x), Num<T>::to_double(origin.y), Num<T>::to_double(origin.z)};
  const double d[3] = {Num<T>::to_double(dir.x), Num<T>::to_double(dir.y), Num<T>::to_double(dir.z)};
  double best_t = Num<T>::to_double(max_distance);
  int best = -2;
  double best_n[3] = {0, 0, 0};
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const query::BoxD b = query::box_of(bodies_[i]);
    double lo[3], ld[3];
    query::to_local(b, o, lo, false);
    query::to_local(b, d, ld, true);
    double t0 = 0.0, t1 = best_t;
    int axis = -1;
    double sign = 0.0;
    bool miss = false;
    for (int a = 0; a < 3 && !miss; ++a) {
      if (ld[a] == 0.0) { miss = std::fabs(lo[a]) > b.h[a]; continue; }
      double ta = (-b.h[a] - lo[a]) / ld[a], tb = (b.h[a] - lo[a]) / ld[a];
      double s = -1.0;
      if (ta > tb) { std::swap(ta, tb); s = 1.0; }
      if (ta > t0) { t0 = ta; axis = a; sign = s; }
      if (tb < t1) t1 = tb;
      miss = t0 > t1;
    }
    if (miss || axis < 0 || !(t0 < best_t)) continue;  // axis < 0: the origin is inside the box
    best_t = t0;
    best = static_cast<int>(i);
    for (int r = 0; r < 3; ++r) best_n[r] = b.R[r][axis] * sign;
  }
  if (scene_.ground.present && d[1] < 0.0) {
    const double t = (scene_.ground.height - o[1]) / d[1];
    if (t >= 0.0 && t < best_t) { best_t = t; best = -1; best_n[0] = 0; best_n[1] = 1; best_n[2] = 0; }
  }
  RayHit<T> hit;
  if (best == -2) return hit;
  hit.hit = true;
  hit.body = best;
  hit.distance = Num<T>::from_double(best_t);
  for (int a = 0; a < 3; ++a) {
    hit.point[a] = Num<T>::from_double(o[a] + d[a] * best_t);
    hit.normal[a] = Num<T>::from_double(best_n[a]);
  }
  return hit;
}

// (B.2) the bodies whose AABB (eq 31) overlaps [lo, hi] (touching counts).
template <class T>
std::vector<int> World<T>::overlap_aabb(const Vec3<T>& lo, const Vec3<T>& hi) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body<T>& b = bodies_[i];
    bool overlap = true;
    for (int a = 0; a < 3; ++a)
      overlap = overlap && !(b.p[a] + b.aabb_half[a] < lo[a]) && !(hi[a] < b.p[a] - b.aabb_half[a]);
    if (overlap) out.push_back(static_cast<int>(i));
  }
  return out;
}

// (B.3) the bodies whose oriented box contains p (the surface counts).
template <class T>
std::vector<int> World<T>::point_query(const Vec3<T>& p) const {
  std::vector<int> out;
  const double x[3] = {Num<T>::to_double(p.x), Num<T>::to_double(p.y), Num<T>::to_double(p.z)};
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const query::BoxD b = query::box_of(bodies_[i]);
    double l[3];
    query::to_local(b, x, l, false);
    if (std::fabs(l[0]) <= b.h[0] && std::fabs(l[1]) <= b.h[1] && std::fabs(l[2]) <= b.h[2]) out.push_back(static_cast<int>(i));
  }
  return out;
}

}  // namespace lockstep
