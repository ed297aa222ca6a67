// Per-element functions of the GPU engine, host and device (LS_HD), templated
// on the number type like the reference's per-equation functions that they
// call. Each is the body of one of World<T>'s per-body or per-contact loops
// (reference/src/*.hpp), written as a function of one element so that a CUDA
// kernel and the host build's loop call the same code: the GPU engine differs
// from World<T> in scheduling, not in formulas.
#pragma once
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/physics/sdf.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/physics/sleep.hpp"

namespace lockstep::gpu {

template <class T>
LS_HD Mat3<T> identity3() {
  const T one = Num<T>::from_int(1);
  return {{{one, T{}, T{}}, {T{}, one, T{}}, {T{}, T{}, one}}};
}

// The contact-side view of an immovable side (ground, SDF volume, static or
// sleeping body): World<T>'s solver::view_of for those cases.
template <class T>
LS_HD BodyView<T> immovable_view() {
  BodyView<T> v;
  v.R = identity3<T>();
  return v;
}

// The contact-side view of an awake body.
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

// Stage 1 (eqs 1, 5, 6, 13) for one awake body.
template <class T>
LS_HD void integrate_velocity(Vec3<T>& v, Vec3<T>& w, bool gravity, bool damping, const Params<T>& P) {
  if (gravity) v = apply_gravity(v, P.gravity_dt);
  if (damping) {
    v = apply_damping(v, P.linear_damping_factor);
    w = apply_damping(w, P.angular_damping_factor);
  }
}

// What the solver counts (docs/SPEC.md 7.6).
struct SolveCounts {
  unsigned solver_contacts = 0, normal_impulses = 0, restitution_bounces = 0, friction_steps = 0;
};

// A contact's solver state (eqs 94-96): accumulated impulses and the values
// fixed when the solve starts.
template <class T>
struct ContactState {
  T j_n{};       // accumulated normal impulse (eq 94), >= 0
  Vec3<T> j_t{};  // accumulated friction impulse (eq 95)
  T v_n0{};      // approach speed before the solve (eq 49)
  T e{};         // restitution after eqs 50, 76
  T mu{};        // friction (eq 58)
  T k_n{};       // inverse effective mass along n (eq 86); 0: both sides immovable
};

// World<T>::solve_contacts' preparation of one contact (eqs 48-50, 58, 76,
// 86) with the velocities before the warm start.
template <class T>
LS_HD ContactState<T> prepare_contact(const BodyView<T>& A, const Vec3<T>& r1, const BodyView<T>& B, const Vec3<T>& r2,
                                      const Vec3<T>& n, const T& e1, const T& mu1, const T& e2, const T& mu2,
                                      bool restitution, bool friction, const Params<T>& P, SolveCounts& counts) {
  ContactState<T> c;
  c.v_n0 = dot(relative_velocity(A, r1, B, r2), n);  // eqs 48-49
  c.e = restitution ? low_speed_restitution(combined_restitution(e1, e2), c.v_n0, P.restitution_min_speed) : T{};  // eqs 50, 76
  if (c.e > T{}) ++counts.restitution_bounces;
  c.mu = friction ? combined_friction(mu1, mu2) : T{};  // eq 58
  c.k_n = inverse_effective_mass(A, r1, B, r2, n);       // eq 86
  return c;
}

// Eq 96: the warm start of one contact from last frame's accumulated normal
// impulse j_n of the same contact, applied to A and B. Friction starts from
// zero (World<T>: a warm-started friction impulse on a resting manifold kept
// re-injecting spin about the normal).
template <class T>
LS_HD void warm_start_contact(BodyView<T>& A, const Vec3<T>& r1, BodyView<T>& B, const Vec3<T>& r2, const Vec3<T>& n,
                              ContactState<T>& c, const T& cached_j_n) {
  if (!(c.k_n > T{})) return;
  c.j_n = cached_j_n;
  apply_impulse(A, r1, B, r2, n * c.j_n);
}

// Eq 97's g_n: gravity presses a body onto an immovable side B; two falling
// bodies feel none (World<T> sets it when the solve starts; B's mobility does
// not change during the solve).
template <class T>
LS_HD T gravity_pressing(const BodyView<T>& B, const Vec3<T>& n, bool gravity, const Params<T>& P) {
  return (gravity && B.inv_mass == T{}) ? -dot(P.gravity, n) : T{};
}

// One solver visit of one contact: the body of World<T>::solve_contacts'
// iteration loop (eqs 48-49, 53, 56-57, 60, 87-88, 94-95, 97). A is body 1,
// B body 2, n points from B to A; A and B are updated in place. `k_scale`
// multiplies the effective masses k_n and k_t: 1 is World<T>'s sequential
// visit; the GPU engine's Jacobi visits of body-body contacts pass the larger
// contact count of the two bodies (mass splitting, docs/GPU.md).
template <class T>
LS_HD void solve_contact(BodyView<T>& A, const Vec3<T>& r1, BodyView<T>& B, const Vec3<T>& r2, const Vec3<T>& n,
                         const T& penetration, ContactState<T>& c, bool friction, bool gravity, const T& k_scale,
                         const Params<T>& P, SolveCounts& counts) {
  if (!(c.k_n > T{})) return;  // both sides immovable
  ++counts.solver_contacts;
  const T v_n = dot(relative_velocity(A, r1, B, r2), n);  // eqs 48-49
  // Only approaching contacts bounce (the fix of 3.1): the target -e v_n0 uses v_n0 <= 0.
  const T target = contact_target_velocity(penetration, c.e, Num<T>::min(c.v_n0, T{}), gravity_pressing(B, n, gravity, P),
                                           P.dt, P.inv_dt);  // eq 97
  const T dj = accumulate_normal_impulse(c.j_n, v_n, target, c.k_n * k_scale);                 // eqs 53, 94
  if (dj != T{}) {
    apply_impulse(A, r1, B, r2, n * dj);  // eq 87
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

// One solver visit of a manifold (eq 99): a body's contacts with one
// environment object (its ground corners, its samples of one SDF volume),
// solved Jacobi-style as World<T>::solve_contacts does: every point's normal
// impulse is computed from the velocities at the start of the visit, then all
// are applied; then every point's friction impulse from the velocities after
// the normal impulses, then all are applied. `point(k, r1, n, penetration)`
// gives point k (k = 0..N-1; false: not a contact); `load(k)` and
// `store(k, state)` read and write its solver state. B is the immovable side
// (r2 = 0). World skips the manifold when its first point's k_n is 0 (both
// sides immovable).
template <int N, class T, class Point, class Load, class Store>
LS_HD void solve_manifold(BodyView<T>& A, BodyView<T>& B, const Point& point, const Load& load, const Store& store,
                          bool friction, bool gravity, const Params<T>& P, SolveCounts& counts) {
  const Vec3<T> r2{};
  bool first = true;
  T dj[N];
  // eq 99: with more than one point, each point's effective mass is scaled by
  // max(1, sum_k m^-1 / k_n,k), as World<T>::solve_contacts does.
  const T one = Num<T>::from_int(1);
  T split = one;
  {
    int count = 0;
    T o{};
    for (int k = 0; k < N; ++k) {
      Vec3<T> r1, n;
      T penetration;
      if (!point(k, r1, n, penetration)) continue;
      ++count;
      o += (A.inv_mass + B.inv_mass) / load(k).k_n;
    }
    if (count > 1 && o > one) split = o;
  }
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < N; ++k) {
    dj[k] = T{};
    Vec3<T> r1, n;
    T penetration;
    if (!point(k, r1, n, penetration)) continue;
    ContactState<T> c = load(k);
    if (first && !(c.k_n > T{})) return;
    first = false;
    ++counts.solver_contacts;
    const T v_n = dot(relative_velocity(A, r1, B, r2), n);  // eqs 48-49, at the visit's start
    const T target = contact_target_velocity(penetration, c.e, Num<T>::min(c.v_n0, T{}),
                                             gravity_pressing(B, n, gravity, P), P.dt, P.inv_dt);  // eq 97
    dj[k] = accumulate_normal_impulse(c.j_n, v_n, target, c.k_n * split);  // eqs 53, 94, 99
    store(k, c);
  }
  if (first) return;
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < N; ++k) {
    Vec3<T> r1, n;
    T penetration;
    if (dj[k] == T{} || !point(k, r1, n, penetration)) continue;
    apply_impulse(A, r1, B, r2, n * dj[k]);  // eq 87
    ++counts.normal_impulses;
  }
  if (!friction) return;
  const BodyView<T> A1 = A, B1 = B;
  Vec3<T> dJ[N];
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < N; ++k) {
    dJ[k] = Vec3<T>{};
    Vec3<T> r1, n;
    T penetration;
    if (!point(k, r1, n, penetration)) continue;
    ContactState<T> c = load(k);
    if (!(c.j_n > T{}) && c.j_t == Vec3<T>{}) continue;
    const Vec3<T> v_tan = tangential_velocity(relative_velocity(A1, r1, B1, r2), n);  // eq 56
    const bool sliding = length(v_tan) > T{};                                         // eq 57
    const T k_t = sliding ? inverse_effective_mass(A1, r1, B1, r2, normalize(v_tan)) * split : one;  // eqs 60, 88, 99
    dJ[k] = accumulate_friction_impulse(c.j_t, v_tan, k_t, c.mu, c.j_n);  // eq 95
    store(k, c);
  }
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < N; ++k) {
    Vec3<T> r1, n;
    T penetration;
    if (dJ[k] == Vec3<T>{} || !point(k, r1, n, penetration)) continue;
    apply_impulse(A, r1, B, r2, dJ[k]);  // eqs 61-62, 87
    ++counts.friction_steps;
  }
}

