// Stage 6 of docs/SPEC.md 7.2: settling of supported bodies (eqs 64-75, 77).
#pragma once
#include <algorithm>
#include <vector>

#include "lockstep/physics/body_step.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

template <class T>
Vec3<T> World<T>::support_normal(std::size_t i) const { return support_n_[i]; }

template <class T>
void World<T>::settle() {
  // Supported awake bodies, lowest first (ties: index; narrow_phase's
  // scratch_.settle_order), so that eq 75 sees a supporting body's final velocity
  // before the body it supports.
  const bool oriented = scene_.pair_contacts == PairModel::kOrientedBox;
  if (oriented) {  // eqs 72-74 on a movable support: the spin relative to the support's, as the solver left it
    scratch_.w_solved.resize(bodies_.size());
    for (std::size_t k = 0; k < bodies_.size(); ++k) scratch_.w_solved[k] = bodies_[k].w;
  }
  // A body reads, of the others, only its first support's velocity: each
  // chain of supports runs on its own, lowest first.
  auto other_of = [&](int idx) {
    const Contact<T>& c = contacts_[static_cast<std::size_t>(support_[static_cast<std::size_t>(idx)])];
    return c.a == idx ? c.b : c.a;
  };
  for (int idx : scratch_.settle_order)
    if (!oriented || over_support_[static_cast<std::size_t>(idx)]) ++counters_.settling_bodies;
  in_order_by_groups(scratch_.settle_order, false, other_of, [&](int idx) {
    const auto i = static_cast<std::size_t>(idx);
    Body<T>& b = bodies_[i];
    if (oriented && !over_support_[i]) return;  // eq 112: it tips; settling would hold it back
    const Vec3<T> n = support_normal(i);
    const int other = other_of(idx);  // the first support: whose velocity (75) uses
    const bool movable = other >= 0 && bodies_[static_cast<std::size_t>(other)].awake();
    const Vec3<T> v_support = movable ? bodies_[static_cast<std::size_t>(other)].v : Vec3<T>{};
    // The oriented-box model settles relative to the support (eq 77) and damps
    // spin (eqs 72-74) relative to a movable support's; the AABB model as the source.
    const T speed = settle_linear_velocity(b.v, v_support, n, support_gap_[i], P_, oriented,
                                           settle_limit_[i]);  // eqs 75, 77, 116
    b.w = settle_spin(b.w, oriented && movable, [&] { return scratch_.w_solved[static_cast<std::size_t>(other)]; }, b.R, n,
                      speed, leaning_[i] != 0, P_);  // eqs 64-74, 115, up = support normal
    check_faults(idx, "settling");
  });
}

}  // namespace lockstep
