// Per-body steps of the frame (docs/SPEC.md 7.2 stages 1, 6, 8, 9 and the
// wake test of stage 4), host and device (LS_HD), generic over the number
// type: World<T>'s per-body loops (reference/src/) and the GPU engine's
// kernels (gpu/src/*_stages.hpp) call these same functions, so the engines
// differ in scheduling, not in formulas.
#pragma once
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/physics/sleep.hpp"

namespace lockstep {

// Stage 1 (eqs 1, 5, 6, 13) for one awake body: gravity when `gravity`, then
// linear and angular damping when `damping`.
template <class T>
LS_HD void integrate_velocity(Vec3<T>& v, Vec3<T>& w, bool gravity, bool damping, const Params<T>& P) {
  if (gravity) v = apply_gravity(v, P.gravity_dt);  // eqs 1, 5
  if (damping) {
    v = apply_damping(v, P.linear_damping_factor);   // eq 6
    w = apply_damping(w, P.angular_damping_factor);  // eq 13
  }
}

// Stage 6 for one supported awake body, linear part: eq 75 against the
// support's velocity v_support (0 for an immovable support), then eq 77 on
// the velocity relative to it (`relative`, the oriented-box model) or on v
// (the source's AABB model). n is the body's support normal (98), gap its
// support gap (Part 4: 0 when a support contact touches). Returns the speed
// eq 77 judged, which righting (eqs 67-71) uses. `limit` (m/s): eq 77 damps
// only a relative speed not above it (eq 116: what friction could stop in
// the frame; settle_speed with the AABB model or where something holds the
// body; negative for a driven body, a slide down a ramp steeper than its
// friction, which is never damped).
template <class T>
LS_HD T settle_linear_velocity(Vec3<T>& v, const Vec3<T>& v_support, const Vec3<T>& n, const T& gap,
                               const Params<T>& P, bool relative, const T& limit) {
  v = cancel_resting_velocity(v, v_support, n, gap * P.inv_dt, P.rest_speed);  // eq 75
  const Vec3<T> base = relative ? v_support : Vec3<T>{};  // the source's AABB model: eq 77 on v itself
  const Vec3<T> rel = v - base;
  const T speed = length(rel);
  if (!(speed > limit)) v = base + settle_linear(rel, speed, P);  // eq 77, relative to the support; eq 116
  return speed;
}

// Stage 6, angular part: righting (eqs 64-71, 65 fixed) and, on an immovable
// support only (`immovable`: ground, SDF, static or sleeping body), the
// damping regimes (eqs 72-74), "up" being the support normal n; `speed` is
// what settle_linear_velocity returned.
// A leaning body (eq 115) is not righted.
template <class T>
LS_HD Vec3<T> settle_angular_velocity(const Vec3<T>& w, const Mat3<T>& R, const Vec3<T>& n, const T& speed,
                                      bool immovable, bool leaning, const Params<T>& P) {
  const Alignment<T> al = alignment_of(R, n);                  // eqs 64-66 (65 fixed)
  const Vec3<T> w1 = leaning ? w : righting(w, al, n, speed, P);  // eqs 67-71, 115
  return immovable ? regime_damping(w1, al.alignment, P) : w1;  // eqs 72-74
}

// Stage 6, angular part, on a movable support (the oriented-box model, an
// awake body under it): righting as above, then the damping regimes (eqs
// 72-74) on the spin relative to the support's, w_support (its angular
// velocity as the solver left it, before its own settling): a body resting
// flat on another cannot turn against it without lifting an edge, and that
// rocking is what the regimes take out, as on the ground; a column turning
// as a whole keeps its turn (damping the absolute spin of a cube on an awake
// cube took angular momentum nothing gave back, and columns crept). Without
// it, towers that statics says stand leaned 1-3 cm as the solver settled
// their loads (4 % of them beyond 2 cm; 1.0 % with it).
template <class T>
LS_HD Vec3<T> settle_angular_velocity_on(const Vec3<T>& w, const Vec3<T>& w_support, const Mat3<T>& R,
                                         const Vec3<T>& n, const T& speed, bool leaning, const Params<T>& P) {
  const Alignment<T> al = alignment_of(R, n);                  // eqs 64-66 (65 fixed)
  const Vec3<T> w1 = leaning ? w : righting(w, al, n, speed, P);  // eqs 67-71, 115
  return w_support + regime_damping(w1 - w_support, al.alignment, P);  // eqs 72-74, relative
}

// eqs 64-74, 115 (stage 6): a settling body's spin, relative to its support's
// (w_support(), as the solver left it) when that support is movable (the
// oriented-box model with an awake support body), else on its own
// (settle_angular_velocity, damped as on an immovable support).
template <class T, class SupportSpin>
LS_HD Vec3<T> settle_spin(const Vec3<T>& w, bool movable_support, SupportSpin&& w_support, const Mat3<T>& R,
                          const Vec3<T>& n, const T& speed, bool leaning, const Params<T>& P) {
  if (movable_support) return settle_angular_velocity_on(w, w_support(), R, n, speed, leaning, P);
  return settle_angular_velocity(w, R, n, speed, true, leaning, P);
}

// Stage 8 (eqs 2, 7-10) for one awake body.
template <class T>
LS_HD void integrate_pose(Vec3<T>& p, Quat<T>& q, const Vec3<T>& v, const Vec3<T>& w, const Params<T>& P) {
  p = integrate_position(p, v, P.dt);          // eq 2
  q = integrate_orientation(q, w, P.half_dt);  // eqs 7-10
}

// Stage 9 (eqs 78-80) for one awake body; `up` is its support normal (4.1),
// (0, 1, 0) when unsupported; `counter` is its sleep counter (eq 78);
// `radius` its half-diagonal |h| (m); `over`: it is over its support (eq 112;
// true with the AABB model). A body that is not may be tipping: its counter
// counts, but it is never slowed (79); it falls asleep (80) only when the
// counter reaches sleep_frames on its own (a tip that starts slowly, undamped,
// grows past the sleep speeds first; one that stays slow is held by what eq
// 112 does not see, as a box resting on three points of a curved bowl).
// `leaning`: it leans (eq 115) and rests tilted on what holds it: it counts
// as supported, its alignment is not asked, and it is slowed (79) once drowsy
// (held, it is not tipping; a leaning cube left to creep woke the cubes on it).
// `can_rest`: statics lets it rest (eqs 116, 117: friction holds it and its
// load is over its support); a body that cannot is no candidate.
// Returns true when it falls asleep (v and w are then zeroed, eq 80).
template <class T>
LS_HD bool update_sleep(Vec3<T>& v, Vec3<T>& w, int& counter, bool supported, bool over, bool leaning,
                        bool support_resting, bool can_rest, const Mat3<T>& R, const Vec3<T>& up, const T& radius,
                        const Params<T>& P) {
  const T speed = length(v), spin = length(w);
  const T alignment = leaning ? Num<T>::from_int(1) : alignment_of(R, up).alignment;  // eqs 64-66, 115
  if (can_rest && sleep_candidate(supported || leaning, speed, spin, alignment, radius, P)) ++counter;  // eqs 78, 115-117
  else counter = 0;
  switch (sleep_stage(counter, P.drowsy_frames, P.sleep_frames)) {
    case SleepStage::kAsleep:  // eq 80
      if (support_resting) {
        v = Vec3<T>{};
        w = Vec3<T>{};
        return true;
      }
      break;  // eq 109: wait, drowsy, for what holds it up to sleep first
    case SleepStage::kDrowsy:  // eq 79
      break;
    case SleepStage::kAwake:
      return false;
  }
  if (over || leaning) {  // eqs 79, 112, 115: one neither over its support nor leaning may tip: not slowed
    v = v * P.drowsy_damping;
    w = w * P.drowsy_damping;
  }
  return false;
}

// Eq 81 for a body-body contact (normal n from b towards a) between an awake
// and a sleeping body: the velocity of a sleeping side counts as 0. True when
// the sleeper wakes (fast approach or deep penetration).
template <class T>
LS_HD bool wake_test(const Vec3<T>& va, bool a_asleep, const Vec3<T>& vb, bool b_asleep, const Vec3<T>& n,
                     const T& penetration, const Params<T>& P) {
  const Vec3<T> v_rel = (a_asleep ? Vec3<T>{} : va) - (b_asleep ? Vec3<T>{} : vb);
  return wakes(dot(v_rel, n), penetration, P);
}

// Eq 108: has a supporter moved under a sleeper? When a body falls asleep
// (eq 80) it records, for each dynamic body it rests on, the support point in
// that body's frame (`local`, from the touching contact's point) and where
// that point was (`rest` = support_point at that moment). While the supporter
// is awake, the point it now carries is `now` = support_point(p, R, local);
// the sleeper wakes when that point has moved from `rest` by more than
// wake_support_distance on any axis, or (eq 108's speed) from `last`, where it
// was at the last frame's start, by more than sleep_linear dt: the supporter
// moves faster than a body riding on it may sleep (78). A box shoved 4.9 mm
// from under a sleeper (at 0.07 m/s) left it asleep where one shoved 6.9 mm
// woke it (AgreementProp seed 7083). `now` becomes the record's `last`.
template <class T>
LS_HD Vec3<T> support_point(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& local) {
  return p + R * local;
}
// Whether `now` is more than `limit` from `from` on any axis.
template <class T>
LS_HD bool support_moved(const Vec3<T>& now, const Vec3<T>& from, const T& limit) {
  return max_abs(now - from) > limit;
}

// eq 108: a supporter has carried the sleeper's support point away: `now`
// more than wake_support_distance from `rest`, or more than sleep_linear dt
// from `last`.
template <class T>
LS_HD bool support_carried_away(const Vec3<T>& now, const Vec3<T>& rest, const Vec3<T>& last, const Params<T>& P) {
  return support_moved(now, rest, P.wake_support_distance) || support_moved(now, last, P.sleep_linear * P.dt);
}

// eq 108: a support point as recorded: in its supporter's frame (at p, turned by R).
template <class T>
LS_HD Vec3<T> support_local(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& point) {
  return mat_transpose_mul(R, point - p);
}

}  // namespace lockstep
