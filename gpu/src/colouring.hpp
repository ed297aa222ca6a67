// Gauss-Seidel between awake bodies on the GPU (docs/GPU.md "Contact
// resolution", GpuOptions::pair_solver = kColoured): the contacts between two
// active bodies (the edges of the contact graph) are coloured so that no two
// contacts of one colour share a body; an iteration solves each body's
// contacts with immovable things (SolveK), then the colours one after the
// other, all contacts of a colour in parallel, each updating both bodies'
// velocities in place, as World<T> does one contact at a time.
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "lockstep/physics/solve_order.hpp"

namespace lockstep::gpu {

// A neighbour-list entry's colour in the coloured solver (colouring.hpp):
// kNoEdge when its body is not active (an immovable contact, solved by
// SolveK), kUncoloured until a colouring round colours it, else the colour
// (0, 1, ...).
inline constexpr int kNoEdge = -2, kUncoloured = -1;

// The order of the edges (eqs 125-126, lockstep/physics/solve_order.hpp:
// EdgeKey, edge_key, kBandsPerExtent, shared with World<T>): lowest first, by
// the band of their height, then a hash of the two body indices, then the
// indices. Solving the colours lowest first carries a stack's support
// upwards in one iteration. Bands of H (a whole layer of tilted cubes) put
// the contacts of two layers of a heap in hash order, the upper often first:
// the bowl then slept late (median sleep frame above 232 in 18 of 100 nudged
// starts, World<float> 0); bands of H / 4: 2 of 100, for 8 % more colours on
// pile1000 (docs/GPU.md).

// The colour words are read while other threads of the round write them:
// volatile accesses on the device (strong, so no data race), plain ones in
// the host build, which runs the threads one after the other.
LS_HD inline int load_word(const int* p) {
#if defined(__CUDA_ARCH__)
  return *static_cast<const volatile int*>(p);
#else
  return *p;
#endif
}
LS_HD inline void store_word(int* p, int v) {
#if defined(__CUDA_ARCH__)
  *static_cast<volatile int*>(p) = v;
#else
  *p = v;
#endif
}

// Where the colouring's per-entry state lives (each array one element per
// neighbour-list entry, but the pending list and its count).
template <class T>
struct EdgeArrays {
  const int* slot_of = nullptr;  // this frame's slot of each active body
  const T* inv_cell = nullptr;  // the awake grid's 1 / (2 H), H its largest AABB half extent
  int* mate = nullptr;           // null: no colouring (the Jacobi solver)
  unsigned long long* key = nullptr;
  int* word = nullptr;  // colour, kUncoloured, or kNoEdge
  int* pending = nullptr;
  int* pending_count = nullptr;
};

// Entry t of body i's list, body j (at heights yi, yj): an edge when j is
// awake (every awake body is active) and i is in j's list, whose entry is
// mate[t] (its copy of the contact state); key[t] is the edge's place in the
// order, word[t] kUncoloured (kNoEdge, and no key, for an entry that is no
// edge), and the owner's entry (the lower body's) goes to the pending list of
// round 0.
// Needs every list sorted (GatherK) and slot_of written.
template <class T>
LS_HD inline void init_edge(const EdgeArrays<T>& e, const NeighbourLists& lists, int i, int t, int j, bool j_awake,
                            T yi, T yj) {
  // -1 when j's list lacks i (not mutual: no edge; kept safe, the pair test is symmetric)
  const int m = j_awake ? lists.find(ro(e.slot_of + j), i) : -1;
  e.mate[t] = m;
  e.word[t] = m < 0 ? kNoEdge : kUncoloured;
  if (m < 0) return;  // a non-edge's key is never read
  const T inv_band = ro(e.inv_cell) * Num<T>::from_int(2 * kBandsPerExtent);  // bands of H / kBandsPerExtent (cell 2H)
  e.key[t] = i < j ? edge_key(i, j, yi, yj, inv_band) : edge_key(j, i, yj, yi, inv_band);
  if (i < j) e.pending[claim_one(e.pending_count)] = t;
}

// Round r of a parallel colouring in the edges' order (Jones-Plassmann): a
// pending (uncoloured) edge that goes before every edge it shares a body with
// that was uncoloured at the start of the round takes colour r; the others
// go to the next round's pending list. Two edges that share a body are never
// both first, so edges of one colour share no body; of two edges that share
// a body the one first in the order has the lower colour (a stack gets one
// colour per contact, bottom-up); and the colours do not depend on the order
// of the threads: a word read as kUncoloured or r means "uncoloured at the
// start of the round" either way. A coloured edge is written on both copies
// and appended to colour r's part of `edges`, which starts where round r-1's
// ended; the positions within it (integer atomics) depend on the threads'
// order, which decides only which thread solves an edge. The threads step
// through the pending list `threads` apart (its length is on the device).
// Counters rotate over three rounds: round r reads pending count r % 3 and
// the edges placed in round r - 1, writes count and placed (r + 1) % 3 and
// r % 3, and its thread 0 clears those of round r + 1 and r + 2 that no
// thread of round r touches, and records where round r - 1's edges ended.
struct ColourRoundK {
  const int* list;
  NeighbourLists lists;
  const int* slot_of;
  const int* mate;
  const unsigned long long* key;
  int* word;
  int round;
  int* pending_count;  // three, rotating
  int* placed;         // three, rotating: edges coloured per round
  int* round_end;      // per round: where its edges end in `edges`
  const int* pending;  // this round's
  int* next;           // the next round's
  int* edges;
  int threads;
  LS_HD void operator()(int k) const {
    const int n = pending_count[round % 3];
    const int start = round == 0 ? 0 : (round >= 2 ? round_end[round - 2] : 0) + placed[(round + 2) % 3];
    if (k == 0) {
      if (round > 0) round_end[round - 1] = start;
      pending_count[(round + 2) % 3] = 0;
      placed[(round + 1) % 3] = 0;
    }
    for (int e = k; e < n; e += threads) {
      const int t = pending[e];
      const int slot = t / lists.stride;
      const int i = ro(list + slot), j = ro(lists.nbr + t), m = ro(mate + t);
      const EdgeKey self{ro(key + t), i, j};
      bool first = true;
      auto visit = [&](int s, int body, int skip) {
        for (int u = lists.begin(s); u < lists.end(s) && first; ++u) {
          if (u == skip) continue;
          const int w = load_word(word + u);
          if (w != kUncoloured && w != round) continue;  // no edge, or coloured before this round
          const int o = ro(lists.nbr + u);
          if (EdgeKey{ro(key + u), body < o ? body : o, body < o ? o : body}.before(self)) first = false;
        }
      };
      visit(slot, i, t);
      visit(ro(slot_of + j), j, m);
      if (first) {
        store_word(word + t, round);
        store_word(word + m, round);
        edges[start + claim_one(placed + round % 3)] = t;
      } else {
        next[claim_one(pending_count + (round + 1) % 3)] = t;
      }
    }
  }
};

}  // namespace lockstep::gpu
