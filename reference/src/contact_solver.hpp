// Stages 5 and 7 of docs/SPEC.md 7.2: sequential impulses (eqs 48-62, 86-88)
// and Baumgarte position correction (eqs 63, 89).
#pragma once
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
  for (int it = 0; it < P_.solver_iterations; ++it) {
    for (const Contact<T>& c : contacts_) {
      BodyView<T> A = solver::view_of(bodies_, c.a, identity);
      BodyView<T> B = solver::view_of(bodies_, c.b, identity);
      if (A.inv_mass == T{} && B.inv_mass == T{}) continue;
      ++counters_.solver_contacts;
      const Vec3<T> r1 = c.point - bodies_[static_cast<std::size_t>(c.a)].p;
      const Vec3<T> r2 = c.b >= 0 ? c.point - bodies_[static_cast<std::size_t>(c.b)].p : Vec3<T>{};
      const T v_n = dot(relative_velocity(A, r1, B, r2), c.n);  // eqs 48-49
      if (!(v_n < T{})) continue;  // only approaching contacts (the fix of 3.1)
      T e1, mu1, e2, mu2;
      material(c.a, e1, mu1);
      material(c.b, e2, mu2);
      T e{};
      if (fx.restitution) {
        e = low_speed_restitution(combined_restitution(e1, e2), v_n, P_.restitution_min_speed);  // eqs 50, 76
        if (e > T{}) ++counters_.restitution_bounces;
      }
      const T k = inverse_effective_mass(A, r1, B, r2, c.n);  // eq 86
      const T j = normal_impulse(e, v_n, k, one);              // eq 53
      apply_impulse(A, r1, B, r2, c.n * j);                    // eq 87
      ++counters_.normal_impulses;
      if (fx.friction && j > T{}) {
        const Vec3<T> v_tan = tangential_velocity(relative_velocity(A, r1, B, r2), c.n);  // eq 56
        const T v_tan_mag = length(v_tan);                                                // eq 57
        if (v_tan_mag > T{}) {
          const Vec3<T> t = normalize(v_tan);                                             // eq 60
          const T k_t = inverse_effective_mass(A, r1, B, r2, t);                          // eq 88
          const T j_t = friction_impulse(v_tan_mag, k_t, combined_friction(mu1, mu2), j);  // eqs 58, 88
          apply_impulse(A, r1, B, r2, t * (-j_t));                                        // eqs 61-62, 87
          ++counters_.friction_steps;
        }
      }
      if (A.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(c.a)]; b.v = A.v; b.w = A.w; }
      if (B.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(c.b)]; b.v = B.v; b.w = B.w; }
      check_faults(c.a, c.b >= 0 ? "contact impulse (with another body)" : "contact impulse");
    }
  }
}

template <class T>
void World<T>::correct_positions() {
  for (const Contact<T>& c : contacts_) {
    if (!c.corrects) continue;
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
