// Per-contact steps of the contact solver (docs/SPEC.md 7.2 stage 5), host
// and device (LS_HD), generic over the number type: World<T>::solve_contacts
// (reference/src/contact_solver.hpp) and the GPU engine's kernels
// (gpu/src/*_stages.hpp) call these same functions for one contact or one
// manifold; they differ in the order of visits, not in formulas.
#pragma once
#include <new>
#include <type_traits>

#include "lockstep/math/vec.hpp"
#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/params.hpp"

namespace lockstep {

template <class T>
LS_HD Mat3<T> identity3() {
  const T one = Num<T>::from_int(1);
  return {{{one, T{}, T{}}, {T{}, one, T{}}, {T{}, T{}, one}}};
}

// The contact-side view of an immovable side (ground, SDF volume, static or
// sleeping body): inverse mass and inertia 0, no velocity.
template <class T>
LS_HD BodyView<T> immovable_view() {
  BodyView<T> v;
  v.R = identity3<T>();
  return v;
}

// The contact-side view of an awake body: velocity v (m/s), angular velocity
// w (rad/s), inverse mass (1/kg), rotation R and body-frame inverse inertia
// (eq 18).
template <class T>
LS_HD BodyView<T> dynamic_view(const Vec3<T>& v, const Vec3<T>& w, const T& inv_mass, const Mat3<T>& R,
                               const Vec3<T>& inv_inertia) {
  BodyView<T> b;
  b.v = v;
  b.w = w;
  b.inv_mass = inv_mass;
  b.R = R;
  b.inv_inertia = inv_inertia;
  return b;
}

// What the solver counts (docs/SPEC.md "Per-stage counters").
struct SolveCounts {
  unsigned solver_contacts = 0;      // contact visits
  unsigned normal_impulses = 0;      // non-zero normal impulses applied (eqs 53, 87)
  unsigned restitution_bounces = 0;  // contacts prepared with e_eff > 0 (eq 76)
  unsigned friction_steps = 0;       // non-zero friction impulses applied (eqs 61-62)
  unsigned shortened_steps = 0;      // eq 99 steps shortened below half (alpha < 1/2): partial progress, never converged (eq 113)
};

// A contact's solver state (eqs 94-96): accumulated impulses and the values
// fixed when the solve starts.
template <class T>
struct ContactState {
  T j_n{};        // accumulated normal impulse (eq 94, N s), >= 0
  Vec3<T> j_t{};  // accumulated friction impulse (eq 95, N s)
  T v_n0{};       // approach speed before the solve (eq 49, m/s)
  T e{};          // restitution after eqs 50, 76 (1)
  T mu{};         // friction coefficient (eq 58, 1)
  T k_n{};        // inverse effective mass along n (eq 86, 1/kg); 0: both sides immovable
};

// eq 113 (7.2 step 5): one side of a solver visit is converged when each
// component of its velocity v (m/s) and angular velocity w (rad/s) differs
// from what the visit last left, v0 and w0, by less than eps
// (converged_speed; 0, the default, is never met): exact comparisons, no
// rounding.
template <class T>
LS_HD bool visit_converged(const Vec3<T>& v0, const Vec3<T>& w0, const Vec3<T>& v, const Vec3<T>& w, const T& eps) {
  for (int k = 0; k < 3; ++k)
    if (!(Num<T>::abs(v[k] - v0[k]) < eps) || !(Num<T>::abs(w[k] - w0[k]) < eps)) return false;
  return true;
}

// The preparation of one contact (eqs 48-50, 58, 76, 86) with the velocities
// before the warm start: A is body 1 with lever arm r1 and material (e1, mu1),
// B body 2 with r2 and (e2, mu2), n points from B to A. Impulses start at 0.
template <class T>
LS_HD ContactState<T> prepare_contact(const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B, const Vec3<T>& r2,
                                      const Vec3<T>& n, const T& e1, const T& mu1, const T& e2, const T& mu2,
                                      bool restitution, bool friction, const Params<T>& P, SolveCounts& counts) {
  ContactState<T> c;
  c.v_n0 = dot(relative_velocity(A, r1, B, r2), n);  // eqs 48-49
  c.e = restitution ? low_speed_restitution(combined_restitution(e1, e2), c.v_n0, P.restitution_min_speed)
                    : T{};  // eqs 50, 76
  if (c.e > T{}) ++counts.restitution_bounces;
  c.mu = friction ? combined_friction(mu1, mu2) : T{};  // eq 58
  c.k_n = inverse_effective_mass(A, r1, B, r2, n);      // eq 86
  return c;
}

// eq 128: the tangent basis of a unit contact normal n: t1 perpendicular to
// n, from the two components other than the smaller of |n.x|, |n.y|
// ((n.z, 0, -n.x) / |.| when |n.x| > |n.y|, else (0, n.z, -n.y) / |.|; never
// a zero vector for a unit n), and t2 = n x t1. Ground and axis-aligned
// normals give axis tangents exactly.
template <class T>
LS_HD_INLINE void tangent_basis(const Vec3<T>& n, Vec3<T>& t1, Vec3<T>& t2) {
  if (Num<T>::abs(n.x) > Num<T>::abs(n.y)) t1 = normalize(Vec3<T>{n.z, T{}, -n.x});
  else t1 = normalize(Vec3<T>{T{}, n.z, -n.y});
  t2 = cross(n, t1);
}

// eqs 114, 128-129: the rows of a contact point (A at r1, B at r2, n from B to
// A), formed from the point and the sides' masses, rotations and inertia,
// which the solve does not change: World<T> forms them once per frame, the
// GPU engine once per visit (the same values). The normal row: r1 x n,
// r2 x n and their images under the sides' world inverse inertia (eq 90);
// the effective mass along n, m_n = 1/k_n (eq 86's k_n, 0 when it is 0).
// The tangent rows: the tangents t_a of eq 128 with r x t_a and
// I^-1 (r x t_a) of each side, and the 2x2 tangent matrix K_t (eq 129:
// k_ab = (m1^-1 + m2^-1) [a = b] + (r1 x t_a).I1^-1 (r1 x t_b)
// + (r2 x t_a).I2^-1 (r2 x t_b): eq 86 in the tangent plane, so that eq 86
// along any tangent u = u_1 t_1 + u_2 t_2 is u^T K_t u).
template <class T>
struct ContactRows {
  Vec3<T> rn1, rn2;        // r1 x n, r2 x n (m)
  Vec3<T> an1, an2;        // I1^-1 (r1 x n), I2^-1 (r2 x n) (1/(kg m))
  Vec3<T> t[2];            // eq 128: the tangents (1)
  Vec3<T> rt1[2], rt2[2];  // r1 x t_a, r2 x t_a (m)
  Vec3<T> at1[2], at2[2];  // I1^-1 (r1 x t_a), I2^-1 (r2 x t_a) (1/(kg m))
  T m_n{};                 // 1 / k_n (kg)
  T k_t[3]{};              // eq 129: K_t as {k11, k12, k22} (1/kg)
};
// The normal half of contact_rows (eq 114 and m_n) and the tangent half
// (eqs 128-129), each alone: a device visit forms the half a step reads where
// it reads it (the same values as contact_rows').
template <class T>
LS_HD_INLINE void normal_rows(ContactRows<T>& w, const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B,
                              const Vec3<T>& r2, const Vec3<T>& n, const T& k_n) {
  w.rn1 = cross(r1, n);  // eq 51
  w.rn2 = cross(r2, n);
  w.an1 = apply_inverse_inertia(A.R, A.inv_inertia, w.rn1);
  w.an2 = apply_inverse_inertia(B.R, B.inv_inertia, w.rn2);
  w.m_n = k_n > T{} ? Num<T>::from_int(1) / k_n : T{};
}
template <class T>
LS_HD_INLINE void tangent_rows(ContactRows<T>& w, const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B,
                               const Vec3<T>& r2, const Vec3<T>& n) {
  tangent_basis(n, w.t[0], w.t[1]);  // eq 128
  for (int a = 0; a < 2; ++a) {
    w.rt1[a] = cross(r1, w.t[a]);
    w.rt2[a] = cross(r2, w.t[a]);
    w.at1[a] = apply_inverse_inertia(A.R, A.inv_inertia, w.rt1[a]);
    w.at2[a] = apply_inverse_inertia(B.R, B.inv_inertia, w.rt2[a]);
  }
  const T lin = A.inv_mass + B.inv_mass;  // eq 129
  w.k_t[0] = lin + dot(w.rt1[0], w.at1[0]) + dot(w.rt2[0], w.at2[0]);
  w.k_t[1] = dot(w.rt1[0], w.at1[1]) + dot(w.rt2[0], w.at2[1]);
  w.k_t[2] = lin + dot(w.rt1[1], w.at1[1]) + dot(w.rt2[1], w.at2[1]);
}
template <class T>
LS_HD_INLINE ContactRows<T> contact_rows(const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B,
                                         const Vec3<T>& r2, const Vec3<T>& n, const T& k_n) {
  ContactRows<T> w;
  normal_rows(w, A, r1, B, r2, n, k_n);
  tangent_rows(w, A, r1, B, r2, n);
  return w;
}
// A still side B (the template flag kStillB of the four functions below
// and of apply_delta): an immovable side at rest (immovable_view: no
// velocity, inverse mass and inertia 0, so its rows' halves I2^-1 (r2 x .)
// are 0) in an exact number type. Each of its terms is then an exact zero
// (v - 0, a dot product with 0, 0 times a number), with no rounding and no
// Q16 status flag, so leaving them out gives the same bits; a float's zero
// has a sign that they could change, so there the flag does nothing.
template <class T, bool kImmovableB>
inline constexpr bool kStillSide = kImmovableB && Num<T>::kExact;

// eqs 48-49 along n through the rows (eq 114): v_n = (v1 - v2).n + w1.(r1 x n) - w2.(r2 x n).
template <bool kStillB = false, class T>
LS_HD_INLINE T normal_velocity(const BodyView<T>& A, const BodyView<T>& B, const ContactRows<T>& row, const Vec3<T>& n) {
  if constexpr (kStillB) return dot(A.v, n) + dot(A.w, row.rn1);
  else return dot(A.v - B.v, n) + dot(A.w, row.rn1) - dot(B.w, row.rn2);
}
// Eq 87's velocity changes for the impulse J = n j through the rows (eq 114):
// n (j m1^-1), I1^-1 (r1 x n) j on A and the same of B (taken off B).
template <bool kStillB = false, class T>
LS_HD_INLINE ImpulseDelta<T> normal_delta(const BodyView<T>& A, const BodyView<T>& B, const ContactRows<T>& row,
                                          const Vec3<T>& n, const T& j) {
  if constexpr (kStillB) return {n * (j * A.inv_mass), row.an1 * j, {}, {}};
  else return {n * (j * A.inv_mass), row.an1 * j, n * (j * B.inv_mass), row.an2 * j};
}
// eqs 48, 56 along the tangents through the rows (eq 129): the sliding
// velocity's components vt_a = (v1 - v2).t_a + w1.(r1 x t_a) - w2.(r2 x t_a).
template <bool kStillB = false, class T>
LS_HD_INLINE void tangent_velocity(const BodyView<T>& A, const BodyView<T>& B, const ContactRows<T>& row, T* vt) {
  if constexpr (kStillB) {
    for (int a = 0; a < 2; ++a) vt[a] = dot(A.v, row.t[a]) + dot(A.w, row.rt1[a]);
  } else {
    const Vec3<T> dv = A.v - B.v;
    for (int a = 0; a < 2; ++a) vt[a] = dot(dv, row.t[a]) + dot(A.w, row.rt1[a]) - dot(B.w, row.rt2[a]);
  }
}
// Eq 87's velocity changes for a friction impulse J (in the tangent plane)
// through the rows (eq 129): with l_a = J.t_a, J m1^-1 and
// I1^-1 (r1 x t_1) l_1 + I1^-1 (r1 x t_2) l_2 on A, the same of B taken off
// B (I^-1 (r x J) in exact arithmetic).
template <bool kStillB = false, class T>
LS_HD_INLINE ImpulseDelta<T> tangent_delta(const BodyView<T>& A, const BodyView<T>& B, const ContactRows<T>& row,
                                           const Vec3<T>& J) {
  const T l0 = dot(J, row.t[0]), l1 = dot(J, row.t[1]);
  if constexpr (kStillB) return {J * A.inv_mass, row.at1[0] * l0 + row.at1[1] * l1, {}, {}};
  else return {J * A.inv_mass, row.at1[0] * l0 + row.at1[1] * l1, J * B.inv_mass, row.at2[0] * l0 + row.at2[1] * l1};
}
// eq 95 with the tangent rows (eq 129): the friction impulse accumulated over
// the passes, a world vector in the contact plane, moves against the
// sliding velocity vt (its components along t_1, t_2) by vt / k_t, k_t eq
// 86's inverse effective mass along the sliding direction (eqs 57, 60, 88),
// read off K_t: with u = vt / max(|vt_1|, |vt_2|) (components in [-1, 1], so
// that no square leaves Q16.16), k_t = u^T K_t u / |u|^2; times `scale`
// (eq 99's 1/split). The sum is clamped to the Coulomb cone
// |J_t| <= mu J_n (so a sliding point's friction opposes its own sliding);
// returns the change to apply. No root and one division per point less
// than forming k_t from the direction (normalize(v_tan), eq 86): the same
// value in exact arithmetic.
template <class T>
LS_HD_INLINE Vec3<T> accumulate_friction_impulse(Vec3<T>& accumulated, const T* vt, const ContactRows<T>& row,
                                                 const T& scale, const T& mu, const T& j_n) {
  Vec3<T> proposal = accumulated;
  const T reach = Num<T>::max(Num<T>::abs(vt[0]), Num<T>::abs(vt[1]));
  if (reach > T{}) {  // eq 57: sliding
    const T u0 = vt[0] / reach, u1 = vt[1] / reach;
    const T uKu = row.k_t[0] * (u0 * u0) + (row.k_t[1] * (u0 * u1)) * Num<T>::from_int(2) + row.k_t[2] * (u1 * u1);
    if (uKu > T{}) {
      const T inv_k = (u0 * u0 + u1 * u1) / uKu;  // 1 / k_t (eqs 60, 88)
      proposal -= (row.t[0] * (vt[0] * inv_k) + row.t[1] * (vt[1] * inv_k)) * scale;
    }
  }
  const Vec3<T> updated = clamp_to_cone(proposal, mu * j_n);
  const Vec3<T> old = accumulated;
  accumulated = updated;
  return updated - old;
}

// Eq 96: the warm start of one contact from last frame's accumulated normal
// impulse cached_j_n of the same contact (same bodies, same feature), applied
// to A and B, unless the contact is already separating faster than
// restitution_min_speed (v_n0 > it, eq 76's threshold): the cache holds a
// load that persists, and a contact moving apart that fast is not loaded; the
// impulse it cached was last frame's impact, and struck again it added 13 J
// to a spinning box deep in the ground that one pass then failed to take
// back (docs/HARD_CASES.md, 2026-11-26). Friction starts from zero: a
// warm-started friction impulse on a resting manifold kept re-injecting spin
// about the normal that 4 iterations did not remove.
// warm_start_delta: the same in two halves, for World<T> on threads: sets
// c.j_n and gives the velocity changes to apply (eq 87; false: none), which
// depend on the sides' masses, rotations and inertia alone, so that each
// body can add its contacts' changes in contact order.
template <class T>
LS_HD bool warm_start_delta(const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B, const Vec3<T>& r2,
                            const Vec3<T>& n, ContactState<T>& c, const T& cached_j_n, const Params<T>& P,
                            ImpulseDelta<T>& delta) {
  if (!(c.k_n > T{}) || c.v_n0 > P.restitution_min_speed) return false;
  c.j_n = cached_j_n;
  delta = impulse_delta(A, r1, B, r2, n * c.j_n);  // eq 87
  return true;
}
template <class T>
LS_HD void warm_start_contact(BodyView<T>& A, const Vec3<T>& r1, BodyView<T>& B, const Vec3<T>& r2, const Vec3<T>& n,
                              ContactState<T>& c, const T& cached_j_n, const Params<T>& P) {
  ImpulseDelta<T> d;
  if (warm_start_delta(A, r1, B, r2, n, c, cached_j_n, P, d)) apply_delta(A, B, d);
}

// Eq 97's g_n: gravity presses a body onto an immovable side B; two falling
// bodies feel none. B's mobility does not change during the solve.
template <class T>
LS_HD_INLINE T gravity_pressing(const BodyView<T>& B, const Vec3<T>& n, bool gravity, const Params<T>& P) {
  return (gravity && B.inv_mass == T{}) ? -dot(P.gravity, n) : T{};
}

// Eq 99's first half, for the normal and the friction step: the sides Z,
// Zb (A's and B's masses, rotations and inertia) are set at rest and gather
// every point's proposed velocity change (eq 87) in point order;
// `propose(k, dl, size)` gives point k's change dl and its impulse's size
// (false: no proposal). Returns R, the largest size; with `deltas`, point
// k's change is kept in deltas[k]; formed[k] tells whether it was formed.
template <bool kStillB = false, class T, class Propose>
LS_HD_INLINE T proposals_at_rest(BodyView<T>& Z, BodyView<T>& Zb, int end, ImpulseDelta<T>* deltas, bool* formed,
                                 const Propose& propose) {
  Z.v = Z.w = Zb.v = Zb.w = Vec3<T>{};
  T reach{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    formed[k] = false;
    ImpulseDelta<T> dl;
    T size;
    if (!propose(k, dl, size)) continue;
    apply_delta<kStillB>(Z, Zb, dl);
    if (deltas != nullptr) deltas[k] = dl;
    formed[k] = true;
    reach = Num<T>::max(reach, size);
  }
  return reach;
}

// Eq 99's step length for a manifold's normal proposals dj_k (eq 114's rows):
// with R = max_k |dj_k| and w_k = dj_k / R, a = sum_k w_k res_k (res_k =
// target_k - v_n,k) and b = sum_k w_k (n_k . dv_k), dv_k the velocity change
// at point k that all the proposals cause together (the normal velocity of
// the sides at rest after them). `normal(k, n)`: whether point k is a contact
// (and its normal n); `row(k)`: its rows. With `deltas`, point k's eq 87
// velocity changes are kept in deltas[k]; formed[k] tells whether they were
// formed (dj_k != 0).
template <int N, bool kStillB = false, class T, class Normal, class Row>
LS_HD_INLINE T normal_manifold_step(const BodyView<T>& A, const BodyView<T>& B, const Normal& normal, const Row& row,
                                    const T* dj, const T* res, int end, ImpulseDelta<T>* deltas, bool* formed) {
  BodyView<T> Z = A, Zb = B;
  const T reach = proposals_at_rest<kStillB>(Z, Zb, end, deltas, formed, [&](int k, ImpulseDelta<T>& dl, T& size) {
    Vec3<T> n;
    if (dj[k] == T{} || !normal(k, n)) return false;
    dl = normal_delta<kStillB>(Z, Zb, row(k), n, dj[k]);
    size = Num<T>::abs(dj[k]);
    return true;
  });
  if (!(reach > T{})) return Num<T>::from_int(1);
  T a{}, b{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    Vec3<T> n;
    if (!formed[k] || !normal(k, n)) continue;
    const T w = dj[k] / reach;  // in [-1, 1]
    a += w * res[k];
    b += w * normal_velocity<kStillB>(Z, Zb, row(k), n);
  }
  return manifold_step_length(a, b);
}

// Eq 99's step length for a manifold's friction proposals dJ_k (world
// vectors in the contact planes) through the tangent rows (eq 129): with
// R = max_k max_abs(dJ_k) and w_k,a = (dJ_k . t_k,a) / R, a = -sum_k w_k . vt_k
// (the pull: the sliding velocities at the step's start) and
// b = sum_k w_k . dvt_k, dvt_k the tangent velocity change at point k that
// all the proposals cause together. `row(k)`: point k's rows (a point with
// dJ_k != 0 is a contact); deltas and formed as normal_manifold_step's.
template <int N, bool kStillB = false, class T, class Row>
LS_HD_INLINE T friction_manifold_step(const BodyView<T>& A, const BodyView<T>& B, const Row& row, const Vec3<T>* dJ,
                                      const T* vt0, const T* vt1, int end, ImpulseDelta<T>* deltas, bool* formed) {
  BodyView<T> Z = A, Zb = B;
  const T reach = proposals_at_rest<kStillB>(Z, Zb, end, deltas, formed, [&](int k, ImpulseDelta<T>& dl, T& size) {
    if (dJ[k] == Vec3<T>{}) return false;
    dl = tangent_delta<kStillB>(Z, Zb, row(k), dJ[k]);
    size = max_abs(dJ[k]);
    return true;
  });
  if (!(reach > T{})) return Num<T>::from_int(1);
  T a{}, b{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    if (!formed[k]) continue;
    const auto& w = row(k);
    const T w0 = dot(dJ[k], w.t[0]) / reach, w1 = dot(dJ[k], w.t[1]) / reach;  // in [-1.8, 1.8]
    T dvt[2];
    tangent_velocity<kStillB>(Z, Zb, w, dvt);
    a -= w0 * vt0[k] + w1 * vt1[k];
    b += w0 * dvt[0] + w1 * dvt[1];
  }
  return manifold_step_length(a, b);
}

// Eq 99's split of a manifold's effective masses: max(1, o) for a manifold of
// count > 1 points, o = sum_k split_share(m1^-1, m2^-1, k_n,k) summed in point
// order (1 for a unit cube's 4 bottom corners, 2 for 8 sunken corners); 1 for
// a single point. It depends on the sides' masses and the points' k_n alone,
// which the solve does not change: World<T> forms it once per frame, the GPU
// engine at each visit (the same values).
template <class T>
LS_HD_INLINE T split_share(const T& inv_mass_a, const T& inv_mass_b, const T& k_n) {
  return (inv_mass_a + inv_mass_b) / k_n;
}
template <class T>
LS_HD_INLINE T manifold_split(const T& o, int count) {
  const T one = Num<T>::from_int(1);
  return (count > 1 && o > one) ? o : one;
}

// Host builds leave a visit's scratch unfilled (below); device builds
// (std::launder is host code) use plain arrays.
#if defined(__CUDA_ARCH__)
inline constexpr bool kUnfilledScratch = false;
#else
inline constexpr bool kUnfilledScratch = true;
#endif

// A manifold visit's scratch of M values of V, each written before it is
// read. Host builds leave it unfilled: the zero fill of the visit's 2.7 KB of
// scratch (Vec3's and Q16's members start at 0) was 5 % of the solve. V, an
// aggregate of trivially copyable numbers, is an implicit-lifetime type, so
// the storage holds a V once one is assigned to it (C++20 [intro.object]).
// Device builds and number types that are not trivially copyable (mp): a
// plain array.
template <class V, int M, bool kUnfilled = kUnfilledScratch && std::is_trivially_copyable_v<V>>
struct Scratch {
  V v[M];
  LS_HD_INLINE V* data() { return v; }
  LS_HD_INLINE V& operator[](int k) { return v[k]; }
};
template <class V, int M>
struct Scratch<V, M, true> {
  alignas(V) unsigned char bytes[sizeof(V) * M];
  V* data() { return std::launder(reinterpret_cast<V*>(bytes)); }
  V& operator[](int k) { return data()[k]; }
};

// One solver visit of a manifold (eq 99): a body A's contacts with one
// immovable environment object B (its ground corners, its samples of one SDF
// volume; r2 = 0), the points of a body pair's box-box manifold (eq 105; B
// the other body, r2 its lever arms), or one contact alone (N = 1:
// solve_contact), solved Jacobi-style so that a symmetric landing stays
// symmetric. Normal step: every point's impulse is proposed from the
// velocities at the start of the visit (eqs 53, 94, 97), with each point's
// effective mass m_n (eq 114) divided by split = max(1, o),
// o = sum_k m^-1 / k_n,k (the points share one body, so their simultaneous
// impulses add up: o is 1 for a unit cube's 4 bottom corners, 2 for 8 sunken
// corners, 3.8 for a tall thin box standing); the proposals are scaled by the
// step length alpha of eq 99 (manifold_step_length), which stops the sum from
// overshooting through the rotation (two corners at one end of a thin plate)
// and so from adding energy; then all are applied. Friction step: the same,
// from the velocities after the normal step, through the tangent rows
// (eqs 95, 128-129).
// `point(k, r1, r2, n, penetration)` gives point k (k = 0..N-1; false: not a
// contact), `row(k)` its rows (eqs 114, 128-129: contact_rows of the visit's
// two sides; World<T> returns a reference to the rows it formed once per
// frame, the GPU engine forms them, and the visit keeps them);
// `load(k)` and `store(k, state)` read and write its solver state.
// The visit is skipped when the first point's k_n is 0 (both sides
// immovable).
// `k_scale` multiplies every point's inverse effective masses on top of eq
// 99's split: 1 is World<T>'s sequential visit; the GPU engine's Jacobi
// visits of a pair of active bodies pass their mass splitting (docs/GPU.md).
// `split_given`: the visit's manifold_split, formed before the solve (World<T>,
// once per frame); nullptr: formed here from the points (the same value).
template <int N, bool kKeepOnDevice = false, bool kImmovableB = false, class T, class Point, class Row, class Load,
          class Store>
LS_HD void solve_manifold_rows(BodyView<T>& A, BodyView<T>& B, const Point& point_at, const Row& row_at,
                               const Load& load_at, const Store& store_at, bool friction, bool gravity,
                               const T& k_scale, const Params<T>& P, SolveCounts& counts,
                               const T* split_given = nullptr) {
  const T one = Num<T>::from_int(1);
  const T half = Num<T>::from_double(0.5);  // eq 113: a step shortened below it is partial progress
  // Host builds keep what the visit reads again: each point's normal,
  // penetration, state and rows (read in place when row_at gives a
  // reference: World<T>'s, formed once per frame), and eq 87's velocity
  // changes as the steps formed them. Float device builds keep none of it
  // (a thread's local memory costs more than forming again: on an H200 the
  // float engine's 10^6 frame took 32.8 ms with the rows kept, 21.9 formed
  // again): they read the point and its state where they need them and form
  // the half of its rows a step reads (normal_rows, tangent_rows). Q16 on a
  // device keeps them (its roots and divisions are 64-bit integer work:
  // gpu-fixed's frame took 74 ms kept, 103 formed again), unless its rows
  // were formed once and are read in place (gpu-fixed's EdgeRowsK): then it
  // keeps nothing either and reads the rows, points and states where they
  // lie (a thread's local memory, spilled past L1 at the visit's 2 KB, cost
  // more than the reads: the 10^6 frame's solve 33.9 ms kept, 29.5 not).
  // kKeepOnDevice keeps the points and states of a visit whose points are
  // formed, not read (SolveK's ground corners); a device reads rows formed
  // once where they lie in any case. The same values either way, so the
  // same bits.
  // kImmovableB: B is immovable_view() (the ground, an SDF volume); in an
  // exact number type its terms are left out (kStillSide: the same bits).
  constexpr bool kStill = kStillSide<T, kImmovableB>;
  constexpr bool kRowsInPlace = std::is_reference_v<decltype(row_at(0))>;
#if defined(__CUDA_ARCH__)
  constexpr bool kCache = !std::is_floating_point_v<T> && (kKeepOnDevice || !kRowsInPlace);
  constexpr bool kReadInPlace = kRowsInPlace;
#else
  constexpr bool kCache = true;
  constexpr bool kReadInPlace = false;
#endif
  constexpr int M = kCache ? N : 1;
  Scratch<Vec3<T>, M> pn;
  Scratch<T, M> ppen;
  Scratch<ContactState<T>, M> pst;
  Scratch<ContactRows<T>, (kCache && !kRowsInPlace) ? N : 1> prow;
  const ContactRows<T>* rows[kReadInPlace ? 1 : M] = {};
  bool pok[M] = {};  // (nvcc cannot see that every read follows the first loop's write)
  // Point k's normal and penetration (false: not a contact).
  auto point = [&](int k, Vec3<T>& n, T& penetration) -> bool {
    if constexpr (kCache) {
      if (!pok[k]) return false;
      n = pn[k];
      penetration = ppen[k];
      return true;
    } else {
      Vec3<T> r1, r2;
      return point_at(k, r1, r2, n, penetration);
    }
  };
  auto normal = [&](int k, Vec3<T>& n) -> bool {
    T penetration;
    return point(k, n, penetration);
  };
  auto load = [&](int k) -> ContactState<T> {
    if constexpr (kCache) return pst[k];
    else return load_at(k);
  };
  auto store = [&](int k, const ContactState<T>& st) {
    if constexpr (kCache) pst[k] = st;
    store_at(k, st);
  };
  // Point k's rows: the normal half (nrow) and the tangent half (trow).
  auto formed_half = [&](int k, bool tangent) {
    ContactRows<T> w;
    Vec3<T> r1, r2, n;
    T penetration;
    point_at(k, r1, r2, n, penetration);
    if (tangent) tangent_rows(w, A, r1, B, r2, n);  // reads the sides' masses, rotations, inertia: unchanged by the visit
    else normal_rows(w, A, r1, B, r2, n, load_at(k).k_n);
    return w;
  };
  auto nrow = [&](int k) -> decltype(auto) {
    if constexpr (kReadInPlace) return static_cast<const ContactRows<T>&>(row_at(k));
    else if constexpr (kCache) return static_cast<const ContactRows<T>&>(*rows[k]);
    else return formed_half(k, false);
  };
  auto trow = [&](int k) -> decltype(auto) {
    if constexpr (kReadInPlace) return static_cast<const ContactRows<T>&>(row_at(k));
    else if constexpr (kCache) return static_cast<const ContactRows<T>&>(*rows[k]);
    else return formed_half(k, true);
  };
  T split = one;  // eq 99
  int count = 0, end = 0;  // end: 1 + the last point that is a contact
  {
    T o{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
    for (int k = 0; k < N; ++k) {
      Vec3<T> r1, r2, n;
      T penetration;
      const bool ok = point_at(k, r1, r2, n, penetration);
      const ContactState<T> st = ok ? load_at(k) : ContactState<T>{};
      if constexpr (kCache) {
        pok[k] = ok;
        if (ok) {
          pn[k] = n, ppen[k] = penetration, pst[k] = st;
          if constexpr (kReadInPlace) {
            // read where they lie, at each use
          } else if constexpr (kRowsInPlace) {
            rows[k] = &row_at(k);
          } else {
            prow[k] = row_at(k);
            rows[k] = &prow[k];
          }
        }
      }
      if (!ok) continue;
      if (count == 0 && !(st.k_n > T{})) return;  // both sides immovable
      ++count;
      end = k + 1;
      if (split_given == nullptr) o += split_share(A.inv_mass, B.inv_mass, st.k_n);
    }
    if (count == 0) return;
    split = split_given != nullptr ? *split_given : manifold_split(o, count);
    if (!(k_scale == one)) split = split * k_scale;
  }
  const T inv_split = split == one ? one : one / split;  // eq 99: the effective masses' share
  Scratch<T, N> dj, res;
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    dj[k] = res[k] = T{};
    Vec3<T> n;
    T penetration;
    if (!point(k, n, penetration)) continue;
    const ContactState<T> c = load(k);
    ++counts.solver_contacts;
    const auto& w = nrow(k);
    const T v_n = normal_velocity<kStill>(A, B, w, n);  // eqs 48-49 (eq 114), at the visit's start
    // Only approaching contacts bounce (the fix of 3.1): the target -e v_n0 uses v_n0 <= 0.
    const T target = contact_target_velocity(penetration, c.e, Num<T>::min(c.v_n0, T{}),
                                             gravity_pressing(B, n, gravity, P), P.dt, P.inv_dt);  // eq 97
    T j_n = c.j_n;
    dj[k] = accumulate_normal_impulse(j_n, v_n, target, w.m_n * inv_split);  // eqs 53, 94, 99
    res[k] = target - v_n;
  }
  // kCache: eq 87's velocity changes as the step formed them, applied as
  // they are when the step is 1 (the impulses unchanged).
  Scratch<ImpulseDelta<T>, M> delta;
  bool formed[N];
  bool cached = false;
  if (count > 1) {
    const T alpha = normal_manifold_step<N, kStill>(A, B, normal, nrow, dj.data(), res.data(), end,
                                            kCache ? delta.data() : nullptr, formed);  // eqs 99, 114
    if (alpha < one) {
      if (alpha < half) ++counts.shortened_steps;  // eq 113: less than half the proposals' change
      for (int k = 0; k < end; ++k) dj[k] = dj[k] * alpha;
    } else {
      cached = kCache;
    }
  }
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    Vec3<T> n;
    if (dj[k] == T{} || !normal(k, n)) continue;
    ContactState<T> c = load(k);
    c.j_n += dj[k];  // eq 94: stays >= 0, alpha <= 1
    store(k, c);
    if (cached && formed[k]) apply_delta<kStill>(A, B, delta[k]);                // eq 87, as the step formed it
    else apply_delta<kStill>(A, B, normal_delta<kStill>(A, B, nrow(k), n, dj[k]));  // eqs 87, 114
    ++counts.normal_impulses;
  }
  if (!friction) return;
  // Friction (eqs 56-62, 95, 128-129). Of a manifold (eq 99), first the cone:
  // a friction impulse left above mu J_n when J_n has since dropped is
  // pulled back onto the cone, whole (a projection, not a step to be
  // shortened: with it inside the proposals, a step length that tends to 0
  // as a tends to 0+ and jumps to 1 at a <= 0 left friction above the cone in
  // one engine and not in another). A single point does both in eq 95's one
  // step.
  if (count > 1) {
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
    for (int k = 0; k < end; ++k) {
      Vec3<T> n;
      if (!normal(k, n)) continue;
      ContactState<T> c = load(k);
      if (c.j_t == Vec3<T>{}) continue;
      const Vec3<T> inside = clamp_to_cone(c.j_t, c.mu * c.j_n);  // eq 95's clamp
      if (inside == c.j_t) continue;
      const Vec3<T> back = inside - c.j_t;
      c.j_t = inside;
      store(k, c);
      apply_delta<kStill>(A, B, tangent_delta<kStill>(A, B, trow(k), back));  // eqs 61-62, 87, 129
      ++counts.friction_steps;
    }
  }
  Scratch<Vec3<T>, N> dJ;
  Scratch<T, N> vt0, vt1;  // the sliding velocities at the step's start: its pull
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    dJ[k] = Vec3<T>{};
    vt0[k] = vt1[k] = T{};
    Vec3<T> n;
    if (!normal(k, n)) continue;
    const ContactState<T> c = load(k);
    if (!(c.j_n > T{}) && c.j_t == Vec3<T>{}) continue;
    const auto& w = trow(k);
    T vt[2];
    tangent_velocity<kStill>(A, B, w, vt);  // eqs 48, 56, 129
    vt0[k] = vt[0];
    vt1[k] = vt[1];
    Vec3<T> j_t = c.j_t;
    dJ[k] = accumulate_friction_impulse(j_t, vt, w, inv_split, c.mu, c.j_n);  // eqs 95, 99, 129
  }
  cached = false;
  if (count > 1) {
    const T alpha = friction_manifold_step<N, kStill>(A, B, trow, dJ.data(), vt0.data(), vt1.data(), end,
                                              kCache ? delta.data() : nullptr, formed);  // eqs 99, 129
    if (alpha < one) {
      if (alpha < half) ++counts.shortened_steps;  // eq 113: less than half the proposals' change
      for (int k = 0; k < end; ++k) dJ[k] = dJ[k] * alpha;
    } else {
      cached = kCache;
    }
  }
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    if (dJ[k] == Vec3<T>{}) continue;
    ContactState<T> c = load(k);
    c.j_t += dJ[k];
    store(k, c);
    if (cached && formed[k]) apply_delta<kStill>(A, B, delta[k]);                // eqs 61-62, 87, as the step formed it
    else apply_delta<kStill>(A, B, tangent_delta<kStill>(A, B, trow(k), dJ[k]));  // eqs 61-62, 87, 129
    ++counts.friction_steps;
  }
}

