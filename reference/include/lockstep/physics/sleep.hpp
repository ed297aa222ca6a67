// Part 4.7 and Part 5 of docs/SPEC.md: multi-stage sleep and wake.
#pragma once
#include "lockstep/physics/params.hpp"

namespace lockstep {

// eq 78: a sleep candidate is supported, slow, not spinning and flat. A body
// whose half-diagonal `radius` (m) is below sleep_small_radius (0.5 m) is
// "not spinning" when its corners move slower than sleep_angular * 0.5 m
// (|w| radius < sleep_corner_speed): the spin that rounding leaves in a
// 2 cm cube in Q16.16 (0.1-0.2 rad/s, its corners at 3 mm/s) kept it awake.
template <class T>
LS_HD bool sleep_candidate(bool supported, const T& speed, const T& spin, const T& alignment, const T& radius,
                           const Params<T>& P) {
  const bool still = radius < P.sleep_small_radius ? spin * radius < P.sleep_corner_speed : spin < P.sleep_angular;
  return supported && speed < P.sleep_linear && still && alignment > P.sleep_alignment;
}

enum class SleepStage : int { kAwake = 0, kDrowsy = 1, kAsleep = 2 };

// eqs 79-80: the stage reached by a body whose candidate counter is `counter`.
inline LS_HD SleepStage sleep_stage(int counter, int drowsy_frames, int sleep_frames) {
  if (counter >= sleep_frames) return SleepStage::kAsleep;  // eq 80
  if (counter >= drowsy_frames) return SleepStage::kDrowsy;  // eq 79
  return SleepStage::kAwake;
}

// eq 81 (5.1): a contact wakes a sleeping body when the awake body approaches
// faster than wake_speed or penetrates deeper than wake_penetration.
template <class T>
LS_HD bool wakes(const T& v_n, const T& penetration, const Params<T>& P) {
  return -v_n > P.wake_speed || penetration > P.wake_penetration;
}

// eq 108: a sleeping body's records: at most kMaxRests dynamic bodies it rested on.
inline constexpr int kMaxRests = 4;

// eq 108: whether a touching body-pair contact (within slop) is recorded for
// a body falling asleep: its normal towards the body (up = its y) is a
// support normal, or the body leans (eq 115: what holds it is recorded).
template <class T>
LS_HD bool records_rest(const T& penetration, const T& up, bool leans, const Params<T>& P) {
  return penetration > -P.slop && !(up < P.support_normal_min && !leans);
}

// eq 108: where supporter `other` goes in a body's records (n of them so far,
// body_at(r) the r-th one's body): -1 when it is there already, kMaxRests when
// they are full, else n.
template <class BodyAt>
LS_HD int rest_slot(int n, int other, BodyAt&& body_at) {
  bool seen = false;
  for (int r = 0; r < n; ++r) seen = seen || body_at(r) == other;
  if (seen) return -1;
  return n == kMaxRests ? kMaxRests : n;
}

// eq 109: a body rests on the other side of a touching body-pair contact
// (within slop) whose normal towards it (up = its y) is a support normal.
template <class T>
LS_HD bool rests_on_contact(const T& penetration, const T& up, const Params<T>& P) {
  return penetration > -P.slop && up >= P.support_normal_min;
}

}  // namespace lockstep
