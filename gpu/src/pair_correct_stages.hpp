// Stages 7 and 8 of docs/SPEC.md 7.2 on the GPU, the oriented-box model:
// the body pairs' corrections (eq 110) and their points turned out (eq 111)
// in World<T>'s bottom-up order as sweeps to its fixed point
// (oriented_stages.hpp), then the integration (IntegrateK).
#pragma once
#include "contact_records.hpp"
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "scene_consts.hpp"

namespace lockstep::gpu {

// Stage 7's order of the body pairs (eqs 110, 111): ascending (lower side's
// y before the stage, lower index, higher index). Calls visit(t, j) for each
// entry t (other body j) of active body i's list whose boxes touch (count >
// 0), in that order; `yi`: i's y before the stage.
template <class T, class Visit>
LS_HD void walk_pairs_in_order(int i, T yi, int beg, int end, const BodyArrays<T>& b, const NeighbourLists& lists,
                               const PairManifold<T>* man, Visit&& visit) {
  bool started = false;
  T last_y = T{};
  int last_lo = 0, last_hi = 0;
  auto before = [](T y1, int lo1, int hi1, T y2, int lo2, int hi2) {  // (height, index), then the other index
    return settles_before(y1, lo1, y2, lo2) || (y1 == y2 && lo1 == lo2 && hi1 < hi2);
  };
  for (;;) {
    int best = -1;
    T by = T{};
    int blo = 0, bhi = 0;
    for (int t = beg; t < end; ++t) {  // the next pair in the order
      if (ro(&man[t].count) == 0) continue;
      const int j = ro(lists.nbr + t);
      const T yj = ro(b.pos + j).y;
      const T y = i < j ? Num<T>::min(yi, yj) : Num<T>::min(yj, yi);
      const int lo = i < j ? i : j, hi = i < j ? j : i;
      if (started && !before(last_y, last_lo, last_hi, y, lo, hi)) continue;
      if (best < 0 || before(y, lo, hi, by, blo, bhi)) { best = t; by = y; blo = lo; bhi = hi; }
    }
    if (best < 0) return;
    started = true;
    last_y = by;
    last_lo = blo;
    last_hi = bhi;
    visit(best, ro(lists.nbr + best));
  }
}

// ---------------------------------------------------------------------------
// Stage 7, eq 110: the corrections of the body pairs after the world's
// (CorrectIntegrateK), in walk_pairs_in_order's order, each by the mean
// depth of its points less what the stage has moved its sides apart
// (manifold_correction). One sweep: each active body walks its pairs in that
// order from its position after the world's corrections, taking the other
// side's position before the pair from the previous sweep (its entry of the
// pair in `before_in`), and records its own position before each pair in
// `before_out`.
template <class T>
struct PairCorrectK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const PairManifold<T>* man;
  const int* slot_of;
  const F4* p_world;    // per slot
  const F4* before_in;  // per entry
  F4* before_out;
  F4* p_out;            // per slot: the position after every pair
  int* changed;         // entries whose result differs from `before_in`
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i);
    const Vec3<T> p0 = xyz(pi4);
    Vec3<T> p = xyz(p_world[k]);
    int differ = 0;
    walk_pairs_in_order(i, p0.y, lists.begin(k), lists.end(k), b, lists, man, [&](int t, int j) {
      const F4 mine = f4(p, T{});
      before_out[t] = mine;
      if (!same_bits(mine, ro(before_in + t))) ++differ;
      const PairManifold<T>& rec = man[t];
      if (bounces(ro(&rec.st[ro(&rec.deepest)].b))) return;  // bouncing (eq 76): its rebound separates it
      const F4 pj4 = ro(b.pos + j);
      const bool j_awake = is_awake(ro(b.flags + j));
      const bool lower = i < j;
      const T inv_j = j_awake ? inv_mass_of(pj4) : T{};
      const T inv_a = lower ? inv_mass_of(pi4) : inv_j, inv_b = lower ? inv_j : inv_mass_of(pi4);
      if (inv_a == T{} && inv_b == T{}) return;
      const Vec3<T> pj0 = xyz(pj4);
      Vec3<T> q = pj0;  // j's position before this pair
      if (j_awake) {
        const int m = lists.find(ro(slot_of + j), i);
        if (m >= 0) q = xyz(ro(before_in + m));
      }
      Vec3<T> pa = lower ? p : q, pb = lower ? q : p;
      const Vec3<T> n = xyz(ro(&rec.n));
      manifold_correction(pa, lower ? p0 : pj0, pb, lower ? pj0 : p0, n, ro(&rec.depth), inv_a, inv_b,
                          is_support_pair(n, sc.P.support_normal_min), sc.P.slop, sc.P.baumgarte);  // eq 110
      p = lower ? pa : pb;
    });
    note_faults<T>(sc.faults, i, kFqCorrection);
    p_out[k] = f4(p, inv_mass_of(pi4));
    if (changed != nullptr) add_to(changed, differ);
  }
};

