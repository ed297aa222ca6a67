// Stages 8 (commit) and 9 of docs/SPEC.md 7.2 on the GPU: the new pose, the
// derived AABB and the sleep update (eqs 31, 78-80).
#pragma once
#include <cstdint>

#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "scene_consts.hpp"
#include "solver_data.hpp"

namespace lockstep::gpu {

// Error codes of the finite check (World<T>::check_finite's order).
inline constexpr int kErrPosition = 0, kErrVelocity = 1, kErrAngular = 2, kErrOrientation = 3;

// Stage 8 commit and stage 9: new pose, derived AABB (eq 31), sleep update
// (eqs 78-80); keep[k] = 1 for a body still awake. A non-finite awake body
// records 4 i + code in *error (the lowest wins, as World<T> reports the
// lowest index).
template <class T>
struct CommitSleepK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  const F4* p_in;
  const F4* q_in;
  const int* support_idx;
  const F4* support_n;
  int frame;
  int* keep;
  int* error;
  Counter* ctr;
  int* ready = nullptr;  // oriented-box model: per slot, 1 when its counter reached sleep_frames (eq 109 decides)
  const int* over = nullptr;  // oriented-box model: per body, over its support (eq 112)
  const int* leaning = nullptr;  // oriented-box model: per body, it leans (eq 115): its alignment is not asked
  const int* can_rest = nullptr;  // per body: statics lets it rest (eqs 116, 117)
  LS_HD void operator()(int k) const {
    const int i = list[k];
    clear_faults<T>();
    const F4 p4 = p_in[k];
    const Quat<T> q = quat(q_in[k]);
    b.pos[i] = p4;
    b.rot[i] = q_in[k];
    const Mat3<T> R = rotation_matrix(q);
    const Vec3<T> a = rotated_half_extents(R, xyz(b.half[i]));  // eq 31
    b.aabb[i] = f4(a, Num<T>::max(a.x, Num<T>::max(a.y, a.z)));
    note_faults<T>(sc.faults, i, kFqPosition);  // eq 31: World<T>::update_derived in stage 8
    Vec3<T> v = xyz(b.vel[i]), w = xyz(b.ang[i]);
    bool asleep = false;
    if (sc.sleep) {
      int counter = b.sleep_counter[i];
      const bool supported = support_idx[i] != kNoSupport;
      const Vec3<T> up = supported ? xyz(support_n[i]) : Vec3<T>{T{}, Num<T>::from_int(1), T{}};
      const bool is_over = over == nullptr || over[i] != 0;  // eq 112: one not over its support may be tipping
      const bool leaning_i = leaning != nullptr && leaning[i] != 0;  // eq 115
      asleep = update_sleep(v, w, counter, supported, is_over, leaning_i, !sc.oriented, can_rest == nullptr || can_rest[i] != 0, R, up,
                            length(xyz(b.half[i])),
                            sc.P);
      b.sleep_counter[i] = counter;
      if (ready != nullptr) ready[k] = counter >= sc.P.sleep_frames ? 1 : 0;
      b.vel[i] = f4(v, T{});
      b.ang[i] = f4(w, T{});
      if (asleep) {
        b.flags[i] = static_cast<std::uint8_t>(b.flags[i] | kFlagAsleep);
        b.sleep_frame[i] = frame;
      }
    }
    note_faults<T>(sc.faults, i, kFqSleep);
    keep[k] = asleep ? 0 : 1;
    if (!asleep) {
      auto fin = [](const Vec3<T>& x) { return Num<T>::finite(x.x) && Num<T>::finite(x.y) && Num<T>::finite(x.z); };
      const int code = !fin(xyz(p4)) ? kErrPosition : !fin(v) ? kErrVelocity : !fin(w) ? kErrAngular
                     : !(Num<T>::finite(q.w) && Num<T>::finite(q.x) && Num<T>::finite(q.y) && Num<T>::finite(q.z)) ? kErrOrientation
                     : -1;
      if (code >= 0) store_min(error, 4 * i + code);
    }
    if (sc.sleep) add_counter(&ctr[kCSleepUpdates], 1u);
  }
};

}  // namespace lockstep::gpu
