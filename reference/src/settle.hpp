// Stage 6 of docs/SPEC.md 7.2: settling of supported bodies (eqs 64-75, 77).
#pragma once
#include <algorithm>
#include <vector>

#include "lockstep/physics/settle.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

template <class T>
Vec3<T> World<T>::support_normal(std::size_t i) const { return support_n_[i]; }

template <class T>
void World<T>::settle() {
  // Supported awake bodies, lowest first (ties: index), so that eq 75 sees a
  // supporting body's final velocity before the body it supports.
  std::vector<int> order;
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (bodies_[i].awake() && support_[i] >= 0) order.push_back(static_cast<int>(i));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const T& ya = bodies_[static_cast<std::size_t>(a)].p.y;
    const T& yb = bodies_[static_cast<std::size_t>(b)].p.y;
    return ya != yb ? ya < yb : a < b;
  });
  for (int idx : order) {
    const auto i = static_cast<std::size_t>(idx);
    Body<T>& b = bodies_[i];
    ++counters_.settling_bodies;
    const Contact<T>& c = contacts_[static_cast<std::size_t>(support_[i])];  // the first support: whose velocity (75) uses
    const Vec3<T> n = support_normal(i);
    const int other = c.a == idx ? c.b : c.a;
    const Vec3<T> v_support = (other >= 0 && bodies_[static_cast<std::size_t>(other)].awake())
                                  ? bodies_[static_cast<std::size_t>(other)].v : Vec3<T>{};
    b.v = cancel_resting_velocity(b.v, v_support, n, P_.rest_speed);  // eq 75
    const T speed = length(b.v);
    const Alignment<T> al = alignment_of(b.R, n);     // eqs 64-66 (65 fixed), up = support normal
    b.w = righting(b.w, al, n, speed, P_);            // eqs 67-71
    b.w = regime_damping(b.w, al.alignment, P_);      // eqs 72-74
    b.v = settle_linear(b.v, speed, P_);              // eq 77
    check_faults(idx, "settling");
  }
}

}  // namespace lockstep