// ---------------------------------------------------------------------------
// Stage 7, eq 111, after every eq 110 correction: the pairs again in the
// same order, each point of a pair's manifold (in point order; bouncing ones,
// e_eff > 0, skipped) pushed out of its residual depth by moving and turning
// the two sides (correct_manifold_point: BodyView v = the displacement this
// stage, w = the turn so far). A support pair moves only its upper side when
// that side can move; a side that is not awake never moves. One sweep, as
// PairCorrectK's: each active body walks its pairs from its position after
// eq 110 and no turn, taking the other side's (position, turn) before the
// pair from the previous sweep, and records its own before each pair.
template <class T>
struct PairTurnK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const PairManifold<T>* man;
  const int* slot_of;
  const F4* p_pairs;    // per slot: the position after eq 110
  const F4* before_in;  // per entry: the position before the pair
  const F4* turn_in;    // per entry: the turn before the pair
  F4* before_out;
  F4* turn_out;
  F4* p_out;            // per slot: the position after every pair
  F4* turn_slot;        // per slot: the turn after every pair
  int* changed;         // entries whose result differs from the inputs
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i);
    const Vec3<T> p0 = xyz(pi4);
    const Mat3<T> Ri = rotation_matrix(quat(ro(b.rot + i)));
    const Vec3<T> Ii = xyz(ro(b.inert + i));
    Vec3<T> p = xyz(p_pairs[k]), w{};
    int differ = 0;
    walk_pairs_in_order(i, p0.y, lists.begin(k), lists.end(k), b, lists, man, [&](int t, int j) {
      const F4 mine = f4(p, T{}), mine_w = f4(w, T{});
      before_out[t] = mine;
      turn_out[t] = mine_w;
      if (!same_bits(mine, ro(before_in + t)) || !same_bits(mine_w, ro(turn_in + t))) ++differ;
      const F4 pj4 = ro(b.pos + j);
      const bool j_awake = is_awake(ro(b.flags + j));
      const Vec3<T> pj0 = xyz(pj4);
      Vec3<T> q = pj0, wj{};  // j's position and turn before this pair
      if (j_awake) {
        const int m = lists.find(ro(slot_of + j), i);
        if (m >= 0) { q = xyz(ro(before_in + m)); wj = xyz(ro(turn_in + m)); }
      }
      const BodyView<T> me{p - p0, w, inv_mass_of(pi4), Ri, Ii};
      const BodyView<T> other{q - pj0, wj, j_awake ? inv_mass_of(pj4) : T{}, rotation_matrix(quat(ro(b.rot + j))),
                                  j_awake ? xyz(ro(b.inert + j)) : Vec3<T>{}};
      const bool lower = i < j;
      BodyView<T> A = lower ? me : other, B = lower ? other : me;
      if (A.inv_mass == T{} && B.inv_mass == T{}) return;
      const PairManifold<T>& rec = man[t];
      const Vec3<T> n = xyz(ro(&rec.n));
      hold_lower_side(A, B, n, sc.P.support_normal_min);  // eq 111: only the upper side moves, if it can
      const Vec3<T> pa0 = lower ? p0 : pj0, pb0 = lower ? pj0 : p0;
      const int count = ro(&rec.count);
      for (int c = 0; c < count; ++c) {
        if (bounces(ro(&rec.st[c].b))) continue;  // a bouncing point separates by its rebound (eq 89)
        const F4 pt = ro(&rec.pt[c]);
        correct_manifold_point(A, xyz(pt) - pa0, B, xyz(pt) - pb0, n, pt.w, sc.P.slop, sc.P.baumgarte);  // eq 111
      }
      const BodyView<T>& done = lower ? A : B;
      p = p0 + done.v;
      w = done.w;
    });
    note_faults<T>(sc.faults, i, kFqCorrection);
    p_out[k] = f4(p, inv_mass_of(pi4));
    turn_slot[k] = f4(w, T{});
    if (changed != nullptr) add_to(changed, differ);
  }
};

// Stage 8 after eqs 110-111: eq 111's turn (q = integrate_orientation(q,
// turn, 1/2), as World<T> applies it at the end of stage 7), then eqs 2,
// 7-10 from the corrected position into the per-slot buffers (CommitSleepK
// commits them); counts the pair corrections (once per pair).
template <class T>
struct IntegrateK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const PairManifold<T>* man;  // null: no pairs
  const F4* p_in;           // per slot
  const F4* turn;           // per slot: eq 111's turn (null: no pairs)
  F4* p_out;
  F4* q_out;
  Counter* ctr;
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i);
    Vec3<T> p = xyz(p_in[k]);
    Quat<T> q = quat(ro(b.rot + i));
    if (turn != nullptr) {
      const Vec3<T> tw = xyz(turn[k]);
      if (!(tw == Vec3<T>{})) q = integrate_orientation(q, tw, Num<T>::from_double(0.5));  // eqs 7-10, eq 111's turn
    }
    integrate_pose(p, q, xyz(b.vel[i]), xyz(b.ang[i]), sc.P);  // eqs 2, 7-10
    unsigned corrections = 0;
    if (man != nullptr) {
      for (int t = lists.begin(k); t < lists.end(k); ++t) {
        const PairManifold<T>& rec = man[t];
        if (ro(&rec.count) == 0 || bounces(ro(&rec.st[ro(&rec.deepest)].b))) continue;
        const int j = ro(lists.nbr + t);
        const bool j_awake = is_awake(ro(b.flags + j));
        if ((i < j || !j_awake) && (inv_mass_of(pi4) != T{} || (j_awake && inv_mass_of(ro(b.pos + j)) != T{}))) ++corrections;
      }
    }
    note_faults<T>(sc.faults, i, kFqPosition);
    p_out[k] = f4(p, inv_mass_of(pi4));
    q_out[k] = f4(q);
    add_counter(&ctr[kCCorrections], corrections);
  }
};

}  // namespace lockstep::gpu
