// Stages 1 and 8 of docs/SPEC.md 7.2: velocity and position integration, one
// call per awake body of the per-body steps in physics/body_step.hpp.
#pragma once
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/body_step.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

template <class T>
void World<T>::integrate_velocities() {
  const Effects& fx = scene_.effects;
  if (!fx.gravity && !fx.damping) return;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body<T>& b = bodies_[i];
    if (!b.awake()) continue;
    integrate_velocity(b.v, b.w, fx.gravity, fx.damping, P_);  // eqs 1, 5, 6, 13
    if (fx.gravity) ++counters_.integrate_velocity;
    if (fx.damping) ++counters_.damping;
    check_faults(static_cast<int>(i), "velocity (gravity, damping)");
  }
}

template <class T>
void World<T>::integrate_positions() {
  parallel_each(bodies_.size(), 64, [&](std::size_t i, int) {  // each body alone
    Body<T>& b = bodies_[i];
    if (!b.awake()) return;
    integrate_pose(b.p, b.q, b.v, b.w, P_);  // eqs 2, 7-10
    update_derived(b);
    check_faults(static_cast<int>(i), "position/orientation");
  });
  for (const Body<T>& b : bodies_) counters_.integrate_position += b.awake() ? 1u : 0u;
}

// R = mat3(q) and the AABB half extents of eq 31, recomputed when q changes.
template <class T>
void World<T>::update_derived(Body<T>& b) {
  b.R = rotation_matrix(b.q);
  b.aabb_half = rotated_half_extents(b.R, b.half);
}

}  // namespace lockstep
