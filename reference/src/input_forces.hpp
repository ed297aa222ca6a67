// Stage 0 of docs/SPEC.md 7.2 (run-time inputs, eq 121): the forces and
// torques given by add_force since the last step act for this step, before
// gravity. In world_impl.hpp (step() calls it) so that the fixed engine's
// certification build, which never applies inputs, compiles it too.
#pragma once
#include "lockstep/physics/integrate.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

// eq 121, in ascending body index: v += (F dt) / m, omega += I^-1_world (tau dt)
// (eq 90), then the pending forces are cleared.
template <class T>
void World<T>::apply_forces() {
  for (const PendingForce& f : forces_) {
    Body<T>& b = bodies_[static_cast<std::size_t>(f.body)];
    if (!b.awake()) continue;  // cannot happen: add_force woke it
    b.v += (f.f * P_.dt) * b.inv_mass;
    b.w += apply_inverse_inertia(b.R, b.inv_inertia, f.tau * P_.dt);
    check_faults(f.body, "velocity (a run-time force, eq 121)");
  }
  forces_.clear();
}

}  // namespace lockstep
