// Stages 5 and 7 of docs/SPEC.md 7.2: sequential impulses (eqs 48-62, 86-88)
// and Baumgarte position correction (eqs 63, 89).
#pragma once
#include <algorithm>
#include <vector>

#include "lockstep/physics/contact.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

namespace solver {
// The contact-side view of body `idx`: the ground, SDF volumes, static and
// sleeping bodies are immovable (inverse mass and inertia 0).
template <class T>
BodyView<T> view_of(const std::vector<Body<T>>& bodies, int idx, const Mat3<T>& identity) {
  BodyView<T> v;
  v.R = identity;
  if (idx < 0) return v;
  const Body<T>& b = bodies[static_cast<std::size_t>(idx)];
  if (!b.awake()) return v;
  v.v = b.v;
  v.w = b.w;
  v.inv_mass = b.inv_mass;
  v.R = b.R;
  v.inv_inertia = b.inv_inertia;
  return v;
}
}  // namespace solver

template <class T>
void World<T>::solve_contacts() {
  const Effects& fx = scene_.effects;
  const T one = Num<T>::from_int(1);
  const Mat3<T> identity{{{one, T{}, T{}}, {T{}, one, T{}}, {T{}, T{}, one}}};
  auto material = [&](int idx, T& e, T& mu) {
    if (idx >= 0) { e = bodies_[static_cast<std::size_t>(idx)].restitution; mu = bodies_[static_cast<std::size_t>(idx)].friction; }
    else if (idx == -1) { e = ground_e_; mu = ground_mu_; }
    else { e = sdf_e_[static_cast<std::size_t>(-2 - idx)]; mu = sdf_mu_[static_cast<std::size_t>(-2 - idx)]; }
  };
  // Prepare: lever arms, approach speed, restitution, effective mass.
  for (Contact<T>& c : contacts_) {
    const BodyView<T> A = solver::view_of(bodies_, c.a, identity);
    const BodyView<T> B = solver::view_of(bodies_, c.b, identity);
    c.r1 = c.point - bodies_[static_cast<std::size_t>(c.a)].p;
    c.r2 = c.b >= 0 ? c.point - bodies_[static_cast<std::size_t>(c.b)].p : Vec3<T>{};
    c.v_n0 = dot(relative_velocity(A, c.r1, B, c.r2), c.n);  // eqs 48-49
    T e1, mu1, e2, mu2;
    material(c.a, e1, mu1);
    material(c.b, e2, mu2);
    c.e = fx.restitution ? low_speed_restitution(combined_restitution(e1, e2), c.v_n0, P_.restitution_min_speed)
                         : T{};  // eqs 50, 76
    if (c.e > T{}) ++counters_.restitution_bounces;
    c.mu = fx.friction ? combined_friction(mu1, mu2) : T{};  // eq 58
    c.k_n = inverse_effective_mass(A, c.r1, B, c.r2, c.n);   // eq 86
    // eq 97: gravity presses a body onto an immovable side; two falling bodies feel none.
    c.g_n = (fx.gravity && B.inv_mass == T{}) ? -dot(P_.gravity, c.n) : T{};
    c.j_n = T{};
    c.j_t = Vec3<T>{};
    check_faults(c.a, "contact preparation");
  }
  // eq 96: warm start from last frame's normal impulse of the same contact
  // (same bodies, same feature), applied in contact order. Friction starts
  // from zero: a warm-started friction impulse on a resting manifold kept
  // re-injecting spin about the normal that 4 iterations did not remove.
  if (!warm_.empty()) {
    for (Contact<T>& c : contacts_) {
      const auto it = std::lower_bound(warm_.begin(), warm_.end(), c, [](const CachedImpulse& w, const Contact<T>& k) {
        return w.a != k.a ? w.a < k.a : (w.b != k.b ? w.b < k.b : w.feature < k.feature);
      });
      if (it == warm_.end() || it->a != c.a || it->b != c.b || it->feature != c.feature) continue;
      if (!(c.k_n > T{})) continue;
      BodyView<T> A = solver::view_of(bodies_, c.a, identity);
      BodyView<T> B = solver::view_of(bodies_, c.b, identity);
      c.j_n = it->j_n;
      apply_impulse(A, c.r1, B, c.r2, c.n * c.j_n);
      if (A.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(c.a)]; b.v = A.v; b.w = A.w; }
      if (B.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(c.b)]; b.v = B.v; b.w = B.w; }
      check_faults(c.a, "warm start impulse");
    }
  }
  // Iterations (eqs 94, 95, 97). A body's contacts with one environment
  // object (its ground corners, its samples of one SDF) form a manifold that
  // is solved Jacobi-style (eq 99): every point's impulse is computed from the
  // same velocities, then all are applied, so a symmetric landing stays
  // symmetric; manifolds and body pairs follow each other Gauss-Seidel-style
  // in contact order.
  std::vector<T> dj(8 + 1);
  std::vector<Vec3<T>> dJ(8 + 1);
  for (int it = 0; it < P_.solver_iterations; ++it) {
    for (std::size_t s = 0; s < contacts_.size();) {
      std::size_t e = s + 1;
      if (contacts_[s].b < 0)
        while (e < contacts_.size() && contacts_[e].a == contacts_[s].a && contacts_[e].b == contacts_[s].b) ++e;
      const int ia = contacts_[s].a, ib = contacts_[s].b;
      BodyView<T> A = solver::view_of(bodies_, ia, identity);
      BodyView<T> B = solver::view_of(bodies_, ib, identity);
      if (!(contacts_[s].k_n > T{})) { s = e; continue; }  // both sides immovable
      if (dj.size() < e - s) { dj.resize(e - s); dJ.resize(e - s); }
      const BodyView<T> A0 = A, B0 = B;
      // eq 99: the manifold's points share one body, so their simultaneous
      // impulses add up; o = sum_k m^-1 / k_n,k is the part of the body's
      // needed velocity change the points deliver together (1 for a unit
      // cube's 4 bottom corners, 2 for 8 sunken corners, 3.8 for a tall thin
      // box standing), and each point's effective mass is scaled by max(1, o).
      T split = one;
      if (e - s > 1) {
        T o{};
        for (std::size_t k = s; k < e; ++k) o += (A.inv_mass + B.inv_mass) / contacts_[k].k_n;
        if (o > one) split = o;
      }
      for (std::size_t k = s; k < e; ++k) {
        Contact<T>& c = contacts_[k];
        ++counters_.solver_contacts;
        const T v_n = dot(relative_velocity(A0, c.r1, B0, c.r2), c.n);  // eqs 48-49
        // Only approaching contacts bounce (the fix of 3.1): the target -e v_n0 uses v_n0 <= 0.
        const T target = contact_target_velocity(c.penetration, c.e, Num<T>::min(c.v_n0, T{}), c.g_n, P_.dt, P_.inv_dt);  // eq 97
        dj[k - s] = accumulate_normal_impulse(c.j_n, v_n, target, c.k_n * split);  // eqs 53, 94, 99
      }
      for (std::size_t k = s; k < e; ++k) {
        if (dj[k - s] == T{}) continue;
        apply_impulse(A, contacts_[k].r1, B, contacts_[k].r2, contacts_[k].n * dj[k - s]);  // eq 87
        ++counters_.normal_impulses;
      }
      // Friction (eqs 56-62, 88, 95); also re-clamps a friction impulse left
      // above mu J_n when J_n has since dropped.
      if (fx.friction) {
        const BodyView<T> A1 = A, B1 = B;
        for (std::size_t k = s; k < e; ++k) {
          Contact<T>& c = contacts_[k];
          dJ[k - s] = Vec3<T>{};
          if (!(c.j_n > T{}) && c.j_t == Vec3<T>{}) continue;
          const Vec3<T> v_tan = tangential_velocity(relative_velocity(A1, c.r1, B1, c.r2), c.n);  // eq 56
          const bool sliding = length(v_tan) > T{};                                               // eq 57
          const T k_t = sliding ? inverse_effective_mass(A1, c.r1, B1, c.r2, normalize(v_tan)) * split : one;  // eqs 60, 88, 99
          dJ[k - s] = accumulate_friction_impulse(c.j_t, v_tan, k_t, c.mu, c.j_n);               // eq 95
        }
        for (std::size_t k = s; k < e; ++k) {
          if (dJ[k - s] == Vec3<T>{}) continue;
          apply_impulse(A, contacts_[k].r1, B, contacts_[k].r2, dJ[k - s]);  // eqs 61-62, 87
          ++counters_.friction_steps;
        }
      }
      if (A.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(ia)]; b.v = A.v; b.w = A.w; }
      if (B.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(ib)]; b.v = B.v; b.w = B.w; }
      check_faults(ia, ib >= 0 ? "contact impulse (with another body)" : "contact impulse");
      s = e;
    }
  }
  warm_.clear();
  for (const Contact<T>& c : contacts_)
    if (c.j_n > T{}) warm_.push_back({c.a, c.b, c.feature, c.j_n});
  std::sort(warm_.begin(), warm_.end(), [](const CachedImpulse& x, const CachedImpulse& y) {
    return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.feature < y.feature);
  });
}

template <class T>
void World<T>::correct_positions() {
  for (const Contact<T>& c : contacts_) {
    // A bouncing contact (e_eff > 0, eq 76) is not corrected: its rebound
    // separates it, and pushing it out as well adds m g penetration of energy
    // per bounce, which kept a cube bouncing at 0.6 m/s for ever.
    if (!c.corrects || c.e > T{}) continue;
    Body<T>& A = bodies_[static_cast<std::size_t>(c.a)];
    const T inv_a = A.awake() ? A.inv_mass : T{};
    Vec3<T> ground_p;
    Body<T>* B = c.b >= 0 ? &bodies_[static_cast<std::size_t>(c.b)] : nullptr;
    const T inv_b = (B != nullptr && B->awake()) ? B->inv_mass : T{};
    if (inv_a == T{} && inv_b == T{}) continue;
    Vec3<T>& pb = B != nullptr ? B->p : ground_p;
    baumgarte_correction(A.p, pb, c.n, c.penetration, inv_a, inv_b, P_.slop, P_.baumgarte);  // eqs 63, 89
    ++counters_.corrections;
    check_faults(c.a, "position correction");
  }
}

}  // namespace lockstep
