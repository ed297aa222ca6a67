// Stages 4 and 9 of docs/SPEC.md 7.2: wake (5.1, eq 81) and sleep (4.7, eqs 78-80).
#pragma once
#include "lockstep/physics/body_step.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

// eq 81: a contact between an awake and a sleeping body wakes the sleeper when
// the approach is fast or the penetration deep. Decided in contact order with
// the velocities at the start of the solve; a body woken here does not wake
// its own sleeping neighbours before the next frame.
template <class T>
void World<T>::wake_touched(const std::vector<Contact<T>>& pair_contacts) {
  for (const Contact<T>& c : pair_contacts) {
    Body<T>& A = bodies_[static_cast<std::size_t>(c.a)];
    Body<T>& B = bodies_[static_cast<std::size_t>(c.b)];
    Body<T>* sleeper = A.asleep ? &A : (B.asleep ? &B : nullptr);
    if (sleeper == nullptr) continue;
    const Body<T>& other = sleeper == &A ? B : A;
    if (!other.awake()) continue;  // a sleeper touched by a sleeper or a static body
    if (wake_test(A.v, A.asleep, B.v, B.asleep, c.n, c.penetration, P_)) {
      sleeper->asleep = false;
      sleeper->sleep_counter = 0;
      ++counters_.wakes;
    }
  }
}

template <class T>
void World<T>::update_sleep() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body<T>& b = bodies_[i];
    if (!b.awake()) continue;
    ++counters_.sleep_updates;
    const bool supported = support_[i] >= 0;
    const Vec3<T> up = supported ? support_normal(i) : Vec3<T>{T{}, Num<T>::from_int(1), T{}};
    if (lockstep::update_sleep(b.v, b.w, b.sleep_counter, supported, b.R, up, length(b.half), P_)) {  // eqs 78-80
      b.asleep = true;
      b.sleep_frame = frame_;
    }
    check_faults(static_cast<int>(i), "sleep");
  }
}

template <class T>
void World<T>::wake(int i) {
  Body<T>& b = bodies_.at(static_cast<std::size_t>(i));
  if (b.is_static || !b.asleep) return;
  b.asleep = false;
  b.sleep_counter = 0;
  ++counters_.wakes;
}

template <class T>
void World<T>::set_velocity(int i, const Vec3<T>& v, const Vec3<T>& w) {
  Body<T>& b = bodies_.at(static_cast<std::size_t>(i));
  if (b.is_static) return;
  wake(i);
  b.v = v;
  b.w = w;
  b.sleep_counter = 0;
}

}  // namespace lockstep
