// Part 4 of docs/SPEC.md: settling (righting torque, damping regimes, resting
// contact cancellation, linear settling damping).
#pragma once
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/params.hpp"

namespace lockstep {

template <class T>
struct Alignment {
  Vec3<T> best_axis;  // unit body axis in world, pointing along up (best_axis.up >= 0)
  T alignment{};      // eq 66 with the fix of eq 65: |a_best . up|
};

// eqs 64-66, with eq 65 fixed: the best axis maximises |a_i . up| (ties: the
// lowest i) and is flipped to point up, so a cube lying flat upside down is
// aligned (the source's signed argmax scores it 0). a_i = R e_i is column i
// of R, so a_i . up = (R^T up)_i. "up" is the support contact's normal
// (docs/SPEC.md 4.1): (0, 1, 0) on the ground as in the source, the surface
// normal on an SDF slope.
template <class T>
LS_HD Alignment<T> alignment_of(const Mat3<T>& R, const Vec3<T>& up) {
  const Vec3<T> d = mat_transpose_mul(R, up);
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (Num<T>::abs(d[i]) > Num<T>::abs(d[best])) best = i;
  Alignment<T> a;
  const Vec3<T> axis{R.row[0][best], R.row[1][best], R.row[2][best]};  // eq 64
  a.best_axis = d[best] < T{} ? -axis : axis;
  a.alignment = Num<T>::abs(d[best]);
  return a;
}

// eqs 67-71: misalign = 1 - alignment; r = normalize(best_axis x up);
// w_desired = kp * speed_factor * misalign, speed_factor = max(sf_min, sf_max - |v|);
// w' = w + kd * (w_desired - w.r) * dt * r. Skipped when |best_axis x up| is
// below 2^-12 (r undefined: the body is already aligned).
template <class T>
LS_HD Vec3<T> righting(const Vec3<T>& w, const Alignment<T>& a, const Vec3<T>& up, const T& speed, const Params<T>& P) {
  const Vec3<T> axis = cross(a.best_axis, up);
  if (length(axis) < P.righting_min_axis) return w;
  const Vec3<T> r = normalize(axis);                                          // eq 68
  const T misalign = Num<T>::from_int(1) - a.alignment;                       // eq 67
  const T speed_factor = Num<T>::max(P.speed_factor_min, P.speed_factor_max - speed);
  const T w_desired = P.kp * speed_factor * misalign;                         // eq 69
  const T w_error = w_desired - dot(w, r);                                    // eq 70
  return w + r * (w_error * P.kd_dt);                                         // eq 71
}

// eqs 72-74: the angular damping regime for an alignment; 1 when none applies.
template <class T>
LS_HD Vec3<T> regime_damping(const Vec3<T>& w, const T& alignment, const Params<T>& P) {
  if (alignment > P.align_fine) return w * P.damp_fine;  // eq 72
  if (alignment > P.align_good) return w * P.damp_good;  // eq 73
  if (alignment > P.align_fair) return w * P.damp_fair;  // eq 74
  return w;
}

// eq 98 (Part 4): the weight of a contact in its body's support normal: 1
// when touching (penetration >= 0), fading linearly to 0 as its gap grows to
// `width` (support_fade = max(slop, |g dt| dt); |g dt| dt is the distance a
// body falls from rest in one frame: 2.7 mm): (penetration + width) / width for -width < penetration
// < 0, 0 beyond (so width = 0 divides by nothing). A corner that rocks on and
// off the surface by a millimetre or two turns the support normal by a part
// of its swing, not by a jump.
template <class T>
LS_HD T support_weight(const T& penetration, const T& width) {
  if (!(penetration < T{})) return Num<T>::from_int(1);
  if (!(penetration > -width)) return T{};
  return (penetration + width) / width;
}

// The gap of a support contact (Part 4, eq 75): max(0, -penetration). A
// body's support gap is the smallest of its support contacts' gaps.
template <class T>
LS_HD T support_gap(const T& penetration) { return Num<T>::max(T{}, -penetration); }

// eq 75 (4.4): with n the body's support normal (pointing from the support
// to the body) and v_s the supporting body's velocity (0 for the ground), a
// slow relative normal velocity (|vn| < rest_speed, vn = (v - v_s).n) is
// removed but for an approach that closes the support gap g this frame:
// vn' = max(min(vn, 0), -gap_speed), gap_speed = g / dt; v' = v - (vn - vn') n.
// A touching body (g = 0) keeps no normal velocity; a body whose nearest
// support is a speculative gap settles onto it instead of hovering on it.
// Bodies are visited in ascending height (then index), so a stack comes to
// rest from the bottom up in one pass.
template <class T>
LS_HD Vec3<T> cancel_resting_velocity(const Vec3<T>& v, const Vec3<T>& v_support, const Vec3<T>& n,
                                      const T& gap_speed, const T& rest_speed) {
  const T vn = dot(v - v_support, n);
  if (!(Num<T>::abs(vn) < rest_speed)) return v;
  const T keep = Num<T>::max(Num<T>::min(vn, T{}), -gap_speed);
  return v - n * (vn - keep);
}

// eq 112 (Part 4): whether a body's centre of mass, seen along n (the
// engine passes up, (0, 1, 0): gravity decides), lies over its support, the
// convex hull of its support contacts' points, given as lever arms
// r[k] = point - p (the centre at the origin), k < count. With
// s_jk = (r[j] x r[k]).n, in the plane normal to n:
// - strictly inside (over): no r[j] has every s_jk >= 0 or every s_jk <= 0
//   (not all 0: an r[j] with no in-plane length is no witness), and some
//   s_jk != 0 (not all points on one line or one point through the centre);
// - strictly outside (not over): some r[j] has every r[k] at an angle in
//   [0, pi) from it: s_jk > 0, or = 0 with r[k] pointing the same way
//   (r[j].r[k] - (r[j].n)(r[k].n) > 0); an r[j] with no in-plane length is no witness;
// - else on the boundary (balanced on an edge or a corner, or the centre on
//   an edge of the hull): over when `boundary_over`, which the engine sets
//   while the body is slow (|w| < sleep_angular: a cube dropped on a corner
//   that comes to rest balanced on an edge is turned flat by settling), not
//   while it rolls over the edge: the boundary is a window of an ulp of the
//   cross product that Q16 hits and double never does, and the righting
//   torque (71) there kicked a box rolling over its edge at 0.47 rad/s back
//   the way it came (AgreementProp seed 7049).
// O(count^2) products, no division. More than kMaxSupportPoints support
// contacts (count > kMaxSupportPoints, only the first kMaxSupportPoints
// given) count as over: such a body is held from many sides; so do none
// (count 0: nothing to tip about). A body held by a contact that
// holds_off_support (a neighbour beside it, a sleeper above it) is not asked
// (World: narrow_phase).
constexpr int kMaxSupportPoints = 16;

template <class T>
LS_HD bool over_support(const Vec3<T>* r, int count, const Vec3<T>& n, bool boundary_over) {
  if (count > kMaxSupportPoints || count == 0) return true;
  // Strictly inside: no witness r[j], and some s_jk != 0. A row that stops
  // early has met both signs, so `any` sees every row that could be all 0.
  bool inside = true, any = false;
  for (int j = 0; j < count && inside; ++j) {
    bool left = true, right = true, nonzero = false;  // every s_jk >= 0, every s_jk <= 0; not all 0
    for (int k = 0; k < count && (left || right); ++k) {
      const T side = dot(cross(r[j], r[k]), n);
      left = left && !(side < T{});
      right = right && !(side > T{});
      nonzero = nonzero || side != T{};
    }
    if ((left || right) && nonzero) inside = false;
    any = any || nonzero;
  }
  if (inside && any) return true;
  if (!boundary_over) return false;
  for (int j = 0; j < count; ++j) {  // strictly outside?
    bool witness = true;  // every point within [0, pi) of r[j]
    const T rjn = dot(r[j], n);
    for (int k = 0; k < count && witness; ++k) {
      const T side = dot(cross(r[j], r[k]), n);
      if (side > T{}) continue;
      if (side < T{}) { witness = false; break; }
      witness = dot(r[j], r[k]) - rjn * dot(r[k], n) > T{};
    }
    if (witness) return false;
  }
  return true;  // on the boundary
}

// eq 112: whether a contact touching a body (within slop) may hold it beyond
// its support, so that eq 112 is not asked of it: its normal towards the body,
// n, is not a support normal (n.y < support_normal_min) and it either pushes
// from the side (n.y > -support_normal_min: a neighbour, a wall) or comes
// from above from something immovable (`immovable`: the ground, an SDF, a
// static or sleeping body: a box wedged under a sleeper). An awake body
// resting on it is a load, not a hold: it presses down and tips with it (a
// box under a column, landed on one edge, held there by (75) with its other
// edge 15 mm up: AgreementProp seed 7027).
template <class T>
LS_HD bool holds_off_support(const Vec3<T>& n, bool immovable, const T& support_normal_min) {
  if (n.y >= support_normal_min) return false;
  return immovable || n.y > -support_normal_min;
}

// eq 112's support points: a contact within support_fade counts, unless it
// is an impact: a speculative contact (gap beyond slop) whose point closes at
// more than rest_speed. v_n = (v_a + w_a x (c - p_a) - v_b - w_b x (c - p_b)) . n,
// a the lower body (or the only one: the ground, an SDF), n from b towards a;
// contact_closing_speed forms it in that order. A corner landing on a frame's
// end is not yet a support: counted, a rocking box falling flat was settled
// (eq 72: w x 0.4) in one engine and not in another at 2.56 against 3.00 mm
// (AgreementProp seed 7106).
template <class T>
LS_HD T contact_closing_speed(const Vec3<T>& va, const Vec3<T>& wa, const Vec3<T>& pa, const Vec3<T>& point,
                              const Vec3<T>& n) {
  return dot(va + cross(wa, point - pa), n);
}
template <class T>
LS_HD T contact_closing_speed(const Vec3<T>& va, const Vec3<T>& wa, const Vec3<T>& pa, const Vec3<T>& vb,
                              const Vec3<T>& wb, const Vec3<T>& pb, const Vec3<T>& point, const Vec3<T>& n) {
  return dot(va + cross(wa, point - pa) - (vb + cross(wb, point - pb)), n);
}
template <class T>
LS_HD bool support_impact(const T& penetration, const T& v_n, const Params<T>& P) {
  return !(penetration > -P.slop) && v_n < -P.rest_speed;
}

// eq 112: whether a contact touching a body (within slop) holds it beyond its
// support (holds_off_support); n: its normal towards the body.
template <class T>
LS_HD bool holds_body(const Vec3<T>& n, const T& penetration, bool immovable, const Params<T>& P) {
  return penetration > -P.slop && holds_off_support(n, immovable, P.support_normal_min);
}

// eqs 75, 98, 112: one contact of a body joins its support, in contact order.
// n: its normal towards the body; arm: its point less the body's centre;
// v_n(): its closing speed (contact_closing_speed, asked of a speculative
// contact only). Within support_fade and facing up (n.y >=
// support_normal_min), its weighted normal joins n_sum (98) and, unless it is
// an impact, its lever arm joins arms (112; n_arms goes up to
// kMaxSupportPoints + 1: too many to look at); within slop it is a support
// contact and its gap joins the support gap (75; `supported`: the body had a
// support contact before). Returns whether it is a support contact.
template <class T, class ClosingSpeed>
LS_HD bool add_support_contact(Vec3<T>& n_sum, Vec3<T>* arms, int& n_arms, T& gap, bool supported, const Vec3<T>& n,
                               const T& penetration, const Vec3<T>& arm, ClosingSpeed&& v_n, const Params<T>& P) {
  if (!(penetration > -P.support_fade) || !(n.y >= P.support_normal_min)) return false;
  n_sum += n * support_weight(penetration, P.support_fade);  // eq 98
  const bool speculative = !(penetration > -P.slop);
  if (!(speculative && support_impact(penetration, v_n(), P))) {  // eq 112: an impact is no support point
    if (n_arms < kMaxSupportPoints) arms[n_arms] = arm;
    if (n_arms <= kMaxSupportPoints) ++n_arms;
  }
  if (speculative) return false;
  const T g = support_gap(penetration);  // eq 75
  gap = supported ? Num<T>::min(gap, g) : g;
  return true;
}

// eq 115: whether a body leans: a contact holds it (`held`:
// holds_off_support, a wall, a neighbour beside it, a sleeper above it) and
// either it has no support contact (`supported`: wedged between steep
// contacts) or its centre is not over its support contacts (`over_contacts`:
// eq 112's test along up). It rests tilted against what holds it: it is not
// righted (67-71 would turn it against the hold: a plank leaning on a wall
// was stood upright, sliding its foot towards the wall), its sleep test (78)
// counts it as supported and asks no alignment, and what it touches is
// recorded for eq 108. A body held beside it but over its support (a cube in
// a pile) does not lean.
LS_HD inline bool leans(bool supported, bool held, bool over_contacts) {
  return held && (!supported || !over_contacts);
}

// eq 117 (the direction of eq 112's holds, 2026-11-28): the contacts that
// hold a body (holds_body), as lever arms from its centre and normals towards it,
// in contact order; at most kMaxHolds (n_holds goes up to kMaxHolds + 1:
// too many to look at, which counts as holding it every way).
inline constexpr int kMaxHolds = 8;
// eq 117: a hold blocks a turn when the turn moves its point into it by at
// least 1/kHoldMinInto of the point's speed (7.2 degrees): a hold square to
// the turn (a wall along the edge a load tips over) is not one, whatever
// the rounding of its contact points says.
inline constexpr int kHoldMinInto = 8;
template <class T>
LS_HD void add_hold(Vec3<T>* arms, Vec3<T>* normals, int& n_holds, const Vec3<T>& arm, const Vec3<T>& n) {
  if (n_holds < kMaxHolds) {
    arms[n_holds] = arm;
    normals[n_holds] = n;
  }
  if (n_holds <= kMaxHolds) ++n_holds;
}

// eq 117 with the direction of eq 112's holds (2026-11-28): whether the
// holds block every way the centre c = p + offset (a load's centre) can tip
// over the support points (lever arms r from p, count of them). A way to
// tip is a turn about a line through a support point r_j, seen along up a
// supporting line of the points with c strictly beyond it: along a unit e,
// either towards another point (e = r_k - r_j, an edge of their hull) or
// across c (e = (c - r_j) x up: about a corner), with (e x (c - r_j)).up >
// 0 (c beyond) and no (e x (r_m - r_j)).up > 0 (every point on the line or
// behind it). Turning about it (spin -e: c goes down), a point P moves at
// -e x (P - r_j); a hold (point P, normal n towards the body) blocks the
// turn when that motion runs into it at more than 7.2 degrees:
// (e x (P - r_j)).n > |e x (P - r_j)| / kHoldMinInto (longer_than: Q16
// without the root). Every way blocked: the holds keep the load where it
// is; one free: it tips, whatever else touches it. No holds: false; more
// than kMaxHolds holds, more than kMaxSupportPoints support points or none:
// true (held, as before). Frictionless statics of one turn at a time;
// `direction_of` gives each e unit length (no e: no way). O(count^2 (count
// + n_holds)) products, asked only of a held body with load children whose
// load's centre is not over its points. *Why:* a cube tipping over the edge
// of the cube under it with its load (the cube on it), a fallen cube
// leaning on its side and pushing across the way they tipped, counted as
// held: eq 117 left its load alone, settled (eqs 72-74 take 60 % of its
// spin a frame) it fell asleep with the load 2.3 cm beyond the edge (the
// float engine's overhang tower 3,122; HeldAcrossTest).
template <class T>
LS_HD bool holds_block_tip(const Vec3<T>* r, int count, const Vec3<T>& offset, const Vec3<T>* hold_arm,
                           const Vec3<T>* hold_n, int n_holds) {
  if (n_holds == 0) return false;
  if (n_holds > kMaxHolds || count > kMaxSupportPoints || count == 0) return true;
  const Vec3<T> up{T{}, Num<T>::from_int(1), T{}};
  for (int j = 0; j < count; ++j) {
    const Vec3<T> rj = r[j] - offset;  // from c
    for (int k = -1; k < count; ++k) {
      if (k == j) continue;
      Vec3<T> e;
      if (!direction_of(k < 0 ? cross(-rj, up) : (r[k] - offset) - rj, e)) continue;
      if (!(cross(e, -rj).y > T{})) continue;  // c not beyond the line
      bool supporting = true;
      for (int m = 0; m < count && supporting; ++m) supporting = !(cross(e, (r[m] - offset) - rj).y > T{});
      if (!supporting) continue;
      bool blocked = false;
      for (int h = 0; h < n_holds && !blocked; ++h) {
        const Vec3<T> turn = cross(e, (hold_arm[h] - offset) - rj);  // -(the hold point's motion), unit spin
        const T into = dot(turn, hold_n[h]);
        blocked = into > T{} && !longer_than(turn, into * Num<T>::from_int(kHoldMinInto));
      }
      if (!blocked) return false;
    }
  }
  return true;
}

// eqs 112, 115: a body's stance from its contacts. `over`: it is over its
// support: something holds it (`held`, holds_body), it has no support
// contact (`supported` false: nothing to tip about), or its centre, seen
// along up, is over its support points (over_support on the lever arms
// `arms`, n_arms of them; a centre on the boundary counts while it turns
// slower than sleep_angular). `leans`: eq 115. (A load's centre, eq 117,
// asks more of a hold: load_stands.)
struct Stance {
  bool over = true;
  bool leans = false;
};
template <class T>
LS_HD Stance stance_of(const Vec3<T>* arms, int n_arms, bool supported, bool held, const Vec3<T>& w,
                       const Params<T>& P) {
  const bool over_contacts =
      !supported || over_support(arms, n_arms, Vec3<T>{T{}, Num<T>::from_int(1), T{}}, length(w) < P.sleep_angular);
  Stance s;
  s.over = held || over_contacts;
  s.leans = leans(supported, held, over_contacts);
  return s;
}

// eq 112 (the chain): whether body i (height yi) settles before body s
// (height ys): stage 6 visits supported bodies in ascending (y, index) order.
template <class T>
LS_HD bool settles_before(const T& ys, int s, const T& yi, int i) {
  return ys < yi || (ys == yi && s < i);
}

// eq 112 (the chain): a body over its support by itself (`over`) still tips
// when its first support is an awake body that settles before it
// (`support_before`, settles_before) and tips (`support_over` false): it
// rides on that body, and settling it (75, 77) or letting it sleep would
// hold the two back (a unit cube 5 mm over an edge with a second cube on it:
// the load, settled towards the lower cube's centre velocity, dragged the
// pair's turn; 6 cm in 10 s, still tipping at frame 600).
LS_HD inline bool over_with_support(bool over, bool support_before, bool support_over) {
  return over && !(support_before && !support_over);
}

// eq 116 (Part 4): whether friction can hold a body still on its support:
// with g the gravity (m/s^2), n its support normal (towards the body) and mu
// the friction of its first support contact (eq 58; 0 with friction off),
// gravity's pull along the support, g_t = g - (g.n) n, is within the cone,
// |g_t| <= mu (-g.n), and gravity presses it onto the support (g.n <= 0).
// Statics: a cube on a ramp of angle a holds when tan a <= mu. A body that
// friction cannot hold is driven: settling (77) does not drag it and it is
// no sleep candidate (78), so it slides at g (sin a - mu cos a); eq 77 as a
// drag held a cube on a 20 degree ramp at mu 0.2 to 0.226 m/s where Newton
// says 3.0 m/s after 2 s. Zero gravity holds anything (0 <= 0).
template <class T>
LS_HD bool friction_holds(const Vec3<T>& g, const Vec3<T>& n, const T& mu) {
  const T gn = dot(g, n);
  if (gn > T{}) return false;
  const Vec3<T> gt = g - n * gn;
  return !longer_than(gt, mu * -gn);
}

// eq 116: the slide friction can stop in one frame beyond holding the body
// against gravity's pull along its support: (mu (-g.n) - |g_t|) dt (m/s;
// negative where friction cannot hold it). Eq 77 damps a held body only
// below it: a slower one friction would stop within the frame anyway, while
// a faster one is sliding and friction alone decelerates it, at
// g (mu cos a - sin a) on a ramp; damped there too, a cube pushed down a
// ramp stopped 4-8 % short of Newton's distance.
template <class T>
LS_HD T friction_spare(const Vec3<T>& g, const Vec3<T>& n, const T& mu, const T& dt) {
  const T gn = dot(g, n);
  const Vec3<T> gt = g - n * gn;
  return (mu * -gn - length(gt)) * dt;
}

// eq 116: the relative speed up to which eq 77 damps a supported body: -1
// (never) when friction cannot hold it (`holds` false: driven); else, with
// the oriented-box model and nothing holding it from the side (`spare`),
// what friction could stop in the frame, at most settle_speed; else (held
// from the side, or the source's AABB model) settle_speed, eq 77 as written.
template <class T>
LS_HD T settle_limit(bool holds, bool spare, const Vec3<T>& g, const Vec3<T>& n, const T& mu, const Params<T>& P) {
  if (!holds) return -Num<T>::from_int(1);
  if (!spare) return P.settle_speed;
  return Num<T>::min(P.settle_speed, friction_spare(g, n, mu, P.dt));
}

// eq 116: a supported body's footing: whether it can rest (something holds
// it, `held`, or friction holds it against gravity g on its support normal n
// with its first support contact's friction mu) and the speed up to which
// eq 77 damps it (settle_limit; `oriented`: the oriented-box model).
template <class T>
struct Footing {
  bool can_rest = true;
  T limit{};
};
template <class T>
LS_HD Footing<T> footing_of(bool held, bool oriented, const Vec3<T>& g, const Vec3<T>& n, const T& mu,
                            const Params<T>& P) {
  Footing<T> f;
  f.can_rest = held || friction_holds(g, n, mu);
  f.limit = settle_limit(f.can_rest, oriented && !held, g, n, mu, P);
  return f;
}

// eq 117 (Part 4): the load a body carries. A body j's load parent is the
// one body s that all of its support contacts (touching within slop, Part
// 4) touch, when s is awake and settles before j (settles_before: lower, so
// the parents never form a cycle); none when j rests on several things, on
// the ground, an SDF, a static or a sleeping body. fold_load_parent folds
// one support contact's other side into `state`: kLoadNone before the first,
// the body, or kLoadMany (several, or an immovable one: pass kLoadMany as
// `other`).
inline constexpr int kLoadNone = -1, kLoadMany = -2;
LS_HD inline int fold_load_parent(int state, int other) {
  if (state == kLoadNone) return other;
  return state == other ? state : kLoadMany;
}

// eq 117: a body's load is itself and its load children (the bodies whose
// load parent it is), each with its own load, children in ascending index:
// mass M = m + sum M_j and centre p + D, D = sum (M_j / M) (p_j + D_j - p).
// M is summed with load_mass_add, which stops at kLoadMassCap (16384 kg,
// half Q16.16's range: a heavier load is weighed as that much); D with
// load_offset_add once M is known. Formed in any order that forms a child
// before its parent (World: descending stage 6 order; the GPU engine: sweeps
// to a fixed point), the result is the same.
template <class T>
LS_HD T load_mass_add(const T& acc, const T& m, const T& cap) {
  return m > cap - acc ? cap : acc + m;
}
template <class T>
LS_HD Vec3<T> load_offset_add(const Vec3<T>& acc, const T& child_mass, const T& mass, const Vec3<T>& child_p,
                              const Vec3<T>& child_offset, const Vec3<T>& p) {
  return acc + ((child_p - p) + child_offset) * (child_mass / mass);
}
inline constexpr double kLoadMassCap = 16384.0;

// eq 117: a body's load (mass M, offset D) from its load children's, in
// ascending index: each_child(f) calls f(M_j, p_j, D_j) for each child in
// that order (twice: the masses first, then the offsets).
template <class T, class EachChild>
LS_HD void sum_load(const T& inv_mass, const Vec3<T>& p, EachChild&& each_child, T& mass, Vec3<T>& offset) {
  const T cap = Num<T>::from_double(kLoadMassCap);
  T m = Num<T>::from_int(1) / inv_mass;
  each_child([&](const T& child_mass, const Vec3<T>&, const Vec3<T>&) { m = load_mass_add(m, child_mass, cap); });
  Vec3<T> d{};
  each_child([&](const T& child_mass, const Vec3<T>& child_p, const Vec3<T>& child_offset) {
    d = load_offset_add(d, child_mass, m, child_p, child_offset, p);
  });
  mass = m;
  offset = d;
}

// eq 117: a load tips when a body in it is not over its support (eq 112, or
// its own load not over it): the body itself, or something in a load
// child's load. A body whose load children's loads tip is not at rest (no
// sleep candidate): what it carries is falling off it and its load is
// changing (an overhang toppling off a column's top left the column's
// lower cubes asleep under what remained, beyond their edge).
LS_HD inline bool load_tips(bool over, bool child_tips) { return !over || child_tips; }
LS_HD inline bool load_rests(bool child_tips) { return !child_tips; }

// eq 117: whether a body's load is over its support: eq 112's test on its
// support points taken from the load's centre p + D instead of p (lever arms
// r_k - D), along up; `boundary_over` as eq 112. Without load children (D
// not formed) it is eq 112's own answer.
template <class T>
LS_HD bool load_over_support(const Vec3<T>* r, int count, const Vec3<T>& offset, const Vec3<T>& n,
                             bool boundary_over) {
  if (count > kMaxSupportPoints || count == 0) return true;
  Vec3<T> shifted[kMaxSupportPoints];
  for (int k = 0; k < count; ++k) shifted[k] = r[k] - offset;
  return over_support(shifted, count, n, boundary_over);
}

// eq 117 with eq 112's holds: a body's load stands when its centre is over
// its support points (load_over_support) or the holds block every way it
// can tip about them (holds_block_tip, from the load's centre).
template <class T>
LS_HD bool load_stands(const Vec3<T>* r, int count, const Vec3<T>& offset, bool boundary_over,
                       const Vec3<T>* hold_arms, const Vec3<T>* hold_n, int n_holds) {
  return load_over_support(r, count, offset, Vec3<T>{T{}, Num<T>::from_int(1), T{}}, boundary_over) ||
         holds_block_tip(r, count, offset, hold_arms, hold_n, n_holds);
}

// eq 124 (Part 4): a sleeper under a load. A body falling asleep (eq 80)
// records its support points' lever arms as they were that frame (eq 112's,
// at most kMaxSupportPoints; a count above it: many) and its load parent
// (eq 117's, the sole dynamic body under it, asleep or awake). While it
// sleeps, its load is itself, its awake load children (eq 117's load parent
// is a sleeper) and its sleeping children (their recorded parent is it),
// each with its own load, summed as eq 117 sums (children in ascending
// index); a child counts only if its parent settles before it now (lower: no
// cycle). When that load's centre is not over the recorded support points,
// seen along up and from their horizontal parts (the sleeper has not moved
// since it recorded them; a centre on the boundary counts as over: it does
// not turn), the sleeper wakes at the end of the frame (stage 9) and tips
// with its load. The parent a body has in this pass: awake, its load parent;
// asleep, the one it recorded.
template <class T>
LS_HD Vec3<T> horizontal(const Vec3<T>& v) {
  return Vec3<T>{v.x, T{}, v.z};
}
LS_HD inline int sleeper_load_parent(bool awake, int load_parent, int recorded_parent) {
  return awake ? load_parent : recorded_parent;
}
template <class T>
LS_HD bool sleeper_load_over_support(const Vec3<T>* arms, int count, const Vec3<T>& offset) {
  return load_over_support(arms, count, horizontal(offset), Vec3<T>{T{}, Num<T>::from_int(1), T{}}, true);
}

// eq 77 (4.6): a supported body slower than settle_speed loses a fraction of its velocity.
template <class T>
LS_HD Vec3<T> settle_linear(const Vec3<T>& v, const T& speed, const Params<T>& P) {
  return speed < P.settle_speed ? v * P.settle_factor : v;
}

}  // namespace lockstep