// Eq 84 for one corner: the ground contact depth of corner k (> 0: a contact).
template <class T>
LS_HD T ground_corner_depth(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& h, int k, const T& ground_y,
                            Vec3<T>& corner) {
  corner = box_corner(p, R, h, k);
  return ground_y - corner.y;
}

// A body-body contact (eqs 38-43, 85, 97) between bodies a < b: the overlap
// test runs on boxes grown by half the contact tolerance each, so pairs up to
// contact_tolerance apart are (speculative) contacts; the penetration is the
// grown overlap minus the tolerance, the point that of the ungrown boxes.
template <class T>
struct PairContact {
  bool hit = false;
  Vec3<T> n{};       // eqs 41-42: from b towards a
  T penetration{};   // eq 43 less the tolerance (negative: a gap)
  Vec3<T> point{};   // eq 85
};

template <class T>
LS_HD PairContact<T> pair_contact(const Vec3<T>& pa, const Vec3<T>& ha, const Vec3<T>& pb, const Vec3<T>& hb,
                                  const T& half_tol, const T& tol) {
  PairContact<T> c;
  const Vec3<T> grow{half_tol, half_tol, half_tol};
  const Overlap<T> o = aabb_overlap(pa, ha + grow, pb, hb + grow);  // eqs 38-43
  if (!o.hit) return c;
  c.hit = true;
  c.n = o.normal;
  c.penetration = o.penetration - tol;
  c.point = aabb_contact_point(pa, ha, pb, hb, Num<T>::from_double(0.5));  // eq 85
  return c;
}

