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

// eq 114: the normal row of a contact point (A at r1, B at r2, n from B to
// A): the moments r1 x n and r2 x n and their images under the sides' world
// inverse inertia (eq 90), I1^-1 (r1 x n) and I2^-1 (r2 x n). They depend on
// the point and on the sides' rotations and inertia, which the solve does not
// change: World<T> forms them once per frame and every pass reads them; the
// GPU engine forms them where it needs them (the same values).
template <class T>
struct NormalRow {
  Vec3<T> rn1, rn2;  // r1 x n, r2 x n (m)
  Vec3<T> an1, an2;  // I1^-1 (r1 x n), I2^-1 (r2 x n) (1/(kg m))
};
template <class T>
LS_HD_INLINE NormalRow<T> normal_row(const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B, const Vec3<T>& r2,
                                     const Vec3<T>& n) {
  const Vec3<T> rn1 = cross(r1, n), rn2 = cross(r2, n);  // eq 51
  return {rn1, rn2, apply_inverse_inertia(A.R, A.inv_inertia, rn1), apply_inverse_inertia(B.R, B.inv_inertia, rn2)};
}
// eqs 48-49 along n through the row (eq 114): v_n = (v1 - v2).n + w1.(r1 x n) - w2.(r2 x n).
template <class T>
LS_HD_INLINE T normal_velocity(const BodyView<T>& A, const BodyView<T>& B, const NormalRow<T>& row, const Vec3<T>& n) {
  return dot(A.v - B.v, n) + dot(A.w, row.rn1) - dot(B.w, row.rn2);
}
// Eq 87's velocity changes for the impulse J = n j through the row (eq 114):
// n (j m1^-1), I1^-1 (r1 x n) j on A and the same of B (taken off B).
template <class T>
LS_HD_INLINE ImpulseDelta<T> normal_delta(const BodyView<T>& A, const BodyView<T>& B, const NormalRow<T>& row,
                                          const Vec3<T>& n, const T& j) {
  return {n * (j * A.inv_mass), row.an1 * j, n * (j * B.inv_mass), row.an2 * j};
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
template <class T>
LS_HD void warm_start_contact(BodyView<T>& A, const Vec3<T>& r1, BodyView<T>& B, const Vec3<T>& r2, const Vec3<T>& n,
                              ContactState<T>& c, const T& cached_j_n, const Params<T>& P) {
  if (!(c.k_n > T{}) || c.v_n0 > P.restitution_min_speed) return;
  c.j_n = cached_j_n;
  apply_impulse(A, r1, B, r2, n * c.j_n);  // eq 87
}

// Eq 97's g_n: gravity presses a body onto an immovable side B; two falling
// bodies feel none. B's mobility does not change during the solve.
template <class T>
LS_HD_INLINE T gravity_pressing(const BodyView<T>& B, const Vec3<T>& n, bool gravity, const Params<T>& P) {
  return (gravity && B.inv_mass == T{}) ? -dot(P.gravity, n) : T{};
}

// One solver visit of one contact (eqs 48-49, 53, 56-57, 60, 87-88, 94-95,
// 97). A is body 1, B body 2, n points from B to A; A and B are updated in
// place. `k_scale` multiplies the effective masses k_n and k_t: 1 is
// World<T>'s sequential visit of a body pair; the GPU engine's Jacobi visits
// of body-body contacts pass the larger contact count of the two bodies (mass
// splitting, docs/GPU.md).
template <class T>
LS_HD void solve_contact(BodyView<T>& A, const Vec3<T>& r1, BodyView<T>& B, const Vec3<T>& r2, const Vec3<T>& n,
                         const T& penetration, ContactState<T>& c, bool friction, bool gravity, const T& k_scale,
                         const Params<T>& P, SolveCounts& counts) {
  if (!(c.k_n > T{})) return;  // both sides immovable
  ++counts.solver_contacts;
  const NormalRow<T> row = normal_row(A, r1, B, r2, n);  // eq 114, as a manifold's point
  const T v_n = normal_velocity(A, B, row, n);            // eqs 48-49
  // Only approaching contacts bounce (the fix of 3.1): the target -e v_n0 uses v_n0 <= 0.
  const T target = contact_target_velocity(penetration, c.e, Num<T>::min(c.v_n0, T{}), gravity_pressing(B, n, gravity, P),
                                           P.dt, P.inv_dt);  // eq 97
  const T dj = accumulate_normal_impulse(c.j_n, v_n, target, c.k_n * k_scale);  // eqs 53, 94
  if (dj != T{}) {
    apply_delta(A, B, normal_delta(A, B, row, n, dj));  // eqs 87, 114
    ++counts.normal_impulses;
  }
  // Friction (eqs 56-62, 88, 95); also re-clamps a friction impulse left
  // above mu J_n when J_n has since dropped.
  if (friction && (c.j_n > T{} || !(c.j_t == Vec3<T>{}))) {
    const Vec3<T> v_tan = tangential_velocity(relative_velocity(A, r1, B, r2), n);  // eq 56
    const bool sliding = length(v_tan) > T{};                                       // eq 57
    const T k_t = sliding ? inverse_effective_mass(A, r1, B, r2, normalize(v_tan)) : Num<T>::from_int(1);  // eqs 60, 88
    const Vec3<T> dJ = accumulate_friction_impulse(c.j_t, v_tan, k_t * k_scale, c.mu, c.j_n);  // eq 95
    if (!(dJ == Vec3<T>{})) {
      apply_impulse(A, r1, B, r2, dJ);  // eqs 61-62, 87
      ++counts.friction_steps;
    }
  }
}

// Eq 99's step length for a manifold's normal proposals dj_k (eq 114's rows):
// with R = max_k |dj_k| and w_k = dj_k / R, a = sum_k w_k res_k (res_k =
// target_k - v_n,k) and b = sum_k w_k (n_k . dv_k), dv_k the velocity change
// at point k that all the proposals cause together (the normal velocity of
// the sides at rest after them). `deltas` and `formed` as manifold_step's.
template <int N, class T, class Point, class Row>
LS_HD_INLINE T normal_manifold_step(const BodyView<T>& A, const BodyView<T>& B, const Point& point, const Row& row,
                                    const T* dj, const T* res, int end, ImpulseDelta<T>* deltas, bool* formed) {
  BodyView<T> Z = A, Zb = B;  // the sides at rest: they gather the proposals' velocity change
  Z.v = Z.w = Zb.v = Zb.w = Vec3<T>{};
  T reach{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    if (formed != nullptr) formed[k] = false;
    Vec3<T> r1, r2, n;
    T penetration;
    if (dj[k] == T{} || !point(k, r1, r2, n, penetration)) continue;
    const ImpulseDelta<T> dl = normal_delta(Z, Zb, row(k), n, dj[k]);
    apply_delta(Z, Zb, dl);
    if (deltas != nullptr) { deltas[k] = dl; formed[k] = true; }
    reach = Num<T>::max(reach, Num<T>::abs(dj[k]));
  }
  if (!(reach > T{})) return Num<T>::from_int(1);
  T a{}, b{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    Vec3<T> r1, r2, n;
    T penetration;
    if (dj[k] == T{} || !point(k, r1, r2, n, penetration)) continue;
    const T w = dj[k] / reach;  // in [-1, 1]
    a += w * res[k];
    b += w * normal_velocity(Z, Zb, row(k), n);
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

// Host builds keep what a manifold visit has formed once and would form again:
// its points and their solver states (read once per visit), eq 87's velocity
// changes of each point's impulse (measured by manifold_step, then applied
// when the step is 1), each point's impulse, and the friction step's relative
// velocities (eq 48, the pull of its eq 99 step). The same values, so the
// same bits; device builds form them again (fewer registers).
#if defined(__CUDA_ARCH__)
inline constexpr bool kManifoldCache = false;
#else
inline constexpr bool kManifoldCache = true;
#endif

// A manifold visit's scratch of M values of V, each written before it is
// read. Host builds leave it unfilled: the zero fill of the visit's 2.7 KB of
// scratch (Vec3's and Q16's members start at 0) was 5 % of the solve. V, an
// aggregate of trivially copyable numbers, is an implicit-lifetime type, so
// the storage holds a V once one is assigned to it (C++20 [intro.object]).
// Device builds and number types that are not trivially copyable (mp): a
// plain array.
template <class V, int M, bool kUnfilled = kManifoldCache && std::is_trivially_copyable_v<V>>
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

// Eq 99's step length for the impulses that a manifold's points propose
// together: `impulse(k, n)` is point k's proposed impulse (0: none) and
// `pull(k, r1, r2, n)` the velocity change it asks for, both in world axes;
// `A`, `B` the two sides (only their masses and inertia are used); points
// k >= `end` are not contacts.
// With R the largest component of any impulse (a common scale that keeps the
// sums inside Q16.16), a = sum_k (J_k / R) . pull_k and b = sum_k (J_k / R) . dv_k,
// dv_k being the velocity change at point k that all impulses cause together.
// With `deltas` (and `formed`), point k's eq 87 velocity changes are kept in
// deltas[k] and formed[k] tells whether they were formed (a non-zero
// impulse); with `impulses`, point k's impulse is kept in impulses[k] (read
// only where formed[k]).
template <int N, class T, class Point, class Impulse, class Pull>
LS_HD_INLINE T manifold_step(const BodyView<T>& A, const BodyView<T>& B, const Point& point, const Impulse& impulse,
                      const Pull& pull, ImpulseDelta<T>* deltas = nullptr, bool* formed = nullptr,
                      Vec3<T>* impulses = nullptr, int end = N) {
  BodyView<T> Z = A, Zb = B;  // the sides at rest: they gather the impulses' velocity change
  Z.v = Z.w = Zb.v = Zb.w = Vec3<T>{};
  T reach{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    if (formed != nullptr) formed[k] = false;
    Vec3<T> r1, r2, n;
    T penetration;
    if (!point(k, r1, r2, n, penetration)) continue;
    const Vec3<T> J = impulse(k, n);
    if (J == Vec3<T>{}) continue;
    const ImpulseDelta<T> dl = impulse_delta(Z, r1, Zb, r2, J);  // Z, Zb: A's and B's masses and inertia
    apply_delta(Z, Zb, dl);
    if (deltas != nullptr) { deltas[k] = dl; formed[k] = true; }
    if (impulses != nullptr) impulses[k] = J;
    reach = Num<T>::max(reach, max_abs(J));
  }
  if (!(reach > T{})) return Num<T>::from_int(1);
  T a{}, b{};
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    Vec3<T> r1, r2, n;
    T penetration;
    Vec3<T> J;
    if (impulses != nullptr) {  // kept by the loop above: formed[k] is whether it is a contact with an impulse
      if (!formed[k]) continue;
      point(k, r1, r2, n, penetration);
      J = impulses[k];
    } else {
      if (!point(k, r1, r2, n, penetration)) continue;
      J = impulse(k, n);
      if (J == Vec3<T>{}) continue;
    }
    const Vec3<T> w{J.x / reach, J.y / reach, J.z / reach};  // in [-1, 1]
    a += dot(w, pull(k, r1, r2, n));
    b += dot(w, relative_velocity(Z, r1, Zb, r2));
  }
  return manifold_step_length(a, b);
}

// One solver visit of a manifold (eq 99): a body A's contacts with one
// immovable environment object B (its ground corners, its samples of one SDF
// volume; r2 = 0), or the points of a body pair's box-box manifold (eq 105; B
// the other body, r2 its lever arms), solved Jacobi-style so that a
// symmetric landing stays symmetric. Normal step: every point's impulse is proposed from the
// velocities at the start of the visit (eqs 53, 94, 97), with each point's
// effective mass scaled by split = max(1, o), o = sum_k m^-1 / k_n,k (the
// points share one body, so their simultaneous impulses add up: o is 1 for a
// unit cube's 4 bottom corners, 2 for 8 sunken corners, 3.8 for a tall thin
// box standing); the proposals are scaled by the step length alpha of eq 99
// (manifold_step_length), which stops the sum from overshooting through the
// rotation (two corners at one end of a thin plate) and so from adding
// energy; then all are applied. Friction step: the same, from the velocities
// after the normal step (eqs 56-62, 88, 95).
// `point(k, r1, r2, n, penetration)` gives point k (k = 0..N-1; false: not a
// contact), `row(k)` its normal row (eq 114: normal_row of the visit's two
// sides; the normal step reads the point's velocity along n and applies its
// impulse through it); `load(k)` and `store(k, state)` read and write its
// solver state.
// The visit is skipped when the first point's k_n is 0 (both sides
// immovable).
// `k_scale` multiplies every point's effective masses on top of eq 99's
// split: 1 is World<T>'s sequential visit; the GPU engine's Jacobi visits of
// a pair of active bodies pass their mass splitting (docs/GPU.md), as
// solve_contact's k_scale.
// `split_given`: the visit's manifold_split, formed before the solve (World<T>,
// once per frame); nullptr: formed here from the points (the same value).
template <int N, class T, class Point, class Row, class Load, class Store>
LS_HD void solve_manifold_rows(BodyView<T>& A, BodyView<T>& B, const Point& point_at, const Row& row_at,
                               const Load& load_at, const Store& store_at, bool friction, bool gravity,
                               const T& k_scale, const Params<T>& P, SolveCounts& counts,
                               const T* split_given = nullptr) {
  const T one = Num<T>::from_int(1);
  const T half = Num<T>::from_double(0.5);  // eq 113: a step shortened below it is partial progress
  constexpr int M = kManifoldCache ? N : 1;
  // kManifoldCache: the points and states, read once (the first loop below).
  Scratch<Vec3<T>, M> pr1, pr2, pn;
  Scratch<T, M> ppen;
  Scratch<ContactState<T>, M> pst;
  Scratch<NormalRow<T>, M> prow;
  bool pok[M];
  auto point = [&](int k, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
    if constexpr (kManifoldCache) {
      if (!pok[k]) return false;
      r1 = pr1[k], r2 = pr2[k], n = pn[k], penetration = ppen[k];
      return true;
    } else {
      return point_at(k, r1, r2, n, penetration);
    }
  };
  auto row = [&](int k) -> std::conditional_t<kManifoldCache, const NormalRow<T>&, NormalRow<T>> {
    if constexpr (kManifoldCache) return prow[k];
    else return row_at(k);
  };
  auto load = [&](int k) -> std::conditional_t<kManifoldCache, const ContactState<T>&, ContactState<T>> {
    if constexpr (kManifoldCache) return pst[k];
    else return load_at(k);
  };
  auto store = [&](int k, const ContactState<T>& st) {
    if constexpr (kManifoldCache) pst[k] = st;
    store_at(k, st);
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
      if constexpr (kManifoldCache) {
        pok[k] = ok;
        if (ok) pr1[k] = r1, pr2[k] = r2, pn[k] = n, ppen[k] = penetration, pst[k] = load_at(k), prow[k] = row_at(k);
      }
      if (!ok) continue;
      const T k_n = load(k).k_n;
      if (count == 0 && !(k_n > T{})) return;  // both sides immovable
      ++count;
      end = k + 1;
      if (split_given == nullptr) o += split_share(A.inv_mass, B.inv_mass, k_n);
    }
    if (count == 0) return;
    split = split_given != nullptr ? *split_given : manifold_split(o, count);
    if (!(k_scale == one)) split = split * k_scale;
  }
  Scratch<T, N> dj, res;
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    dj[k] = res[k] = T{};
    Vec3<T> r1, r2, n;
    T penetration;
    if (!point(k, r1, r2, n, penetration)) continue;
    const ContactState<T>& c = load(k);
    ++counts.solver_contacts;
    const T v_n = normal_velocity(A, B, row(k), n);  // eqs 48-49 (eq 114), at the visit's start
    // Only approaching contacts bounce (the fix of 3.1): the target -e v_n0 uses v_n0 <= 0.
    const T target = contact_target_velocity(penetration, c.e, Num<T>::min(c.v_n0, T{}),
                                             gravity_pressing(B, n, gravity, P), P.dt, P.inv_dt);  // eq 97
    T j_n = c.j_n;
    dj[k] = accumulate_normal_impulse(j_n, v_n, target, c.k_n * split);  // eqs 53, 94, 99
    res[k] = target - v_n;
  }
  // kManifoldCache: eq 87's velocity changes as manifold_step formed them,
  // applied as they are when the step is 1 (the impulses unchanged).
  Scratch<ImpulseDelta<T>, M> delta;
  bool formed[M];
  Scratch<Vec3<T>, M> impulse;
  bool cached = false;
  if (count > 1) {
    const T alpha = normal_manifold_step<N>(A, B, point, row, dj.data(), res.data(), end,
                                            kManifoldCache ? delta.data() : nullptr,
                                            kManifoldCache ? formed : nullptr);  // eqs 99, 114
    if (alpha < one) {
      if (alpha < half) ++counts.shortened_steps;  // eq 113: less than half the proposals' change
      for (int k = 0; k < end; ++k) dj[k] = dj[k] * alpha;
    } else {
      cached = kManifoldCache;
    }
  }
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    Vec3<T> r1, r2, n;
    T penetration;
    if (dj[k] == T{} || !point(k, r1, r2, n, penetration)) continue;
    ContactState<T> c = load(k);
    c.j_n += dj[k];  // eq 94: stays >= 0, alpha <= 1
    store(k, c);
    if (cached && formed[k]) apply_delta(A, B, delta[k]);  // eq 87, as formed by normal_manifold_step
    else apply_delta(A, B, normal_delta(A, B, row(k), n, dj[k]));  // eqs 87, 114
    ++counts.normal_impulses;
  }
  if (!friction) return;
  // Friction (eqs 56-62, 88, 95). Of a manifold (eq 99), first the cone: a
  // friction impulse left above mu J_n when J_n has since dropped is pulled
  // back onto the cone, whole (a projection, not a step to be shortened: with
  // it inside the proposals, a step length that tends to 0 as a tends to 0+
  // and jumps to 1 at a <= 0 left friction above the cone in one engine and
  // not in another). A single point does both in eq 95's one step.
  if (count > 1) {
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
    for (int k = 0; k < end; ++k) {
      Vec3<T> r1, r2, n;
      T penetration;
      if (!point(k, r1, r2, n, penetration)) continue;
      ContactState<T> c = load(k);
      if (c.j_t == Vec3<T>{}) continue;
      const Vec3<T> inside = clamp_to_cone(c.j_t, c.mu * c.j_n);  // eq 95's clamp
      if (inside == c.j_t) continue;
      const Vec3<T> back = inside - c.j_t;
      c.j_t = inside;
      store(k, c);
      apply_impulse(A, r1, B, r2, back);  // eqs 61-62, 87
      ++counts.friction_steps;
    }
  }
  const BodyView<T> A1 = A, B1 = B;
  Scratch<Vec3<T>, N> dJ;
  Scratch<Vec3<T>, M> vrel;  // kManifoldCache: eq 48 at each point, for the step's pull
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    dJ[k] = Vec3<T>{};
    Vec3<T> r1, r2, n;
    T penetration;
    if (!point(k, r1, r2, n, penetration)) continue;
    const ContactState<T>& c = load(k);
    if (!(c.j_n > T{}) && c.j_t == Vec3<T>{}) continue;
    const Vec3<T> vr = relative_velocity(A1, r1, B1, r2);  // eq 48
    if constexpr (kManifoldCache) vrel[k] = vr;
    const Vec3<T> v_tan = tangential_velocity(vr, n);  // eq 56
    Vec3<T> t;
    const bool sliding = direction_of(v_tan, t);                                   // eq 57: |v_tan| > 0, t = v_tan / |v_tan|
    const T k_t = sliding ? inverse_effective_mass(A1, r1, B1, r2, t) * split : one;  // eqs 60, 88, 99
    Vec3<T> j_t = c.j_t;
    dJ[k] = accumulate_friction_impulse(j_t, v_tan, k_t, c.mu, c.j_n);  // eq 95
  }
  cached = false;
  if (count > 1) {
    const T alpha = manifold_step<N>(
        A1, B1, point, [&](int k, const Vec3<T>&) { return dJ[k]; },
        [&](int k, const Vec3<T>& r1, const Vec3<T>& r2, const Vec3<T>&) {
          if constexpr (kManifoldCache) return -vrel[k];  // pull is only asked of a point with an impulse
          else return -relative_velocity(A1, r1, B1, r2);
        },  // eq 99
        kManifoldCache ? delta.data() : nullptr, kManifoldCache ? formed : nullptr,
        kManifoldCache ? impulse.data() : nullptr,
        end);
    if (alpha < one) {
      if (alpha < half) ++counts.shortened_steps;  // eq 113: less than half the proposals' change
      for (int k = 0; k < end; ++k) dJ[k] = dJ[k] * alpha;
    } else {
      cached = kManifoldCache;
    }
  }
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < end; ++k) {
    Vec3<T> r1, r2, n;
    T penetration;
    if (dJ[k] == Vec3<T>{} || !point(k, r1, r2, n, penetration)) continue;
    ContactState<T> c = load(k);
    c.j_t += dJ[k];
    store(k, c);
    if (cached && formed[k]) apply_delta(A, B, delta[k]);  // eqs 61-62, 87, as formed by manifold_step
    else apply_impulse(A, r1, B, r2, dJ[k]);                // eqs 61-62, 87
    ++counts.friction_steps;
  }
}

// A manifold visit whose rows (eq 114) are formed on the spot from the
// visit's two sides (the GPU engine's visits; World<T> passes the rows it
// formed once per frame from the same sides: the same values).
template <int N, class T, class Point, class Load, class Store>
LS_HD void solve_manifold(BodyView<T>& A, BodyView<T>& B, const Point& point, const Load& load, const Store& store,
                          bool friction, bool gravity, const T& k_scale, const Params<T>& P, SolveCounts& counts) {
  auto row = [&](int k) {  // reads A's and B's mass, rotation and inertia, which the visit does not change
    Vec3<T> r1, r2, n;
    T penetration;
    point(k, r1, r2, n, penetration);
    return normal_row(A, r1, B, r2, n);
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

}  // namespace lockstep
