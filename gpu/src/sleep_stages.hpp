// Stages 2a and 9 of docs/SPEC.md 7.2 on the GPU, the oriented-box model
// (as reference/src/sleep.hpp): the support wake (eq 108) and the sleep on a
// resting support (eq 109) as sweeps to World<T>'s fixed point
// (oriented_stages.hpp), and eq 108's and eq 124's records.
#pragma once
#include <cstdint>

#include "contact_records.hpp"
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "scene_consts.hpp"

namespace lockstep::gpu {

// Eq 108's record of a sleeping body (World<T>::record_supports): the
// dynamic bodies it rested on when it fell asleep (at most 4, in contact
// order), each support point in that body's frame and where it was.
template <class T>
struct RestArrays {
  using F4 = T4<T>;
  int* count = nullptr;  // per body
  int* body = nullptr;   // 4 per body
  F4* local = nullptr;   // 4 per body
  F4* rest = nullptr;    // 4 per body
  F4* last = nullptr;    // 4 per body: where the point was at the frame's start (eq 108's speed)
};

// eq 124's records, per body: written when it falls asleep (SleepApplyK).
template <class T>
struct SleepSupportArrays {
  using F4 = T4<T>;
  int* parent = nullptr;  // its load parent then (eq 117, kLoadNone: none)
  int* count = nullptr;   // its support points then (kMaxSupportPoints + 1: many)
  F4* arms = nullptr;     // kMaxSupportPoints per body: their lever arms' horizontal parts
};

// Stage 2a (eq 108), one sweep over every body: a sleeping body wakes when a
// body it rested on is awake (awake at the frame's start, or woken by this
// wake at a lower index: the previous sweep's `in`) and has carried its
// support point away by more than wake_support_distance, or by more than
// sleep_linear dt since the last frame's start (`rests.last`, which
// RestLastK then moves on).
template <class T>
struct SupportWakeK {
  BodyArrays<T> b;
  SceneConsts<T> sc;
  RestArrays<T> rests;
  const int* in;  // per body: woken by the previous sweep
  int* out;
  int* changed;   // bodies whose result differs from `in`
  LS_HD void operator()(int i) const {
    clear_faults<T>();
    int woke = 0;
    const int n = (ro(b.flags + i) & kFlagAsleep) != 0 ? ro(rests.count + i) : 0;
    for (int r = 0; r < n && woke == 0; ++r) {
      const int s = ro(rests.body + kMaxRests * i + r);
      const bool awake = is_awake(ro(b.flags + s)) || (s < i && ro(in + s) != 0);
      if (!awake) continue;
      const Mat3<T> R = rotation_matrix(quat(ro(b.rot + s)));
      const Vec3<T> now = support_point(xyz(ro(b.pos + s)), R, xyz(ro(rests.local + kMaxRests * i + r)));
      if (support_carried_away(now, xyz(ro(rests.rest + kMaxRests * i + r)), xyz(ro(rests.last + kMaxRests * i + r)),
                               sc.P))  // eq 108
        woke = 1;
    }
    note_faults<T>(sc.faults, i, kFqSupportWake);
    out[i] = woke;
    if (changed != nullptr) add_to(changed, woke != ro(in + i) ? 1 : 0);
  }
};

// Eq 108's speed, after the support wake: every sleeper's records take
// where their points are now (World<T>::wake_unsupported's `last`).
template <class T>
struct RestLastK {
  BodyArrays<T> b;
  RestArrays<T> rests;
  FaultSink faults{};
  LS_HD void operator()(int i) const {
    if ((ro(b.flags + i) & kFlagAsleep) == 0) return;
    clear_faults<T>();
    const int n = ro(rests.count + i);
    for (int r = 0; r < n; ++r) {
      const int s = ro(rests.body + kMaxRests * i + r);
      const Mat3<T> R = rotation_matrix(quat(ro(b.rot + s)));
      rests.last[kMaxRests * i + r] =
          f4(support_point(xyz(ro(b.pos + s)), R, xyz(ro(rests.local + kMaxRests * i + r))), T{});
    }
    note_faults<T>(faults, i, kFqSupportWake);
  }
};

// The bodies the support wake woke: awake again (counter 0), listed (the
// host sorts the list and appends it to the awake list).
template <class T>
struct SupportWakeApplyK {
  BodyArrays<T> b;
  const int* woke;
  int* woken;
  int* n_woken;
  LS_HD void operator()(int i) const {
    if (woke[i] == 0) return;
    b.flags[i] = static_cast<std::uint8_t>(b.flags[i] & ~kFlagAsleep);
    b.sleep_counter[i] = 0;
    woken[claim_one(n_woken)] = i;
  }
};

// ---------------------------------------------------------------------------
// Stage 9, eq 109, one sweep over the active bodies: a ready body (its
// counter reached sleep_frames, CommitSleepK) falls asleep when every dynamic
// body it rests on (the other side of a touching pair point whose normal
// towards it is within acos(support_normal_min) of up) is not awake, or is a
// ready body before it in ascending (y, index) order that falls asleep (the
// previous sweep's `in`).
template <class T>
struct SleepSweepK {
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const PairManifold<T>* man;  // null: no pairs
  const int* slot_of;
  const int* ready;  // per slot
  const int* in;     // per slot
  int* out;
  int* changed;
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    int sleeps = ro(ready + k);
    const T yi = ro(b.pos + i).y;
    if (sleeps != 0 && man != nullptr) {
      for (int t = lists.begin(k); t < lists.end(k) && sleeps != 0; ++t) {
        const PairManifold<T>& rec = man[t];
        const int count = ro(&rec.count);
        const int j = ro(lists.nbr + t);
        const Vec3<T> n = xyz(ro(&rec.n));
        const T up = i < j ? n.y : -n.y;
        if (!is_awake(ro(b.flags + j))) continue;
        bool rests = false;  // eq 109: on j
        for (int c = 0; c < count; ++c) rests = rests || rests_on_contact(ro(&rec.pt[c].w), up, sc.P);
        if (!rests) continue;
        const bool earlier = settles_before(ro(b.pos + j).y, j, yi, i);
        if (!(earlier && ro(in + ro(slot_of + j)) != 0)) sleeps = 0;
      }
    }
    note_faults<T>(sc.faults, i, kFqSleep);
    out[k] = sleeps;
    if (changed != nullptr) add_to(changed, sleeps != ro(in + k) ? 1 : 0);
  }
};

