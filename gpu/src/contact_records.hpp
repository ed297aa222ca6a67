// The GPU engine's body-pair tests as World<T> makes them (body a the lower
// index) and the per-contact records the kernels keep: the solver state of a
// contact (ContactRecord) and the oriented-box model's pair manifold
// (PairManifold).
#pragma once
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "lockstep/physics/box_box.hpp"
#include "lockstep/fixed/q16_num.hpp"
#include "scene_consts.hpp"

namespace lockstep::gpu {

// The body-body contact between self and j as World<T> computes it: body 1
// (a) is the lower index.
template <class T>
LS_HD inline PairContact<T> canonical_pair(const SceneConsts<T>& sc, int self, const Vec3<T>& p,
                                               const Vec3<T>& a, int j, const Vec3<T>& pj,
                                               const Vec3<T>& aj) {
  // World<T>'s narrowphase: the two growths together (in Q16.16 not the
  // contact tolerance itself, whose half rounds: 655 raw halves to 328).
  const T tol = sc.half_tol + sc.half_tol;
  return self < j ? pair_contact(p, a, pj, aj, sc.half_tol, tol) : pair_contact(pj, aj, p, a, sc.half_tol, tol);
}

// Per-contact solver state in two F4s: {j_n, j_t} (accumulated, rewritten by
// each iteration) and {v_n0, e, mu, k_n} (fixed when the solve starts), side
// by side in one 32-byte sector.
template <class T>
struct alignas(32) ContactRecord {
  T4<T> a, b;
};

// Whether a contact bounces: its e_eff (eq 76, the y of its record's b) is
// above 0; its rebound separates it, and the position correction (eqs 89,
// 110, 111) leaves it alone.
template <class T>
LS_HD inline bool bounces(const T4<T>& state_b) { return T{} < state_b.y; }

template <class T>
LS_HD inline ContactState<T> load_state(const T4<T>& a, const T4<T>& b) {
  ContactState<T> c;
  c.j_n = a.x;
  c.j_t = {a.y, a.z, a.w};
  c.v_n0 = b.x;
  c.e = b.y;
  c.mu = b.z;
  c.k_n = b.w;
  return c;
}
template <class T>
LS_HD inline void store_state(const ContactState<T>& c, T4<T>& a, T4<T>& b) {
  a = {c.j_n, c.j_t.x, c.j_t.y, c.j_t.z};
  b = {c.v_n0, c.e, c.mu, c.k_n};
}

// ---------------------------------------------------------------------------
// The oriented-box pair model (docs/SPEC.md 2.4). Each neighbour-list entry
// of a pair holds the pair's manifold (eqs 100-106) as World<T>'s narrowphase
// computes it, body a the lower index (n from the higher towards the lower),
// and its points' solver state; each body keeps its own copy (equal for two
// active bodies: both compute it with the same arguments, and the coloured
// solver writes both).
template <class T>
struct alignas(32) PairManifold {  // 256 bytes (static_assert below)
  using F4 = T4<T>;
  F4 n;                            // xyz: the normal (from the higher index towards the lower)
  F4 pt[kBoxManifoldPoints];       // xyz: the point (m), w: its penetration (m; negative: a speculative gap)
  int feature[kBoxManifoldPoints]; // eq 96's key
  int count = 0;                   // points (0: the grown AABBs overlap but the boxes are apart)
  int deepest = 0;                 // the point that carries the pair's correction (first on ties)
  T depth{};                       // eq 110: the mean depth of the points
  int unused = 0;
  ContactRecord<T> st[kBoxManifoldPoints];
};

static_assert(sizeof(PairManifold<float>) == 256 && sizeof(PairManifold<Q16>) == 256, "the pair record: eq 113's records live apart (SolverData::conv_pair)");

// eq 97 and 107: the AABB growth of a body at the broadphase, half the
// contact tolerance plus, for an awake body, its speculative reach.
template <class T>
LS_HD inline T body_growth(const SceneConsts<T>& sc, const Vec3<T>& v, const Vec3<T>& w, const Vec3<T>& h) {
  return sc.half_tol + speculative_reach(v, w, h, sc.P.dt);  // eq 107
}

// World<T>'s pair test of the oriented-box model: the broadphase's grown
// boxes (eqs 82-83, 97, 107) and the narrowphase's early-out (eqs 38-39 on
// the grown boxes); body a is the lower index.
template <class T>
LS_HD inline bool grown_overlap(const Vec3<T>& pa, const Vec3<T>& aa, const T& ga, const Vec3<T>& pb,
                                const Vec3<T>& ab, const T& gb) {
  for (int ax = 0; ax < 3; ++ax)
    if (pa[ax] + (aa[ax] + ga) < pb[ax] - (ab[ax] + gb) || pb[ax] + (ab[ax] + gb) < pa[ax] - (aa[ax] + ga)) return false;
  return aabb_overlap(pa, aa + Vec3<T>{ga, ga, ga}, pb, ab + Vec3<T>{gb, gb, gb}).hit;
}

// eqs 100-107: the manifold of bodies a < b (growths ga, gb), points up to
// the contact tolerance plus both reaches apart.
template <class T>
LS_HD inline BoxManifold<T> pair_manifold(const SceneConsts<T>& sc, const Vec3<T>& pa, const Mat3<T>& Ra,
                                          const Vec3<T>& ha, const T& ga, const Vec3<T>& pb,
                                          const Mat3<T>& Rb, const Vec3<T>& hb, const T& gb) {
  const T pair_tol = (ga - sc.half_tol) + (gb - sc.half_tol) + sc.P.contact_tolerance;
  return box_box_manifold(pa, Ra, ha, pb, Rb, hb, pair_tol);
}
// The manifold of bodies i and j, the lower index as body a (i_is_a: i < j):
// the sides are picked before the one call (two calls, one a side, put two
// inlined copies of eqs 100-107 into a kernel).
template <class T>
LS_HD inline BoxManifold<T> pair_manifold(const SceneConsts<T>& sc, bool i_is_a, const Vec3<T>& pi, const Mat3<T>& Ri,
                                          const Vec3<T>& hi, const T& gi, const Vec3<T>& pj, const Mat3<T>& Rj,
                                          const Vec3<T>& hj, const T& gj) {
  return pair_manifold(sc, i_is_a ? pi : pj, i_is_a ? Ri : Rj, i_is_a ? hi : hj, i_is_a ? gi : gj, i_is_a ? pj : pi,
                       i_is_a ? Rj : Ri, i_is_a ? hj : hi, i_is_a ? gj : gi);
}

}  // namespace lockstep::gpu
