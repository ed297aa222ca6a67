// What the GPU engine's contact kernels share (stages 3, 5, 7): the Jacobi
// mass splitting, the contact-side view of a body, the solver's buffers
// (SolverData), eq 113's visit records and last frame's contacts (eq 96).
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "contact_records.hpp"
#include "scene_consts.hpp"

namespace lockstep::gpu {

// Which of the six axis directions a body-body contact normal points most
// nearly along (its largest component, the first on ties; eqs 41-42's
// normals are +-1 on one axis): 2 axis + (negative).
template <class T>
LS_HD inline int direction_of(const Vec3<T>& n) {
  int axis = 0;
  for (int ax = 1; ax < 3; ++ax)
    if (Num<T>::abs(n[ax]) > Num<T>::abs(n[axis])) axis = ax;
  return 2 * axis + (n[axis] < T{} ? 1 : 0);
}

// Mass splitting of the Jacobi solver: a body's contacts with other active
// bodies are counted per normal direction (one byte each of dir_count); a
// contact's effective mass is scaled by the larger of its two bodies' counts
// in its direction (n towards body i), over the relaxation. Contacts pushing a
// body the same way share it; opposite ones (a body in a stack) do not.
template <class T>
LS_HD inline T jacobi_split(Counter counts_i, Counter counts_j, const Vec3<T>& n_towards_i, const T& relaxation) {
  const int d = direction_of(n_towards_i);
  const unsigned mine = static_cast<unsigned>((counts_i >> (8 * d)) & 255u);
  const unsigned theirs = static_cast<unsigned>((counts_j >> (8 * (d ^ 1))) & 255u);
  return Num<T>::from_int(static_cast<int>(mine > theirs ? mine : theirs)) / relaxation;
}

// Support contact of a body (settling eq 75, sleep eq 78).
inline constexpr int kNoSupport = -1;
inline constexpr int kStaticSupport = -2;  // ground or SDF volume: v_s = 0

// c ? x : y, one float at a time (a select of whole structs can put them in
// local memory).
template <class T>
LS_HD inline T pick(bool c, const T& x, const T& y) { return c ? x : y; }
template <class T>
LS_HD inline Vec3<T> pick(bool c, const Vec3<T>& x, const Vec3<T>& y) {
  return {pick(c, x.x, y.x), pick(c, x.y, y.y), pick(c, x.z, y.z)};
}
template <class T>
LS_HD inline BodyView<T> pick(bool c, const BodyView<T>& x, const BodyView<T>& y) {
  BodyView<T> r;
  r.v = pick(c, x.v, y.v);
  r.w = pick(c, x.w, y.w);
  r.inv_mass = pick(c, x.inv_mass, y.inv_mass);
  for (int row = 0; row < 3; ++row) r.R.row[row] = pick(c, x.R.row[row], y.R.row[row]);
  r.inv_inertia = pick(c, x.inv_inertia, y.inv_inertia);
  return r;
}

// The contact-side view of body j (dynamic when awake, else immovable). For
// kernels that write none of the arrays it reads.
template <class T>
LS_HD inline BodyView<T> view_of(const BodyArrays<T>& b, int j, const T4<T>* vel, const T4<T>* ang) {
  if (!is_awake(ro(b.flags + j))) return immovable_view<T>();
  const T4<T> pj = ro(b.pos + j);
  return dynamic_view(xyz(ro(vel + j)), xyz(ro(ang + j)), inv_mass_of(pj), rotation_matrix(quat(ro(b.rot + j))),
                      xyz(ro(b.inert + j)));
}

// Everything the solver kernels share.
template <class T>
struct SolverData {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const Counter* dir_count;
  const F4* sdf_c0;
  const F4* sdf_c1;
  ContactRecord<T>* imm;   // immovable contacts' state, imm_stride() per slot
  ContactRecord<T>* pair;  // body-body contacts' state, one per neighbour-list entry (each body keeps its own copy)
  PairManifold<T>* man = nullptr;  // oriented-box model: the pair's manifold and state, per entry (instead of `pair`)
  // eq 113's records, only with the skip on (converged_speed > 0; null
  // otherwise: none is read or written, and the pair record stays 256 bytes):
  // 4 F4 per visit, the sides' v, w (lower index first) its last visit left,
  // [0].w = 1 when it changed them by < converged_speed.
  F4* conv_imm = nullptr;   // each slot's ground and SDF manifolds
  F4* conv_pair = nullptr;  // each neighbour-list entry's pair (oriented-box model)
  LS_HD F4* conv_of_pair(int t) const { return conv_pair != nullptr ? conv_pair + 4 * static_cast<long>(t) : nullptr; }
};

// eq 113 (7.2 step 5, oriented-box model): a visit is skipped, converged,
// from pass converged_pass on (never the first) when its last visit changed
// its sides' velocities by less than converged_speed and they have moved by
// less than that since. `st`: the 4 F4 of its record, A the lower index
// (null, and never read, with the skip off).
template <class T>
LS_HD inline bool visit_is_converged(const T4<T>* st, const BodyView<T>& A, const BodyView<T>& B,
                                     const Params<T>& P, int pass) {
  if (!(T{} < P.converged_speed) || pass == 0 || pass < P.converged_pass || st[0].w == T{}) return false;
  return visit_converged(xyz(st[0]), xyz(st[1]), A.v, A.w, P.converged_speed) &&
         visit_converged(xyz(st[2]), xyz(st[3]), B.v, B.w, P.converged_speed);
}
// The record of a visit that took its sides from (va0, wa0, vb0, wb0) to A, B
// with `shortened` steps of eq 99 (alpha < 1: partial progress, not small).
template <class T>
LS_HD inline void record_visit(T4<T>* st, const Vec3<T>& va0, const Vec3<T>& wa0, const Vec3<T>& vb0,
                               const Vec3<T>& wb0, const BodyView<T>& A, const BodyView<T>& B,
                               const Params<T>& P, unsigned shortened) {
  if (!(T{} < P.converged_speed)) return;  // the skip is off (the default): no record is read, none is kept
  const bool small = shortened == 0 && visit_converged(va0, wa0, A.v, A.w, P.converged_speed) &&
                     visit_converged(vb0, wb0, B.v, B.w, P.converged_speed);
  st[0] = f4(A.v, small ? Num<T>::from_int(1) : T{});
  st[1] = f4(A.w, T{});
  st[2] = f4(B.v, T{});
  st[3] = f4(B.w, T{});
}

// Last frame's contacts, for the warm start (eq 96): the accumulated normal
// impulse is the x of each contact's first state F4.
template <class T>
struct PreviousContacts {
  using F4 = T4<T>;
  int frame;  // the previous frame's number
  const int* slot_of;
  const int* stamp;
  NeighbourLists lists;
  const ContactRecord<T>* imm;
  const int* ground_mask;  // per slot: bit c set when ground corner c was a contact
  const ContactRecord<T>* pair;
  const PairManifold<T>* man = nullptr;  // oriented-box model
  LS_HD bool had(int i) const { return ro(stamp + i) == frame; }
  // The entry of pair (i, j) in j's previous list (j active last frame), or -1.
  LS_HD int entry_of(int j, int i) const { return had(j) ? lists.find(ro(slot_of + j), i) : -1; }
  // The accumulated impulses of pair (i, j) from j's copy (j active last
  // frame); j_n = 0 when there is none.
  LS_HD F4 from(int j, int i) const {
    if (!had(j)) return F4{};
    const int t = lists.find(ro(slot_of + j), i);
    return t >= 0 ? ro(&pair[t].a) : F4{};
  }
};

}  // namespace lockstep::gpu
