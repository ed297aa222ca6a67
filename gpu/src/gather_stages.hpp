// Stages 2-4 of docs/SPEC.md 7.2 on the GPU: each active body gathers its
// neighbours from the grids (the broadphase and the narrowphase's pair
// test, eqs 38-39, 82-83, 97, 107) and wakes the sleepers it touches (eq
// 81); the work order of the solver's threads.
#pragma once
#include <cstdint>

#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "contact_records.hpp"
#include "grid.hpp"
#include "scene_consts.hpp"

namespace lockstep::gpu {

// The threads of the solver's iterations in an order of their work (a
// scheduling choice: each slot's result does not depend on the thread that
// computes it). A warp runs the union of its threads' paths, so within
// each segment of 2^11 consecutive slots, slots near the ground (a manifold
// to solve: the lowest corner of the AABB within the contact tolerance) are
// put together, then ordered by the length of their neighbour lists. Whole
// segments keep their place, so that the memory a segment touches stays in
// the cache while its threads run. The gather writes the key of each slot,
// sorted with the slots as values (stable: ascending slots within a class).
struct WorkOrder {
  unsigned* key = nullptr;
  int* slot = nullptr;
};
inline constexpr int kWorkClassBits = 5, kWorkSegmentBits = 11;
LS_HD inline unsigned work_key(int slot, bool manifold, int neighbours) {
  const unsigned m = neighbours < 15 ? static_cast<unsigned>(neighbours) : 15u;
  const unsigned segment = static_cast<unsigned>(slot) >> kWorkSegmentBits;
  return (segment << kWorkClassBits) | (manifold ? 0u : 16u) | m;
}
// The key bits to sort for n slots.
inline int work_key_bits(int n) {
  int bits = kWorkClassBits;
  for (unsigned s = static_cast<unsigned>(n - 1) >> kWorkSegmentBits; s != 0; s >>= 1) ++bits;
  return bits;
}

// Where this frame's contacts of body i are, for next frame's warm start (eq
// 96): its slot, written with the frame number (double-buffered by frame parity).
struct ContactIndex {
  int* slot_of;  // per body
  int* stamp;    // per body: frame at which slot_of was written
};

// Stages 2-4: each active body gathers the bodies whose (grown) AABB overlaps
// its own, up to `stride` of them (the count goes on: the host enlarges the
// blocks and gathers again when one overflows), and wakes (eq 81) sleeping
// ones that it touches fast or deeply. Awake bodies look in the awake grid,
// the frozen grid and the large statics; woken bodies (`woken_pass`) only in
// the awake grid: World<T> pairs only bodies of which one was awake at the
// broadphase. `count_work` is off when gathering again.
template <class T>
struct GatherK {
  const int* list;
  int slot0;  // slot of list[0]
  BodyArrays<T> b;
  SceneConsts<T> sc;
  GridView<T> awake_grid, frozen_grid;
  bool woken_pass, count_work;
  NeighbourLists lists;
  int* max_count;
  int* wake_flag;
  int* woken;
  int* n_woken;
  WorkOrder order;  // keys to write, or none
  ContactIndex index;
  int frame;
  Counter* ctr;
  const T* grow = nullptr;  // oriented-box model: per body, its AABB growth (eqs 97, 107); null: AABB model
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    const int slot = slot0 + k;
    clear_faults<T>();
    index.slot_of[i] = slot;
    index.stamp[i] = frame;
    const Vec3<T> p = xyz(ro(b.pos + i)), a = xyz(ro(b.aabb + i));
    int* out = lists.nbr + slot * lists.stride;
    unsigned tested = 0, contacts = 0;
    int m = 0;
    const bool oriented = grow != nullptr;
    const T gi = oriented ? ro(grow + i) : T{};
    const Vec3<T> reach = oriented ? a + Vec3<T>{gi, gi, gi} : a;  // the candidates of the grown box
    // World<T>'s pair test: the AABBs grown by half the contact tolerance
    // (eqs 38-39, 97), or, oriented-box model, by each body's growth (107).
    auto touches = [&](int j, const Vec3<T>& pj, const Vec3<T>& aj) {
      bool hit;
      if (!oriented) {
        hit = canonical_pair(sc, i, p, a, j, pj, aj).hit;
      } else {
        const T gj = ro(grow + j);
        hit = i < j ? grown_overlap(p, a, gi, pj, aj, gj) : grown_overlap(pj, aj, gj, p, a, gi);
      }
      note_faults<T>(sc.faults, i < j ? i : j, kFqPairContact);
      return hit;
    };
    visit_candidates(awake_grid, i, p, reach, tested, [&](int j, const Vec3<T>& pj, const Vec3<T>& aj) {
      if (!touches(j, pj, aj)) return;
      if (m < lists.stride) out[m] = j;
      ++m;
      if (!woken_pass && i < j && !oriented) ++contacts;
    });
    if (!woken_pass) {
      auto other = [&](int j, const Vec3<T>& pj, const Vec3<T>& aj) {
        if (!touches(j, pj, aj)) return;
        if (m < lists.stride) out[m] = j;
        ++m;
        if (!oriented) ++contacts;
        if (count_work && sc.sleep && (ro(b.flags + j) & kFlagAsleep) != 0) {
          const bool i_is_a = i < j;
          const Vec3<T> vi = xyz(ro(b.vel + i)), vj = xyz(ro(b.vel + j));
          const Vec3<T> va = i_is_a ? vi : vj, vb = i_is_a ? vj : vi;
          bool wakes_j = false;
          if (!oriented) {
            const PairContact<T> c = canonical_pair(sc, i, p, a, j, pj, aj);
            wakes_j = wake_test(va, !i_is_a, vb, i_is_a, c.n, c.penetration, sc.P);
          } else {  // eq 81 on each point of the pair's manifold
            const Mat3<T> Ri = rotation_matrix(quat(ro(b.rot + i))), Rj = rotation_matrix(quat(ro(b.rot + j)));
            const Vec3<T> hi = xyz(ro(b.half + i)), hj = xyz(ro(b.half + j));
            const T gj = ro(grow + j);
            const BoxManifold<T> mf = pair_manifold(sc, i_is_a, p, Ri, hi, gi, pj, Rj, hj, gj);
            for (int q = 0; q < mf.count && !wakes_j; ++q)
              wakes_j = wake_test(va, !i_is_a, vb, i_is_a, mf.n, mf.penetration[q], sc.P);
          }
          note_faults<T>(sc.faults, i < j ? i : j, kFqPairContact);
          if (wakes_j && claim_flag(&wake_flag[j])) woken[fetch_add(n_woken, 1)] = j;
        }
      };
      visit_candidates(frozen_grid, i, p, reach, tested, other);
      for (int t = 0; t < sc.n_large; ++t) {
        const int j = sc.large[t];
        ++tested;
        other(j, xyz(ro(b.pos + j)), xyz(ro(b.aabb + j)));
      }
    }
    const int kept = m < lists.stride ? m : lists.stride;
    lists.count[slot] = kept;
    if (m > lists.stride) store_max(max_count, m);
    for (int s = 1; s < kept; ++s) {  // insertion sort: ascending body index
      const int x = out[s];
      int t = s - 1;
      while (t >= 0 && out[t] > x) { out[t + 1] = out[t]; --t; }
      out[t + 1] = x;
    }
    if (order.key != nullptr) {
      order.key[slot] = work_key(slot, sc.ground_on && p.y - a.y < sc.ground_y + sc.P.contact_tolerance, m);
      order.slot[slot] = slot;
    }
    if (count_work) {
      add_counter(&ctr[kCPairsTested], tested);
      add_counter(&ctr[kCBodyContacts], contacts);
    }
  }
};

// Each active body's slot, when no gather runs (no body-body contacts).
struct SlotIndexK {
  const int* list;
  ContactIndex index;
  int frame;
  LS_HD void operator()(int k) const {
    index.slot_of[list[k]] = k;
    index.stamp[list[k]] = frame;
  }
};

// Woken bodies join the active set after the awake ones (slots n_awake..).
template <class T>
struct WakeApplyK {
  const int* woken;
  BodyArrays<T> b;
  int* wake_flag;
  int* active;
  int n_awake;
  T* grow = nullptr;  // oriented-box model: a body woken here was asleep at the broadphase (growth half_tol)
  T half_tol = T{};
  LS_HD void operator()(int k) const {
    const int i = woken[k];
    b.flags[i] = static_cast<std::uint8_t>(b.flags[i] & ~kFlagAsleep);
    b.sleep_counter[i] = 0;
    if (grow != nullptr) grow[i] = half_tol;
    wake_flag[i] = 0;
    active[n_awake + k] = i;
  }
};

}  // namespace lockstep::gpu
