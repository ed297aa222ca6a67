// Gauss-Seidel between awake bodies on the GPU (docs/GPU.md "Contact
// resolution", GpuOptions::pair_solver = kColoured): the contacts between two
// active bodies (the edges of the contact graph) are coloured so that no two
// contacts of one colour share a body; an iteration solves each body's
// contacts with immovable things (SolveK), then the colours one after the
// other, all contacts of a colour in parallel, each updating both bodies'
// velocities in place, as World<T> does one contact at a time.
#pragma once
#include "stages.hpp"

namespace lockstep::gpu {

// The order of the edges: lowest first, by the band of their height (the
// bodies' mean y in bands of H, the awake grid's largest AABB half extent:
// a stack's contacts are one band or more apart), then by a hash of the two
// body indices, then by the indices, so that every edge has its own place.
// Solving the colours lowest first carries a stack's support upwards in one
// iteration, as World<T>'s order does for a stack built bottom-up.
// Unsigned arithmetic only (wraps by definition); the band is clamped.
struct EdgeKey {
  unsigned long long key;  // (band + 2^31) << 32 | hash
  int lo, hi;              // the bodies, lo < hi
  LS_HD bool before(const EdgeKey& o) const {
    if (key != o.key) return key < o.key;
    return lo != o.lo ? lo < o.lo : hi < o.hi;
  }
};
LS_HD inline unsigned long long edge_key(int lo, int hi, float y_lo, float y_hi, float inv_band) {
  unsigned x = static_cast<unsigned>(lo) * 0x9E3779B1u ^ static_cast<unsigned>(hi) * 0x85EBCA77u;
  x ^= x >> 15;
  x *= 0x2C1B3C6Du;
  x ^= x >> 12;
  const float limit = Num<float>::from_double(1073741824.0);  // 2^30 bands
  float y = (y_lo + y_hi) * Num<float>::from_double(0.5) * inv_band;
  y = y == y ? Num<float>::max(-limit, Num<float>::min(y, limit)) : 0.0f;  // NaN: caught at the frame's end
  const unsigned biased = static_cast<unsigned>(Num<float>::floor_int(y)) + 0x80000000u;
  return (static_cast<unsigned long long>(biased) << 32) | x;
}

// The entries of body i's list that are edges: j awake (every awake body is
// active) and i in j's list. mate[t] is the entry of the same contact in j's
// list (its copy of the contact state), key[t] the edge's place in the order;
// both colour buffers start kUncoloured there and kNoEdge elsewhere. Runs
// after ContactsK, which sorted every list and wrote slot_of.
struct PairEdgesK {
  const int* list;
  BodyArrays b;
  NeighbourLists lists;
  const int* slot_of;
  const GridParams* grid;  // the awake grid: its cells are 2 H wide
  int* mate;
  unsigned long long* key;
  int* colour0;
  int* colour1;
  LS_HD void operator()(int k) const {
    const int i = list[k];
    const float inv_band = grid->inv_cell * Num<float>::from_int(2);
    for (int t = lists.begin(k); t < lists.end(k); ++t) {
      const int j = lists.nbr[t];
      int m = -1;
      if (is_awake(b.flags[j])) {
        const int s = slot_of[j];
        int lo = lists.begin(s), hi = lists.end(s);
        while (lo < hi) {  // binary search in j's ascending list
          const int mid = lo + (hi - lo) / 2;
          if (lists.nbr[mid] < i) lo = mid + 1;
          else hi = mid;
        }
        if (lo < lists.end(s) && lists.nbr[lo] == i) m = lo;  // else not mutual: no edge (kept safe)
      }
      mate[t] = m;
      key[t] = i < j ? edge_key(i, j, b.pos[i].y, b.pos[j].y, inv_band) : edge_key(j, i, b.pos[j].y, b.pos[i].y, inv_band);
      colour0[t] = colour1[t] = m < 0 ? kNoEdge : kUncoloured;
    }
  }
};

// Round r of a parallel colouring in the edges' order (Jones-Plassmann): an
// uncoloured edge that goes before every uncoloured edge it shares a body
// with takes colour r. Edges of one colour share no body, and the colours
// follow the order: a stack gets one colour per contact, bottom-up. The
// round reads `in` and writes `out` (every edge's word, by the thread of its
// lower body, its owner, into both copies), so no thread reads what another
// writes: the result does not depend on the order of the threads. With
// `count`, *left counts the edges still uncoloured and *colours is the
// number of colours used (integer atomics, order-free).
struct ColourRoundK {
  const int* list;
  NeighbourLists lists;
  const int* slot_of;
  const int* mate;
  const unsigned long long* key;
  const int* in;
  int* out;
  int round;
  bool count;
  int* left;
  int* colours;
  LS_HD void operator()(int k) const {
    const int i = list[k];
    int waiting = 0, most = 0;
    for (int t = lists.begin(k); t < lists.end(k); ++t) {
      const int j = ro(lists.nbr + t);
      int word = ro(in + t);
      if (word == kNoEdge || j < i) continue;  // not an edge, or owned by j
      const int m = ro(mate + t);
      if (word == kUncoloured) {
        const EdgeKey self{ro(key + t), i, j};
        bool first = true;
        auto visit = [&](int slot, int body, int skip) {
          for (int u = lists.begin(slot); u < lists.end(slot) && first; ++u) {
            if (u == skip || ro(in + u) != kUncoloured) continue;
            const int o = ro(lists.nbr + u);
            const EdgeKey other{ro(key + u), body < o ? body : o, body < o ? o : body};
            if (other.before(self)) first = false;
          }
        };
        visit(k, i, t);
        visit(ro(slot_of + j), j, m);
        if (first) word = round;
        else ++waiting;
      }
      if (word + 1 > most) most = word + 1;
      out[t] = word;
      out[m] = word;
    }
    if (count) {
      add_to(left, waiting);
      max_to(colours, most);
    }
  }
};

// One colour of one iteration: every edge of colour c, by its owner's thread
// (body 1 = the lower index, as World<T>), solved on both bodies' current
// velocities, which it updates in place (no other edge of the colour touches
// either body); both copies of the contact state are rewritten.
struct SolvePairsK {
  SolverData d;
  const int* mate;
  const int* colour;
  int c;
  F4* vel;
  F4* ang;
  Counter* ctr;
  LS_HD void operator()(int k) const {
    const BodyArrays& b = d.b;
    const SceneConsts& sc = d.sc;
    const int i = ro(d.list + k);
    SolveCounts counts;
    for (int t = d.lists.begin(k); t < d.lists.end(k); ++t) {
      const int j = ro(d.lists.nbr + t);
      if (j < i || ro(colour + t) != c) continue;
      const F4 pi4 = ro(b.pos + i), pj4 = ro(b.pos + j);
      const Vec3<float> p = xyz(pi4), pj = xyz(pj4);
      const PairContact<float> pc = pair_contact(p, xyz(ro(b.aabb + i)), pj, xyz(ro(b.aabb + j)), sc.half_tol,
                                                 sc.P.contact_tolerance);
      BodyView<float> A = dynamic_view(xyz(vel[i]), xyz(ang[i]), pi4.w, rotation_matrix(quat(ro(b.rot + i))),
                                       xyz(ro(b.inert + i)));
      BodyView<float> B = dynamic_view(xyz(vel[j]), xyz(ang[j]), pj4.w, rotation_matrix(quat(ro(b.rot + j))),
                                       xyz(ro(b.inert + j)));
      ContactState<float> cs = load_state(d.pair[t].a, d.pair[t].b);
      solve_contact(A, pc.point - p, B, pc.point - pj, pc.n, pc.penetration, cs, sc.friction, sc.gravity, 1.0f,
                    sc.P, counts);
      vel[i] = f4(A.v, 0.0f);
      ang[i] = f4(A.w, 0.0f);
      vel[j] = f4(B.v, 0.0f);
      ang[j] = f4(B.w, 0.0f);
      const F4 state{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z};
      d.pair[t].a = state;
      d.pair[ro(mate + t)].a = state;
    }
    add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
    add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
    add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
  }
};

}  // namespace lockstep::gpu