// An SDF contact (eqs 32-37, 93, 97) of one sample point of a body.
template <class T>
struct SdfContact {
  bool hit = false;
  Vec3<T> n{}, point{};
  T penetration{};
};

// World<T>::narrow_phase's SDF sample s (0-7: corner s, radius 0; 8: the
// centre, radius min h): a contact when it lies inside the volume, closer
// than contact_tolerance to the surface, with a non-zero gradient.
template <class T>
LS_HD SdfContact<T> sdf_sample_contact(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& half, const SdfGrid<T>& g,
                                       int s, const T& tol) {
  SdfContact<T> out;
  const Vec3<T> pt = s < 8 ? box_corner(p, R, half, s) : p;
  const T radius = s < 8 ? T{} : Num<T>::min(half.x, Num<T>::min(half.y, half.z));
  if (!sdf_contains(g, pt)) return out;
  const T dist = sdf_distance(g, pt);  // eq 33
  const T pen = radius - dist;         // eq 35
  if (!(pen > -tol)) return out;       // eq 97
  const Vec3<T> grad = sdf_gradient(g, pt);  // eq 34
  if (length(grad) == T{}) return out;
  out.hit = true;
  out.n = normalize(grad);        // eq 36
  out.point = pt - out.n * dist;  // eq 37
  out.penetration = pen;
  return out;
}

