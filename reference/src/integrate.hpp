// Stages 1 and 8 of docs/SPEC.md 7.2: velocity and position integration.
#pragma once
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

template <class T>
void World<T>::integrate_velocities() {
  const Effects& fx = scene_.effects;
  if (!fx.gravity && !fx.damping) return;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body<T>& b = bodies_[i];
    if (!b.awake()) continue;
    if (fx.gravity) {
      b.v = apply_gravity(b.v, P_.gravity_dt);  // eqs 1, 5
      ++counters_.integrate_velocity;
    }
    if (fx.damping) {
      b.v = apply_damping(b.v, P_.linear_damping_factor);   // eq 6
      b.w = apply_damping(b.w, P_.angular_damping_factor);  // eq 13
      ++counters_.damping;
    }
    check_faults(static_cast<int>(i), "velocity (gravity, damping)");
  }
}

template <class T>
void World<T>::integrate_positions() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body<T>& b = bodies_[i];
    if (!b.awake()) continue;
    b.p = integrate_position(b.p, b.v, P_.dt);        // eq 2
    b.q = integrate_orientation(b.q, b.w, P_.half_dt);  // eqs 7-10
    update_derived(b);
    ++counters_.integrate_position;
    check_faults(static_cast<int>(i), "position/orientation");
  }
}

// R = mat3(q) and the AABB half extents of eq 31, recomputed when q changes.
template <class T>
void World<T>::update_derived(Body<T>& b) {
  b.R = rotation_matrix(b.q);
  b.aabb_half = rotated_half_extents(b.R, b.half);
}

}  // namespace lockstep
