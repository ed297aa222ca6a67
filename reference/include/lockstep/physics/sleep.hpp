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

}  // namespace lockstep
