// Part 3 of docs/SPEC.md: impulses, friction and position correction, in the
// two-body forms (86)-(89) that the source gives for one body only.
#pragma once
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/integrate.hpp"

namespace lockstep {

// What a contact needs of one body. Ground, SDF volumes, static and
// sleeping-as-static bodies have inv_mass = 0 and inv_inertia = 0.
template <class T>
struct BodyView {
  Vec3<T> v, w;
  T inv_mass{};
  Mat3<T> R;
  Vec3<T> inv_inertia;  // body-frame diagonal, eq 18
};

// eq 48: v_rel = v1 + w1 x r1 - v2 - w2 x r2.
template <class T>
LS_HD_INLINE Vec3<T> relative_velocity(const BodyView<T>& a, const Vec3<T>& r1, const BodyView<T>& b, const Vec3<T>& r2) {
  return a.v + cross(a.w, r1) - b.v - cross(b.w, r2);
}

// eq 86 (two-body eq 52): k = m1^-1 + m2^-1 + (I1^-1 (r1 x d)).(r1 x d) + (I2^-1 (r2 x d)).(r2 x d);
// an inverse effective mass along direction d (n for eq 53, t for eq 88).
template <class T>
LS_HD_INLINE T inverse_effective_mass(const BodyView<T>& a, const Vec3<T>& r1, const BodyView<T>& b, const Vec3<T>& r2,
                               const Vec3<T>& d) {
  const Vec3<T> rd1 = cross(r1, d), rd2 = cross(r2, d);  // eq 51
  return a.inv_mass + b.inv_mass + dot(apply_inverse_inertia(a.R, a.inv_inertia, rd1), rd1) +
         dot(apply_inverse_inertia(b.R, b.inv_inertia, rd2), rd2);
}

// eq 50: e = min(e1, e2).
template <class T>
LS_HD T combined_restitution(const T& e1, const T& e2) { return Num<T>::min(e1, e2); }

// eq 76 (4.5): below the approach speed restitution_min_speed, a contact does not bounce.
template <class T>
LS_HD T low_speed_restitution(const T& e, const T& v_n, const T& restitution_min_speed) {
  return -v_n > restitution_min_speed ? e : T{};
}

// eq 53: j = -(1 + e) v_n / k, for an approaching contact (v_n < 0: the fix of 3.1).
template <class T>
LS_HD T normal_impulse(const T& e, const T& v_n, const T& k, const T& one) { return -(one + e) * v_n / k; }

// eq 94 (the iterated form of eq 53, Catto's accumulated impulses): each
// iteration drives the normal velocity v_n to the contact's target velocity:
// dj = (target - v_n) m, m the effective mass along n (1/k, eq 86; formed
// once per frame, eq 114), with the accumulated impulse kept >= 0:
// J' = max(J + dj, 0); the impulse applied is J' - J. For a touching contact
// the target is the bounce -e v_n0 (v_n0 <= 0, the approach speed at the start
// of the solve); one iteration on one contact from J = 0 is then eq 53.
template <class T>
LS_HD_INLINE T accumulate_normal_impulse(T& accumulated, const T& v_n, const T& target, const T& m) {
  const T dj = (target - v_n) * m;
  const T updated = Num<T>::max(accumulated + dj, T{});
  const T applied = updated - accumulated;
  accumulated = updated;
  return applied;
}

// eq 97: the target normal velocity of eq 94. Touching (penetration >= 0):
// the bounce -e v_n0. Speculative (a gap g = -penetration > 0 within
// contact_tolerance): the bodies may still approach by g this frame, so the
// target is -g / dt and no impulse acts unless they would pass through. A
// bouncing contact (e > 0) that closes its gap within this frame (-v_n0 dt > g)
// bounces now, so a gap never swallows a bounce, with the speed it would have
// after falling through the gap to the surface against g_n (the gravity
// pressing it on, 0 between two falling bodies), bouncing there with e, and
// rising back to the gap: u^2 = e^2 (v_n0^2 + 2 g_n g) - 2 g_n g
// = (e v_n0)^2 - 2 g_n g (1 - e^2), 0 if negative (e <= 1), so a bounce from a
// gap neither adds nor loses energy against one from the surface. Above
// 128 m/s the correction (< 0.001 m/s) is dropped, which keeps u^2 inside
// Q16.16.
template <class T>
LS_HD_INLINE T contact_target_velocity(const T& penetration, const T& e, const T& v_n0, const T& g_n, const T& dt,
                                const T& inv_dt) {
  if (!(penetration < T{})) return -(e * v_n0);
  const T gap = -penetration;
  if (!(e > T{}) || !(-(v_n0 * dt) > gap)) return penetration * inv_dt;
  const T ev = -(e * v_n0);
  const T one = Num<T>::from_int(1);
  const T rise = Num<T>::sqrt(Num<T>::max(g_n, T{}) * gap * Num<T>::from_int(2) * (one - e * e));
  if (!(ev > rise)) return T{};
  if (ev > Num<T>::from_int(128)) return ev;
  // u <= ev in real arithmetic; the min keeps it so against the rounding of a
  // small square (Q16: ev 621 raw, sqrt(ev * ev) 627 raw).
  return Num<T>::min(ev, Num<T>::sqrt((ev - rise) * (ev + rise)));
}

// eq 95 (the iterated form of eq 88): the friction impulse accumulated over
// the iterations, a vector in the contact plane, is clamped to the Coulomb
// cone |J_t| <= mu J_n (accumulate_friction_impulse, physics/solver.hpp,
// through the tangent rows of eq 129). The clamp: a friction impulse J
// scaled onto the cone |J| <= limit (limit = mu J_n), unchanged inside it.
template <class T>
LS_HD_INLINE Vec3<T> clamp_to_cone(const Vec3<T>& J, const T& limit) {
  if (!longer_than(J, limit)) return J;  // |J| <= limit (Q16: without the root)
  return J * (limit / length(J));
}

// eq 99: the step length of a manifold's Jacobi step. A body's points
// against one environment object are solved from the same velocities and
// their proposed impulses dJ_k applied together; their sum can overshoot (two
// corners at one end of a thin plate push its rotation twice as hard as one).
// With a = sum_k dJ_k . (target_k - v_k) (the residual's pull) and
// b = sum_k dJ_k . dv_k (dv_k: the velocity change at point k that all the
// dJ cause together; b = dJ^T K dJ >= 0), the kinetic energy along
// alpha dJ is minimal at alpha = a / b; the step is min(1, a / b), 0 when
// a <= 0 (nothing to gain; continuous at a = 0). A friction impulse above
// the cone is pulled back before the proposals (solve_manifold), whole. a and b may carry any common
// positive factor (the manifold divides dJ by its largest component first,
// which keeps them inside Q16.16).
template <class T>
LS_HD T manifold_step_length(const T& a, const T& b) {
  if (!(a > T{})) return T{};  // no descent along the proposals (continuous: a/b -> 0 as a -> 0+)
  if (!(b > a)) return Num<T>::from_int(1);
  return a / b;
}

// eq 87's four velocity changes for impulse J (at r1 on a, -J at r2 on b),
// before they are added: they depend on the bodies' masses, rotations and
// inertia only, so a manifold (eq 99) that has formed them once to measure
// its step applies the same values.
template <class T>
struct ImpulseDelta {
  Vec3<T> va, wa, vb, wb;
};
template <class T>
LS_HD_INLINE ImpulseDelta<T> impulse_delta(const BodyView<T>& a, const Vec3<T>& r1, const BodyView<T>& b,
                                           const Vec3<T>& r2, const Vec3<T>& J) {
  return {J * a.inv_mass, apply_inverse_inertia(a.R, a.inv_inertia, cross(r1, J)), J * b.inv_mass,
          apply_inverse_inertia(b.R, b.inv_inertia, cross(r2, J))};
}
// kStillB: b is a still side (kStillSide), whose changes are exact zeros: b is left as it is.
template <bool kStillB = false, class T>
LS_HD_INLINE void apply_delta(BodyView<T>& a, BodyView<T>& b, const ImpulseDelta<T>& d) {
  a.v += d.va;
  a.w += d.wa;
  if constexpr (!kStillB) {
    b.v -= d.vb;
    b.w -= d.wb;
  }
}

// eq 87 (two-body eqs 54-55 and 61-62): impulse J on body a at r1, -J on b at r2.
template <class T>
LS_HD_INLINE void apply_impulse(BodyView<T>& a, const Vec3<T>& r1, BodyView<T>& b, const Vec3<T>& r2, const Vec3<T>& J) {
  apply_delta(a, b, impulse_delta(a, r1, b, r2, J));
}

// eq 56: v_tan = v_rel - (v_rel.n) n.
template <class T>
LS_HD_INLINE Vec3<T> tangential_velocity(const Vec3<T>& v_rel, const Vec3<T>& n) { return v_rel - n * dot(v_rel, n); }

// eq 58: mu = sqrt(mu1 mu2).
template <class T>
LS_HD T combined_friction(const T& mu1, const T& mu2) { return Num<T>::sqrt(mu1 * mu2); }

// eq 88 (the fix of eq 59): j_t = min(|v_tan| / k_t, mu j), k_t from eq 86 along t.
template <class T>
LS_HD T friction_impulse(const T& v_tan_mag, const T& k_t, const T& mu, const T& j) {
  return Num<T>::min(v_tan_mag / k_t, mu * j);
}

// eq 89 (two-body eq 63): c = max(0, pen - slop) * percent; body a moves by
// +n c m1^-1 / (m1^-1 + m2^-1) and body b by -n c m2^-1 / (m1^-1 + m2^-1).
// The caller skips contacts whose total inverse mass is 0.
template <class T>
LS_HD void baumgarte_correction(Vec3<T>& pa, Vec3<T>& pb, const Vec3<T>& n, const T& penetration,
                                const T& inv_mass_a, const T& inv_mass_b, const T& slop, const T& percent) {
  const T c = Num<T>::max(T{}, penetration - slop) * percent;
  if (!(c > T{})) return;
  const T total = inv_mass_a + inv_mass_b;
  pa += n * (c * (inv_mass_a / total));
  pb -= n * (c * (inv_mass_b / total));
}

// eq 110 for one box-box pair of the oriented-box model: its correction by
// `depth` (the mean depth of its points) less what this stage has already
// moved the two sides apart along n (pa0, pb0: their positions before the
// stage), by eq 89 (pa, pb updated). A support pair (`support_pair`: |n.y| >=
// support_normal_min) moves only its upper side (n points from b to a: a is
// upper when n.y > 0), unless that side cannot move. The caller skips pairs
// whose total inverse mass is 0 and bouncing ones (eq 76).
template <class T>
LS_HD void manifold_correction(Vec3<T>& pa, const Vec3<T>& pa0, Vec3<T>& pb, const Vec3<T>& pb0, const Vec3<T>& n,
                               const T& depth, T inv_a, T inv_b, bool support_pair, const T& slop, const T& percent) {
  if (support_pair) {
    if (n.y > T{} ? inv_a > T{} : inv_b > T{}) (n.y > T{} ? inv_b : inv_a) = T{};
  }
  Vec3<T> moved = pa - pa0;
  moved -= pb - pb0;
  baumgarte_correction(pa, pb, n, depth - dot(moved, n), inv_a, inv_b, slop, percent);  // eqs 63, 89
}

// eq 110: a support pair (|n.y| >= support_normal_min) moves only its upper side.
template <class T>
LS_HD bool is_support_pair(const Vec3<T>& n, const T& support_normal_min) {
  return Num<T>::abs(n.y) >= support_normal_min;
}

// eq 110: the depth by which a box-box pair is corrected, the mean of its
// points' penetrations (a tilted box resting on one corner is not lifted by
// that corner); 0 with no points.
template <class T>
LS_HD T mean_depth(const T* penetration, int count) {
  if (count <= 0) return T{};
  T sum{};
  for (int k = 0; k < count; ++k) sum += penetration[k];
  return sum / Num<T>::from_int(count);
}

// eqs 89, 110: the point of a manifold that carries its correction: the
// deepest, the first on ties (0 with no points).
template <class T>
LS_HD int deepest_point(const T* penetration, int count) {
  int deepest = 0;
  for (int k = 1; k < count; ++k)
    if (penetration[k] > penetration[deepest]) deepest = k;
  return deepest;
}

// eq 89's ground tie rule: the ground point of a body that carries its
// correction is the deepest, the first on ties but a resting one before a
// bouncing one (which tied corner is "first" depends on the corner
// numbering, which a mirror image permutes; this keeps the choice
// sign-symmetric); -1 when there is none. point(k, depth) -> false: k is no
// contact; bounces(k): its e_eff > 0 (eq 76); best_depth: the chosen one's
// depth. A bouncing choice is not corrected.
template <class T, class Point, class Bounces>
LS_HD int ground_correction_point(int count, Point&& point, Bounces&& bounces, T& best_depth) {
  int best = -1;
  best_depth = T{};
  for (int k = 0; k < count; ++k) {
    T depth{};
    if (!point(k, depth)) continue;
    if (best < 0 || depth > best_depth || (depth == best_depth && bounces(best) && !bounces(k))) {
      best = k;
      best_depth = depth;
    }
  }
  return best;
}

// eq 111 (as eq 110): a support pair moves only its upper side (n points from
// b to a: a is upper when n.y > 0), if that side can move: the lower side's
// view is made immovable.
template <class T>
LS_HD void hold_lower_side(BodyView<T>& a, BodyView<T>& b, const Vec3<T>& n, const T& support_normal_min) {
  if (!is_support_pair(n, support_normal_min)) return;
  BodyView<T>& upper = n.y > T{} ? a : b;
  BodyView<T>& lower = n.y > T{} ? b : a;
  if (upper.inv_mass > T{}) {
    lower.inv_mass = T{};
    lower.inv_inertia = Vec3<T>{};
  }
}

// eq 111: one point of a body pair's manifold pushed out of its residual
// penetration, by translating and turning the two sides (non-linear
// Gauss-Seidel on positions). `a.v`, `a.w` (and b's) hold the displacement
// (m) and the small turn (rad) this stage has given each side so far, so
// `penetration - n.(relative displacement at the point)` is the point's depth
// now (first order); what exceeds `slop` is removed (times `percent`) by the
// position impulse `c/k` along n (eq 86's k), applied as eq 87 applies an
// impulse. A side that must not move has inv_mass 0 and inv_inertia 0.
template <class T>
LS_HD void correct_manifold_point(BodyView<T>& a, const Vec3<T>& r1, BodyView<T>& b, const Vec3<T>& r2, const Vec3<T>& n,
                                  const T& penetration, const T& slop, const T& percent) {
  const T now = penetration - dot(relative_velocity(a, r1, b, r2), n);
  const T c = (now - slop) * percent;
  if (!(c > T{})) return;
  const T k = inverse_effective_mass(a, r1, b, r2, n);  // eq 86
  if (!(k > T{})) return;
  apply_impulse(a, r1, b, r2, n * (c / k));  // eq 87, on positions
}

}  // namespace lockstep