// The bodies eq 109 put to sleep: eq 80 (velocities 0), asleep since this
// frame, left out of the next awake list, growth back to half_tol, and what
// they rest on recorded for eq 108 (World<T>::record_supports).
template <class T>
struct SleepApplyK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const PairManifold<T>* man;  // null: no pairs
  const int* sleeps;        // per slot
  const int* leaning;       // per body (eq 115): what it touches holds it, and is recorded
  RestArrays<T> rests;
  T* grow;
  int frame;
  int* keep;
  // eq 124: the load parents (per body) and support points (per slot,
  // ContactsK) to record; records.parent null: none (the AABB model).
  const int* load_parent = nullptr;
  const F4* arms = nullptr;
  const int* n_arms = nullptr;
  SleepSupportArrays<T> records{};
  LS_HD void operator()(int k) const {
    if (sleeps[k] == 0) return;
    const int i = list[k];
    clear_faults<T>();
    if (records.parent != nullptr) {  // eq 124
      records.parent[i] = load_parent[i];
      const int count = n_arms[k];
      records.count[i] = count;
      for (int a = 0; a < count && a < kMaxSupportPoints; ++a)
        records.arms[i * kMaxSupportPoints + a] = f4(horizontal(xyz(arms[k * kMaxSupportPoints + a])), T{});
    }
    b.vel[i] = F4{};
    b.ang[i] = F4{};
    b.flags[i] = static_cast<std::uint8_t>(b.flags[i] | kFlagAsleep);
    b.sleep_frame[i] = frame;
    keep[k] = 0;
    grow[i] = sc.half_tol;
    int n = 0;
    bool full = false;
    const bool leans_i = ro(leaning + i) != 0;
    if (man != nullptr) {
      for (int t = lists.begin(k); t < lists.end(k) && !full; ++t) {
        const PairManifold<T>& rec = man[t];
        const int j = ro(lists.nbr + t);
        const Vec3<T> nn = xyz(rec.n);
        const T up = i < j ? nn.y : -nn.y;
        for (int c = 0; c < rec.count; ++c) {
          if (!records_rest(rec.pt[c].w, up, leans_i, sc.P)) continue;
          if (inv_mass_of(ro(b.pos + j)) == T{}) continue;  // a static body (inverse mass 0; its flags may be written now)
          const int slot = rest_slot(n, j, [&](int r) { return rests.body[kMaxRests * i + r]; });
          if (slot < 0) continue;
          if (slot == kMaxRests) { full = true; break; }
          const F4 pj4 = ro(b.pos + j);
          const Mat3<T> R = rotation_matrix(quat(b.rot[j]));
          const Vec3<T> pj = xyz(pj4);
          const Vec3<T> local = support_local(pj, R, xyz(rec.pt[c]));
          rests.body[kMaxRests * i + n] = j;
          rests.local[kMaxRests * i + n] = f4(local, T{});
          rests.rest[kMaxRests * i + n] = rests.last[kMaxRests * i + n] = f4(support_point(pj, R, local), T{});
          ++n;
        }
      }
    }
    rests.count[i] = n;
    note_faults<T>(sc.faults, i, kFqSleep);
  }
};

}  // namespace lockstep::gpu