// A manifold visit whose rows (eqs 114, 128-129) are formed by the visit
// from its two sides (the GPU engine's visits; World<T> passes the rows it
// formed once per frame from the same sides: the same values).
template <int N, class T, class Point, class Load, class Store>
LS_HD void solve_manifold(BodyView<T>& A, BodyView<T>& B, const Point& point, const Load& load, const Store& store,
                          bool friction, bool gravity, const T& k_scale, const Params<T>& P, SolveCounts& counts) {
  auto row = [&](int k) {  // reads A's and B's mass, rotation and inertia, which the visit does not change
    Vec3<T> r1, r2, n;
    T penetration;
    point(k, r1, r2, n, penetration);
    return contact_rows(A, r1, B, r2, n, load(k).k_n);
  };
  solve_manifold_rows<N>(A, B, point, row, load, store, friction, gravity, k_scale, P, counts);
}

// The sequential visit (k_scale 1): World<T>'s, and the GPU engine's visits
// on one body's own velocity.
template <int N, class T, class Point, class Load, class Store>
LS_HD void solve_manifold(BodyView<T>& A, BodyView<T>& B, const Point& point, const Load& load, const Store& store,
                          bool friction, bool gravity, const Params<T>& P, SolveCounts& counts) {
  solve_manifold<N>(A, B, point, load, store, friction, gravity, Num<T>::from_int(1), P, counts);
}

