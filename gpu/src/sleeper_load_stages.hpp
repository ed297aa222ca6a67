// The GPU engine's kernels of eq 124 (docs/SPEC.md Part 4: a sleeper under
// a load). World<T> forms the sleepers' loads from the top down in one pass;
// here the (sleeping parent, child) pairs are compacted in ascending child
// index and stably sorted by parent (so each parent's children stay in
// ascending index, the order eq 117 sums them in), each parent finds its
// range, and the parents' loads are swept to a fixed point (the parents
// settle before their children: no cycle). A parent whose load's centre is
// not over the support points it recorded wakes at the end of stage 9.
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "sleep_stages.hpp"

namespace lockstep::gpu {

LS_HD inline bool is_asleep(std::uint8_t f) { return (f & (kFlagStatic | kFlagAsleep)) == kFlagAsleep; }

// Per body j: its sleeping load parent (eq 124's pair key), or n (none).
template <class T>
struct SleeperChildK {
  BodyArrays<T> b;
  const int* load_parent;  // per body (ContactsK): read for the awake ones
  SleepSupportArrays<T> rec;
  int n;
  int* flag;      // per body: 1 when j is a sleeper's load child
  unsigned* key;  // per body: the parent, or n
  int* awake_children;  // how many of them are awake (none: eq 124 has nothing to do)
  LS_HD void operator()(int j) const {
    const std::uint8_t fj = ro(b.flags + j);
    int s = kLoadNone;
    if ((fj & kFlagStatic) == 0) {
      const bool awake = is_awake(fj);
      s = sleeper_load_parent(awake, awake ? ro(load_parent + j) : kLoadNone, awake ? kLoadNone : ro(rec.parent + j));
      // an awake body's load parent settles before it (ContactsK); a sleeper's recorded one must still
      if (s >= 0 && !awake && !settles_before(ro(b.pos + s).y, s, ro(b.pos + j).y, j)) s = kLoadNone;
    }
    const bool child = s >= 0 && is_asleep(ro(b.flags + s));
    flag[j] = child ? 1 : 0;
    if (child && is_awake(fj)) add_to(awake_children, 1);
    key[j] = static_cast<unsigned>(child ? s : n);
  }
};

// The flagged bodies, in ascending index: (key, child) at their scan slot.
struct SleeperPairsK {
  const int* flag;
  const int* scan;
  const unsigned* key_in;
  unsigned* key;
  int* child;
  LS_HD void operator()(int j) const {
    if (ro(flag + j) == 0) return;
    const int t = ro(scan + j);
    key[t] = ro(key_in + j);
    child[t] = j;
  }
};

// After the sort: each parent's range [begin, end) of the pairs; the
// parents in ascending index (`heads`, at the scan of head flags).
struct SleeperRangeK {
  const unsigned* key;
  int m;
  int* begin;  // per body, -1 unless a parent
  int* end;
  int* head;   // per pair: 1 at a parent's first
  LS_HD void operator()(int t) const {
    const unsigned k = ro(key + t);
    const bool first = t == 0 || ro(key + t - 1) != k, last = t == m - 1 || ro(key + t + 1) != k;
    if (first) begin[k] = t;
    if (last) end[k] = t + 1;
    head[t] = first ? 1 : 0;
  }
};
struct SleeperHeadsK {
  const unsigned* key;
  const int* head;
  const int* scan;
  int* heads;
  LS_HD void operator()(int t) const {
    if (ro(head + t) != 0) heads[ro(scan + t)] = static_cast<int>(ro(key + t));
  }
};

// One sweep: out[s] = (offset D, mass M) of sleeper s's load (eq 117's sums,
// children in ascending index): an awake child's load is eq 117's (`awake`),
// a sleeping child's the previous sweep's when it is a parent, else its own
// mass alone.
template <class T>
struct SleeperLoadK {
  using F4 = T4<T>;
  const int* heads;
  BodyArrays<T> b;
  const unsigned* key;
  const int* child;
  const int* begin;
  const int* end;
  const F4* awake;  // eq 117's loads (LoadK's result)
  const F4* in;
  F4* out;
  int* changed;
  FaultSink faults{};
  LS_HD F4 load_of(int c) const {
    if (is_awake(ro(b.flags + c))) return ro(awake + c);
    if (ro(begin + c) >= 0) return ro(in + c);
    return F4{T{}, T{}, T{}, Num<T>::from_int(1) / inv_mass_of(ro(b.pos + c))};
  }
  LS_HD void operator()(int h) const {
    const int s = ro(heads + h);
    clear_faults<T>();
    const F4 ps = ro(b.pos + s);
    const int beg = ro(begin + s), stop = ro(end + s);
    auto each_child = [&](auto&& f) {  // ascending index
      for (int t = beg; t < stop; ++t) {
        const int c = ro(child + t);
        const F4 lc = load_of(c);
        f(lc.w, xyz(ro(b.pos + c)), xyz(lc));
      }
    };
    T mass;
    Vec3<T> offset;
    sum_load(inv_mass_of(ps), xyz(ps), each_child, mass, offset);  // eq 117's sums
    note_faults<T>(faults, s, kFqSleeperLoad);
    const F4 result = f4(offset, mass);
    out[s] = result;
    if (changed != nullptr) {
      const F4 was = ro(in + s);
      add_to(changed, result.x != was.x || result.y != was.y || result.z != was.z || result.w != was.w ? 1 : 0);
    }
  }
};

// After the sweeps: a parent whose load is not over its recorded support
// points wakes at the end of stage 9 (SleeperWakeK).
template <class T>
struct SleeperTestK {
  using F4 = T4<T>;
  const int* heads;
  SleepSupportArrays<T> rec;
  const F4* load;
  int* wake;  // per head
  FaultSink faults{};
  LS_HD void operator()(int h) const {
    const int s = ro(heads + h);
    clear_faults<T>();
    const int count = ro(rec.count + s);
    Vec3<T> r[kMaxSupportPoints];
    for (int a = 0; a < count && a < kMaxSupportPoints; ++a) r[a] = xyz(ro(rec.arms + s * kMaxSupportPoints + a));
    wake[h] = sleeper_load_over_support(r, count, xyz(ro(load + s))) ? 0 : 1;
    note_faults<T>(faults, s, kFqSleeperLoad);
  }
};

// End of stage 9: the sleepers SleeperTestK found wake (as eq 81 wakes a
// body, World<T>::wake_loaded) and join the next frame's awake list.
template <class T>
struct SleeperWakeK {
  const int* heads;
  const int* wake;
  BodyArrays<T> b;
  RestArrays<T> rests;
  int* woken;
  int* n_woken;
  LS_HD void operator()(int h) const {
    if (wake[h] == 0) return;
    const int s = heads[h];
    if ((b.flags[s] & kFlagAsleep) == 0) return;
    b.flags[s] = static_cast<std::uint8_t>(b.flags[s] & ~kFlagAsleep);
    b.sleep_counter[s] = 0;
    rests.count[s] = 0;
    woken[claim_one(n_woken)] = s;
  }
};

}  // namespace lockstep::gpu