// Stage 6 for one supported awake body, linear part: eq 75 against the
// support's velocity, then |v|, then eq 77. Returns |v| after eq 75 (the speed
// that righting uses).
template <class T>
LS_HD T settle_linear_velocity(Vec3<T>& v, const Vec3<T>& v_support, const Vec3<T>& n, const Params<T>& P) {
  v = cancel_resting_velocity(v, v_support, n, P.rest_speed);  // eq 75
  const T speed = length(v);
  v = settle_linear(v, speed, P);  // eq 77
  return speed;
}

// Stage 6, angular part: righting (64-71) and the damping regimes (72-74),
// "up" being the support contact's normal n.
template <class T>
LS_HD Vec3<T> settle_angular_velocity(const Vec3<T>& w, const Mat3<T>& R, const Vec3<T>& n, const T& speed,
                                      const Params<T>& P) {
  const Alignment<T> al = alignment_of(R, n);       // eqs 64-66 (65 fixed)
  const Vec3<T> w1 = righting(w, al, n, speed, P);  // eqs 67-71
  return regime_damping(w1, al.alignment, P);    // eqs 72-74
}

// Stage 9 (eqs 78-80) for one awake body; `up` is its support contact's
// normal, (0, 1, 0) when unsupported. Returns true when it falls asleep (v
// and w are then zeroed).
template <class T>
LS_HD bool update_sleep(Vec3<T>& v, Vec3<T>& w, int& counter, bool supported, const Mat3<T>& R, const Vec3<T>& up,
                        const Params<T>& P) {
  const T speed = length(v), spin = length(w);
  const Alignment<T> al = alignment_of(R, up);
  if (sleep_candidate(supported, speed, spin, al.alignment, P)) ++counter;  // eq 78
  else counter = 0;
  switch (sleep_stage(counter, P.drowsy_frames, P.sleep_frames)) {
    case SleepStage::kAsleep:  // eq 80
      v = Vec3<T>{};
      w = Vec3<T>{};
      return true;
    case SleepStage::kDrowsy:  // eq 79
      v = v * P.drowsy_damping;
      w = w * P.drowsy_damping;
      return false;
    case SleepStage::kAwake: break;
  }
  return false;
}

// Eq 81 for a body-body contact between an awake and a sleeping body: the
// velocity of a sleeping side counts as 0 (World<T>::wake_touched).
template <class T>
LS_HD bool wake_test(const Vec3<T>& va, bool a_asleep, const Vec3<T>& vb, bool b_asleep, const Vec3<T>& n,
                     const T& penetration, const Params<T>& P) {
  const Vec3<T> v_rel = (a_asleep ? Vec3<T>{} : va) - (b_asleep ? Vec3<T>{} : vb);
  return wakes(dot(v_rel, n), penetration, P);
}

// Stage 8 (eqs 2, 7-10) for one awake body.
template <class T>
LS_HD void integrate_pose(Vec3<T>& p, Quat<T>& q, const Vec3<T>& v, const Vec3<T>& w, const Params<T>& P) {
  p = integrate_position(p, v, P.dt);
  q = integrate_orientation(q, w, P.half_dt);
}

// Grid cells of the GPU broadphase: a 32-bit spatial hash of the integer cell
// coordinates (wrapping unsigned arithmetic), masked to the table size.
LS_HD inline unsigned cell_hash(int x, int y, int z) {
  return (static_cast<unsigned>(x) * 73856093u) ^ (static_cast<unsigned>(y) * 19349663u) ^
         (static_cast<unsigned>(z) * 83492791u);
}

}  // namespace lockstep::gpu
