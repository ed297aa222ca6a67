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
LS_HD inline int direction_of(const Vec3<float>& n) {
  int axis = 0;
  for (int ax = 1; ax < 3; ++ax)
    if (Num<float>::abs(n[ax]) > Num<float>::abs(n[axis])) axis = ax;
  return 2 * axis + (n[axis] < 0.0f ? 1 : 0);
}

// Mass splitting of the Jacobi solver: a body's contacts with other active
// bodies are counted per normal direction (one byte each of dir_count); a
// contact's effective mass is scaled by the larger of its two bodies' counts
// in its direction (n towards body i), over the relaxation. Contacts pushing a
// body the same way share it; opposite ones (a body in a stack) do not.
LS_HD inline float jacobi_split(Counter counts_i, Counter counts_j, const Vec3<float>& n_towards_i, float relaxation) {
  const int d = direction_of(n_towards_i);
  const unsigned mine = static_cast<unsigned>((counts_i >> (8 * d)) & 255u);
  const unsigned theirs = static_cast<unsigned>((counts_j >> (8 * (d ^ 1))) & 255u);
  return Num<float>::from_int(static_cast<int>(mine > theirs ? mine : theirs)) / relaxation;
}

// Support contact of a body (settling eq 75, sleep eq 78).
inline constexpr int kNoSupport = -1;
inline constexpr int kStaticSupport = -2;  // ground or SDF volume: v_s = 0

// c ? x : y, one float at a time (a select of whole structs can put them in
// local memory).
LS_HD inline float pick(bool c, float x, float y) { return c ? x : y; }
LS_HD inline Vec3<float> pick(bool c, const Vec3<float>& x, const Vec3<float>& y) {
  return {pick(c, x.x, y.x), pick(c, x.y, y.y), pick(c, x.z, y.z)};
}
LS_HD inline BodyView<float> pick(bool c, const BodyView<float>& x, const BodyView<float>& y) {
  BodyView<float> r;
  r.v = pick(c, x.v, y.v);
  r.w = pick(c, x.w, y.w);
  r.inv_mass = pick(c, x.inv_mass, y.inv_mass);
  for (int row = 0; row < 3; ++row) r.R.row[row] = pick(c, x.R.row[row], y.R.row[row]);
  r.inv_inertia = pick(c, x.inv_inertia, y.inv_inertia);
  return r;
}

// The contact-side view of body j (dynamic when awake, else immovable). For
// kernels that write none of the arrays it reads.
LS_HD inline BodyView<float> view_of(const BodyArrays& b, int j, const F4* vel, const F4* ang) {
  if (!is_awake(ro(b.flags + j))) return immovable_view<float>();
  const F4 pj = ro(b.pos + j);
  return dynamic_view(xyz(ro(vel + j)), xyz(ro(ang + j)), inv_mass_of(pj), rotation_matrix(quat(ro(b.rot + j))),
                      xyz(ro(b.inert + j)));
}

// Everything the solver kernels share.
struct SolverData {
  const int* list;
  BodyArrays b;
  SceneConsts sc;
  NeighbourLists lists;
  const Counter* dir_count;
  const F4* sdf_c0;
  const F4* sdf_c1;
  ContactRecord* imm;   // immovable contacts' state, imm_stride() per slot
  ContactRecord* pair;  // body-body contacts' state, one per neighbour-list entry (each body keeps its own copy)
  PairManifold* man = nullptr;  // oriented-box model: the pair's manifold and state, per entry (instead of `pair`)
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
LS_HD inline bool visit_is_converged(const F4* st, const BodyView<float>& A, const BodyView<float>& B,
                                     const Params<float>& P, int pass) {
  if (!(P.converged_speed > 0.0f) || pass == 0 || pass < P.converged_pass || st[0].w == 0.0f) return false;
  return visit_converged(xyz(st[0]), xyz(st[1]), A.v, A.w, P.converged_speed) &&
         visit_converged(xyz(st[2]), xyz(st[3]), B.v, B.w, P.converged_speed);
}
// The record of a visit that took its sides from (va0, wa0, vb0, wb0) to A, B
// with `shortened` steps of eq 99 (alpha < 1: partial progress, not small).
LS_HD inline void record_visit(F4* st, const Vec3<float>& va0, const Vec3<float>& wa0, const Vec3<float>& vb0,
                               const Vec3<float>& wb0, const BodyView<float>& A, const BodyView<float>& B,
                               const Params<float>& P, unsigned shortened) {
  if (!(P.converged_speed > 0.0f)) return;  // the skip is off (the default): no record is read, none is kept
  const bool small = shortened == 0 && visit_converged(va0, wa0, A.v, A.w, P.converged_speed) &&
                     visit_converged(vb0, wb0, B.v, B.w, P.converged_speed);
  st[0] = f4(A.v, small ? 1.0f : 0.0f);
  st[1] = f4(A.w, 0.0f);
  st[2] = f4(B.v, 0.0f);
  st[3] = f4(B.w, 0.0f);
}

// Last frame's contacts, for the warm start (eq 96): the accumulated normal
// impulse is the x of each contact's first state F4.
struct PreviousContacts {
  int frame;  // the previous frame's number
  const int* slot_of;
  const int* stamp;
  NeighbourLists lists;
  const ContactRecord* imm;
  const int* ground_mask;  // per slot: bit c set when ground corner c was a contact
  const ContactRecord* pair;
  const PairManifold* man = nullptr;  // oriented-box model
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
