// The GPU engine's kernels of eq 117 (docs/SPEC.md Part 4: the load a body
// carries and whether it is over its support). World<T> forms each load from
// the top down in one pass (children before parents); here every active
// body gathers its load children's loads from the previous sweep (its
// neighbour list is in ascending index, the order eq 117 sums them in), and
// the sweeps repeat until one reproduces its input bit for bit: the load
// parents settle before their children, so the chains are acyclic and the
// fixed point, reached after the longest chain plus one sweep, is World<T>'s.
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "scene_consts.hpp"
#include "solver_data.hpp"

namespace lockstep::gpu {

// One sweep: out[i] = (offset D, mass M) of body i's load from its load
// children's previous values in[j] (eq 117; `in` zero before the first).
// `changed` counts the bodies whose result differs from `in`.
template <class T>
struct LoadK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  NeighbourLists lists;
  const int* load_parent;  // per body (ContactsK)
  const F4* in;
  F4* out;
  int* changed;
  FaultSink faults{};
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i);
    const int beg = lists.begin(k), end = lists.end(k);
    auto each_child = [&](auto&& f) {  // its load children, ascending index (the neighbour list's order)
      for (int t = beg; t < end; ++t) {
        const int j = ro(lists.nbr + t);
        if (!is_awake(ro(b.flags + j)) || ro(load_parent + j) != i) continue;
        const F4 lj = ro(in + j);
        f(lj.w, xyz(ro(b.pos + j)), xyz(lj));
      }
    };
    T mass;
    Vec3<T> offset;
    sum_load(inv_mass_of(pi4), xyz(pi4), each_child, mass, offset);  // eq 117
    note_faults<T>(faults, i, kFqLoad);
    const F4 result = f4(offset, mass);
    out[i] = result;
    if (changed != nullptr) {
      const F4 was = ro(in + i);
      add_to(changed, result.x != was.x || result.y != was.y || result.z != was.z || result.w != was.w ? 1 : 0);
    }
  }
};

// After the sweeps: a supported body with load children whose load's centre
// is not over its support points, unless what holds it (eq 112) blocks
// every way that load can tip (load_stands), tips with its load: not over
// its support (no settling; eq 112's chain reads it) and it cannot rest (no
// sleep candidate).
template <class T>
struct LoadOverK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const int* load_parent;
  const int* support_idx;
  const F4* load;      // the sweeps' result
  const F4* arms;      // per slot, kMaxSupportPoints (ContactsK)
  const int* n_arms;   // per slot
  const F4* hold_arms;  // per slot, kMaxHolds (ContactsK): what holds it (eq 112)
  const F4* hold_n;     // per slot, kMaxHolds
  const int* n_holds;   // per slot
  int* over_support;   // per body
  int* can_rest;       // per body
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    if (ro(support_idx + i) == kNoSupport) return;
    clear_faults<T>();
    bool carries = false;
    for (int t = lists.begin(k), end = lists.end(k); t < end && !carries; ++t) {
      const int j = ro(lists.nbr + t);
      carries = is_awake(ro(b.flags + j)) && ro(load_parent + j) == i;
    }
    if (!carries) return;
    Vec3<T> r[kMaxSupportPoints];
    const int count = ro(n_arms + k);
    for (int a = 0; a < count && a < kMaxSupportPoints; ++a) r[a] = xyz(ro(arms + k * kMaxSupportPoints + a));
    Vec3<T> ha[kMaxHolds], hn[kMaxHolds];
    const int holds = ro(n_holds + k);
    for (int a = 0; a < holds && a < kMaxHolds; ++a) {
      ha[a] = xyz(ro(hold_arms + k * kMaxHolds + a));
      hn[a] = xyz(ro(hold_n + k * kMaxHolds + a));
    }
    const bool over = load_stands(r, count, xyz(ro(load + i)), length(xyz(ro(b.ang + i))) < sc.P.sleep_angular, ha, hn, holds);
    note_faults<T>(sc.faults, i, kFqLoad);
    if (over) return;
    over_support[i] = 0;
    can_rest[i] = 0;
  }
};

// eq 117, after LoadOverK: whether something in a body's load tips (it, or
// a load child's load), one sweep from the previous sweep's `in` (zero
// before the first); the fixed point is World<T>'s top-down pass. The last
// call (`can_rest` set, `changed` null) also takes a body whose load
// children's loads tip out of the sleep candidates.
template <class T>
struct LoadTipsK {
  const int* list;
  BodyArrays<T> b;
  NeighbourLists lists;
  const int* load_parent;
  const int* over_support;  // per body (eq 112, LoadOverK)
  const int* support_idx;   // per body: an unsupported body is no one's load child and is left alone
  const int* in;
  int* out;
  int* changed;
  int* can_rest;  // per body; the last call only
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    bool child_tips = false;
    for (int t = lists.begin(k), end = lists.end(k); t < end && !child_tips; ++t) {
      const int j = ro(lists.nbr + t);
      child_tips = is_awake(ro(b.flags + j)) && ro(load_parent + j) == i && ro(in + j) != 0;
    }
    const int tips = load_tips(ro(over_support + i) != 0, child_tips) ? 1 : 0;
    out[i] = tips;
    if (changed != nullptr) add_to(changed, tips != ro(in + i) ? 1 : 0);
    if (can_rest != nullptr && ro(support_idx + i) != kNoSupport && !load_rests(child_tips)) can_rest[i] = 0;
  }
};

}  // namespace lockstep::gpu
