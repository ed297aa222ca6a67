// Stages 4 and 9 of docs/SPEC.md 7.2: wake (5.1, eq 81) and sleep (4.7, eqs 78-80).
#pragma once
#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/physics/sleep.hpp"
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
    const Vec3<T> v_rel = (A.asleep ? Vec3<T>{} : A.v) - (B.asleep ? Vec3<T>{} : B.v);
    if (wakes(dot(v_rel, c.n), c.penetration, P_)) {
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
    const T speed = length(b.v), spin = length(b.w);
    const Alignment<T> al = alignment_of(b.R, supported ? support_normal(i) : Vec3<T>{T{}, Num<T>::from_int(1), T{}});
    if (sleep_candidate(supported, speed, spin, al.alignment, P_)) ++b.sleep_counter;  // eq 78
    else b.sleep_counter = 0;
    switch (sleep_stage(b.sleep_counter, P_.drowsy_frames, P_.sleep_frames)) {
      case SleepStage::kAsleep:  // eq 80
        b.v = Vec3<T>{};
        b.w = Vec3<T>{};
        b.asleep = true;
        b.sleep_frame = frame_;
        break;
      case SleepStage::kDrowsy:  // eq 79
        b.v = b.v * P_.drowsy_damping;
        b.w = b.w * P_.drowsy_damping;
        break;
      case SleepStage::kAwake: break;
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