// One solver visit of one contact (eqs 48-49, 53, 56, 87, 94-95, 97,
// 128-129): a manifold of one point (eq 99 with N = 1: no split, no step).
// A is body 1, B body 2, n points from B to A; A and B are updated in place.
// `k_scale` as solve_manifold's: 1 is World<T>'s sequential visit of a body
// pair; the GPU engine's Jacobi visits of body-body contacts pass the larger
// contact count of the two bodies (mass splitting, docs/GPU.md). With `rows`,
// the contact's rows formed before the solve (World<T>); without, formed here.
template <class T>
LS_HD void solve_contact(BodyView<T>& A, const Vec3<T>& r1, BodyView<T>& B, const Vec3<T>& r2, const Vec3<T>& n,
                         const T& penetration, ContactState<T>& c, bool friction, bool gravity, const T& k_scale,
                         const Params<T>& P, SolveCounts& counts, const ContactRows<T>* rows = nullptr) {
  auto point = [&](int, Vec3<T>& pr1, Vec3<T>& pr2, Vec3<T>& pn, T& pen) {
    pr1 = r1, pr2 = r2, pn = n, pen = penetration;
    return true;
  };
  auto load = [&](int) { return c; };
  auto store = [&](int, const ContactState<T>& st) { c = st; };
  if (rows != nullptr) {
    auto row = [&](int) -> const ContactRows<T>& { return *rows; };
    solve_manifold_rows<1>(A, B, point, row, load, store, friction, gravity, k_scale, P, counts);
  } else {
    solve_manifold<1>(A, B, point, load, store, friction, gravity, k_scale, P, counts);
  }
}

}  // namespace lockstep
