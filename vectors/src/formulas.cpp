// Level 2: single equations of docs/SPEC.md in raw Q16.16. Every case calls the
// engine's own per-equation functions (reference/include/lockstep/physics/),
// the same code World<Q16> runs; one compute function per formula serves both
// generation and verification.
#include "lockstep/vectors/formulas.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>

#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/body_step.hpp"
#include "lockstep/physics/box_box.hpp"
#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/physics/sdf.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/physics/sleep.hpp"
#include "lockstep/physics/solve_order.hpp"
#include "lockstep/physics/solver.hpp"
#include "lockstep/vectors/params_json.hpp"
#include "lockstep/vectors/scenes.hpp"
#include "lockstep/vectors/sdf_json.hpp"
#include "lockstep/world.hpp"

namespace lockstep::vectors {
namespace {

using V = Vec3<Q16>;
using Qt = Quat<Q16>;
using M = Mat3<Q16>;
using View = BodyView<Q16>;
using In = const Json&;
using Fn = std::function<Json(In, const std::string&)>;

constexpr std::int32_t kOne = 65536;

struct Formula {
  const char* function;
  std::vector<int> equations;
  const char* description;  // the computation, in the order it is done
  Fn compute;
};

M identity() { return identity3<Q16>(); }

// An immovable contact side (ground, SDF, static or sleeping body): v = w = 0,
// m^-1 = 0, I^-1 = 0, R = identity (SPEC 0.1), as the solver builds it.
View immovable() { return immovable_view<Q16>(); }

View view_at(In in, const std::string& key, const std::string& path) {
  const Json& b = member(in, key, path);
  const std::string p = path + "." + key;
  View v;
  v.v = vec_at(b, "v", p);
  v.w = vec_at(b, "w", p);
  v.inv_mass = q16_at(b, "inv_mass", p);
  v.R = mat_at(b, "R", p);
  v.inv_inertia = vec_at(b, "inv_inertia", p);
  return v;
}

Json view_json(const View& v) {
  return Json{{"v", to_json(v.v)},
              {"w", to_json(v.w)},
              {"inv_mass", to_json(v.inv_mass)},
              {"R", to_json(v.R)},
              {"inv_inertia", to_json(v.inv_inertia)}};
}

Json velocities(const View& v) { return Json{{"v", to_json(v.v)}, {"w", to_json(v.w)}}; }

// Params with the defaults of Appendix A, overridden by any Params field
// present in `in` (the group's shared inputs name the ones a formula uses).
Params<Q16> params_at(In in, const std::string& path) {
  Params<Q16> P = Params<Q16>::from(Constants{});
  for (const ParamField& f : param_fields()) {
    if (!in.contains(f.name)) continue;
    if (f.q16 != nullptr)
      P.*(f.q16) = q16_at(in, f.name, path);
    else if (f.vec != nullptr)
      P.*(f.vec) = vec_at(in, f.name, path);
    else
      P.*(f.integer) = static_cast<int>(int_at(in, f.name, path));
  }
  return P;
}

Json shared_params(std::initializer_list<const char*> names) {
  const Json all = params_to_json(Params<Q16>::from(Constants{}));
  Json s = Json::object();
  for (const char* n : names) s[n] = all.at(n);
  return s;
}

// ---------------------------------------------------------------------------
// The formulas
// ---------------------------------------------------------------------------

Json f_params(In in, const std::string& p) { return params_to_json(Params<Q16>::from(constants_from_json(in, p))); }

Json f_apply_gravity(In in, const std::string& p) {
  return Json{{"v", to_json(apply_gravity(vec_at(in, "v", p), vec_at(in, "gravity_dt", p)))}};
}
Json f_apply_damping(In in, const std::string& p) {
  return Json{{"x", to_json(apply_damping(vec_at(in, "x", p), q16_at(in, "factor", p)))}};
}
Json f_integrate_position(In in, const std::string& p) {
  return Json{{"p", to_json(integrate_position(vec_at(in, "p", p), vec_at(in, "v", p), q16_at(in, "dt", p)))}};
}
Json f_integrate_orientation(In in, const std::string& p) {
  return Json{{"q", to_json(integrate_orientation(quat_at(in, "q", p), vec_at(in, "w", p), q16_at(in, "half_dt", p)))}};
}
Json f_box_inverse_inertia(In in, const std::string& p) {
  const Q16 three = Q16::from_int(3);
  return Json{{"inv_inertia", to_json(box_inverse_inertia(vec_at(in, "half", p), q16_at(in, "inv_mass", p), three))}};
}
Json f_apply_inverse_inertia(In in, const std::string& p) {
  return Json{
      {"out", to_json(apply_inverse_inertia(mat_at(in, "R", p), vec_at(in, "inv_inertia", p), vec_at(in, "x", p)))}};
}
Json f_rotated_half_extents(In in, const std::string& p) {
  const M R = rotation_matrix(quat_at(in, "q", p));
  return Json{{"R", to_json(R)}, {"aabb_half", to_json(rotated_half_extents(R, vec_at(in, "half", p)))}};
}
Json f_cell_coord(In in, const std::string& p) {
  return Json{{"cell", cell_coord(q16_at(in, "x", p), q16_at(in, "inv_cell_size", p))}};
}
Json f_aabb_overlap(In in, const std::string& p) {
  const Overlap<Q16> o =
      aabb_overlap(vec_at(in, "p1", p), vec_at(in, "h1", p), vec_at(in, "p2", p), vec_at(in, "h2", p));
  return Json{{"hit", o.hit}, {"axis", o.axis}, {"penetration", to_json(o.penetration)}, {"normal", to_json(o.normal)}};
}
Json f_aabb_contact_point(In in, const std::string& p) {
  return Json{{"point", to_json(aabb_contact_point(vec_at(in, "p1", p), vec_at(in, "h1", p), vec_at(in, "p2", p),
                                                   vec_at(in, "h2", p), Q16::from_double(0.5)))}};
}
Json f_box_corner(In in, const std::string& p) {
  const M R = rotation_matrix(quat_at(in, "q", p));
  const auto k = int_at(in, "k", p);
  if (k < 0 || k > 7) throw FormatError(p + ".k: must be 0..7");
  return Json{{"R", to_json(R)},
              {"corner", to_json(box_corner(vec_at(in, "p", p), R, vec_at(in, "half", p), static_cast<int>(k)))}};
}
Json f_contact_prepare(In in, const std::string& p) {
  const View A = view_at(in, "a", p);
  const View B = view_at(in, "b", p);
  const V r1 = vec_at(in, "r1", p), r2 = vec_at(in, "r2", p), n = vec_at(in, "n", p);
  const Q16 v_n0 = dot(relative_velocity(A, r1, B, r2), n);  // eqs 48-49
  const Q16 e = low_speed_restitution(combined_restitution(q16_at(in, "e1", p), q16_at(in, "e2", p)), v_n0,
                                      q16_at(in, "restitution_min_speed", p));   // eqs 50, 76
  const Q16 mu = combined_friction(q16_at(in, "mu1", p), q16_at(in, "mu2", p));  // eq 58
  const Q16 k_n = inverse_effective_mass(A, r1, B, r2, n);                       // eq 86
  return Json{{"v_n0", to_json(v_n0)}, {"e", to_json(e)}, {"mu", to_json(mu)}, {"k_n", to_json(k_n)}};
}
// One solver iteration's normal impulse on one contact (SPEC 7.2 step 5): the
// target normal velocity (eq 97) is an input, so this group depends on eqs
// 86, 48-49, 94 and 87 only.
Json normal_step(View A, View B, In in, const std::string& p) {
  const V r1 = vec_at(in, "r1", p), r2 = vec_at(in, "r2", p), n = vec_at(in, "n", p);
  Q16 j_n = q16_at(in, "j_n", p);
  const Q16 k_n = inverse_effective_mass(A, r1, B, r2, n);                           // eq 86
  const Q16 v_n = dot(relative_velocity(A, r1, B, r2), n);                           // eqs 48-49
  const Q16 m_n = k_n > Q16{} ? Q16::from_int(1) / k_n : Q16{};                     // eq 114
  const Q16 dj = accumulate_normal_impulse(j_n, v_n, q16_at(in, "target", p), m_n);  // eqs 53, 94
  if (dj != Q16{}) apply_impulse(A, r1, B, r2, n * dj);                              // eq 87
  return Json{{"k_n", to_json(k_n)}, {"m_n", to_json(m_n)}, {"v_n", to_json(v_n)}, {"dj", to_json(dj)},
              {"j_n", to_json(j_n)}, {"a", velocities(A)},  {"b", velocities(B)}};
}
Json f_ground_impulse(In in, const std::string& p) {
  Json inb = in;
  inb["r2"] = Json::array({0, 0, 0});
  Json out = normal_step(view_at(in, "a", p), immovable(), inb, p);
  out.erase("b");
  return out;
}
Json f_two_body_impulse(In in, const std::string& p) {
  return normal_step(view_at(in, "a", p), view_at(in, "b", p), in, p);
}
// eq 97 as the solver calls it: v_n0 is first clamped to <= 0 (only an
// approaching contact bounces, the fix of 3.1).
Json f_contact_target_velocity(In in, const std::string& p) {
  const Q16 v_n0 = Num<Q16>::min(q16_at(in, "v_n0", p), Q16{});
  return Json{{"target", to_json(contact_target_velocity(q16_at(in, "penetration", p), q16_at(in, "e", p), v_n0,
                                                         q16_at(in, "g_n", p), q16_at(in, "dt", p),
                                                         q16_at(in, "inv_dt", p)))}};
}
// eqs 100-106 through the engine's box_box_manifold: the contact manifold of
// box a and box b (centres, rotation matrices, half extents) within tol.
Json f_box_box_manifold(In in, const std::string& p) {
  const BoxManifold<Q16> m = box_box_manifold(vec_at(in, "pa", p), mat_at(in, "Ra", p), vec_at(in, "ha", p),
                                              vec_at(in, "pb", p), mat_at(in, "Rb", p), vec_at(in, "hb", p),
                                              q16_at(in, "tol", p));
  Json pts = Json::array();
  for (int k = 0; k < m.count; ++k)
    pts.push_back(Json{{"point", to_json(m.point[k])}, {"penetration", to_json(m.penetration[k])}, {"feature", m.feature[k]}});
  return Json{{"count", m.count}, {"n", to_json(m.n)}, {"points", pts}};
}
// eq 107: a body's speculative reach in one step.
Json f_speculative_reach(In in, const std::string& p) {
  return Json{{"reach", to_json(speculative_reach(vec_at(in, "v", p), vec_at(in, "w", p), vec_at(in, "h", p),
                                                  q16_at(in, "dt", p)))}};
}
// eqs 97, 107: the ground tolerance of a body from its growth.
Json f_immovable_tolerance(In in, const std::string& p) {
  return Json{{"tolerance", to_json(immovable_tolerance(q16_at(in, "growth", p), q16_at(in, "half_tol", p),
                                                        q16_at(in, "tol", p)))}};
}
// eq 108: has the supporter carried the support point beyond the distance?
Json f_support_moved(In in, const std::string& p) {
  const V now = support_point(vec_at(in, "p", p), mat_at(in, "R", p), vec_at(in, "local", p));
  return Json{{"moved", support_moved(now, vec_at(in, "rest", p), q16_at(in, "distance", p))}};
}
// eq 108's speed: the support point now (p + R local) and whether it moved
// by more than step (sleep_linear dt) since `last`.
Json f_support_moving(In in, const std::string& p) {
  const V now = support_point(vec_at(in, "p", p), mat_at(in, "R", p), vec_at(in, "local", p));
  return Json{{"now", to_json(now)}, {"moving", support_moved(now, vec_at(in, "last", p), q16_at(in, "step", p))}};
}

// eq 111 through the engine's correct_manifold_point: one point of a pair
// pushed out of its residual depth; a.v, a.w (b's) are the displacement (m)
// and small turn (rad) so far, and come back updated.
Json f_correct_manifold_point(In in, const std::string& p) {
  View A = view_at(in, "a", p);
  View B = view_at(in, "b", p);
  correct_manifold_point(A, vec_at(in, "r1", p), B, vec_at(in, "r2", p), vec_at(in, "n", p),
                         q16_at(in, "penetration", p), q16_at(in, "slop", p), q16_at(in, "percent", p));
  return Json{{"a", velocities(A)}, {"b", velocities(B)}};
}

// The most points of one manifold: 8 ground corners or 9 samples of one SDF
// volume (eq 93), as World<T>::solve_contacts passes them.
constexpr int kManifoldPoints = 9;

// eq 99 through the engine's solve_manifold: one solver visit of body a's
// manifold against an immovable side (r2 = 0). Each point's k_n is eq 86 of
// a at r1 along n, as the contact preparation computes it.
Json f_manifold_visit(In in, const std::string& p) {
  View A = view_at(in, "a", p);
  View B = immovable();
  const Json& pts = member(in, "points", p);
  if (!pts.is_array() || pts.empty() || pts.size() > static_cast<std::size_t>(kManifoldPoints))
    throw FormatError(p + ".points: expected 1 to 9 contact points");
  struct Point {
    V r1, n;
    Q16 penetration;
    ContactState<Q16> state;
  };
  std::vector<Point> points;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const std::string pp = p + ".points[" + std::to_string(k) + "]";
    Point pt;
    pt.r1 = vec_at(pts[k], "r1", pp);
    pt.n = vec_at(pts[k], "n", pp);
    pt.penetration = q16_at(pts[k], "penetration", pp);
    pt.state.v_n0 = q16_at(pts[k], "v_n0", pp);
    pt.state.e = q16_at(pts[k], "e", pp);
    pt.state.mu = q16_at(pts[k], "mu", pp);
    pt.state.j_n = q16_at(pts[k], "j_n", pp);
    pt.state.j_t = vec_at(pts[k], "j_t", pp);
    pt.state.k_n = inverse_effective_mass(A, pt.r1, B, V{}, pt.n);  // eq 86
    points.push_back(pt);
  }
  const int count = static_cast<int>(points.size());
  auto point = [&](int k, V& r1, V& r2, V& n, Q16& penetration) {
    if (k >= count) return false;
    r2 = V{};
    const Point& pt = points[static_cast<std::size_t>(k)];
    r1 = pt.r1;
    n = pt.n;
    penetration = pt.penetration;
    return true;
  };
  auto load = [&](int k) { return points[static_cast<std::size_t>(k)].state; };
  auto store = [&](int k, const ContactState<Q16>& st) { points[static_cast<std::size_t>(k)].state = st; };
  SolveCounts counts;
  const bool friction = bool_at(in, "effect_friction", p), gravity = bool_at(in, "effect_gravity", p);
  solve_manifold<kManifoldPoints>(A, B, point, load, store, friction, gravity, params_at(in, p), counts);
  Json out_points = Json::array();
  for (const Point& pt : points)
    out_points.push_back(
        Json{{"k_n", to_json(pt.state.k_n)}, {"j_n", to_json(pt.state.j_n)}, {"j_t", to_json(pt.state.j_t)}});
  return Json{{"points", std::move(out_points)},
              {"a", velocities(A)},
              {"solver_contacts", counts.solver_contacts},
              {"normal_impulses", counts.normal_impulses},
              {"friction_steps", counts.friction_steps}};
}
Json f_friction_step(In in, const std::string& p) {
  View A = view_at(in, "a", p);
  View B = view_at(in, "b", p);
  const V r1 = vec_at(in, "r1", p), r2 = vec_at(in, "r2", p), n = vec_at(in, "n", p);
  V j_t = vec_at(in, "j_t", p);
  const ContactRows<Q16> rows = contact_rows(A, r1, B, r2, n, inverse_effective_mass(A, r1, B, r2, n));  // eqs 86, 114, 128-129
  Q16 vt[2];
  tangent_velocity(A, B, rows, vt);  // eqs 48, 56, 129
  const V dJ = accumulate_friction_impulse(j_t, vt, rows, Q16::from_int(1), q16_at(in, "mu", p), q16_at(in, "j_n", p));  // eq 95
  if (!(dJ == V{})) apply_delta(A, B, tangent_delta(A, B, rows, dJ));  // eqs 61-62, 87, 129
  return Json{{"t1", to_json(rows.t[0])}, {"t2", to_json(rows.t[1])},
              {"k_t", Json::array({to_json(rows.k_t[0]), to_json(rows.k_t[1]), to_json(rows.k_t[2])})},
              {"vt", Json::array({to_json(vt[0]), to_json(vt[1])})},
              {"dJ", to_json(dJ)}, {"j_t", to_json(j_t)}, {"a", velocities(A)}, {"b", velocities(B)}};
}
Json f_baumgarte(In in, const std::string& p) {
  V pa = vec_at(in, "pa", p), pb = vec_at(in, "pb", p);
  baumgarte_correction(pa, pb, vec_at(in, "n", p), q16_at(in, "penetration", p), q16_at(in, "inv_mass_a", p),
                       q16_at(in, "inv_mass_b", p), q16_at(in, "slop", p), q16_at(in, "percent", p));
  return Json{{"pa", to_json(pa)}, {"pb", to_json(pb)}};
}
Json f_alignment(In in, const std::string& p) {
  const M R = rotation_matrix(quat_at(in, "q", p));
  const Alignment<Q16> a = alignment_of(R, vec_at(in, "up", p));
  return Json{{"R", to_json(R)}, {"best_axis", to_json(a.best_axis)}, {"alignment", to_json(a.alignment)}};
}
Json f_righting(In in, const std::string& p) {
  const V up = vec_at(in, "up", p);
  const Alignment<Q16> a = alignment_of(mat_at(in, "R", p), up);
  return Json{{"best_axis", to_json(a.best_axis)},
              {"alignment", to_json(a.alignment)},
              {"w", to_json(righting(vec_at(in, "w", p), a, up, q16_at(in, "speed", p), params_at(in, p)))}};
}
Json f_regime_damping(In in, const std::string& p) {
  return Json{{"w", to_json(regime_damping(vec_at(in, "w", p), q16_at(in, "alignment", p), params_at(in, p)))}};
}
Json f_cancel_resting(In in, const std::string& p) {
  return Json{{"v", to_json(cancel_resting_velocity(vec_at(in, "v", p), vec_at(in, "v_support", p), vec_at(in, "n", p),
                                                    q16_at(in, "gap_speed", p), q16_at(in, "rest_speed", p)))}};
}
Json f_support_weight(In in, const std::string& p) {
  return Json{{"w", to_json(support_weight(q16_at(in, "penetration", p), q16_at(in, "width", p)))}};
}
// eq 112: whether the centre (the origin) is over the convex hull of the
// lever arms r, seen along n.
Json f_over_support(In in, const std::string& p) {
  const Json& rs = member(in, "r", p);
  if (!rs.is_array() || rs.size() > static_cast<std::size_t>(kMaxSupportPoints))
    throw FormatError(p + ".r: expected 0 to 16 lever arms");
  std::vector<V> r;
  for (std::size_t k = 0; k < rs.size(); ++k) r.push_back(vec_at(Json{{"r", rs[k]}}, "r", p + ".r[" + std::to_string(k) + "]"));
  return Json{{"over", over_support(r.data(), static_cast<int>(r.size()), vec_at(in, "n", p), bool_at(in, "boundary_over", p))}};
}
// eq 112's holds: whether a touching contact exempts a body from eq 112.
Json f_holds_off_support(In in, const std::string& p) {
  return Json{{"holds", holds_off_support(vec_at(in, "n", p), bool_at(in, "immovable", p),
                                          q16_at(in, "support_normal_min", p))}};
}
// eq 112's impacts: the closing speed at a contact's point (one body against
// the ground or an SDF; a body pair, a the lower index, n from b towards a),
// and whether a speculative contact closing faster than rest_speed is an
// impact (no support point).
Json f_contact_closing_speed(In in, const std::string& p) {
  return Json{{"v_n", to_json(contact_closing_speed(vec_at(in, "va", p), vec_at(in, "wa", p), vec_at(in, "pa", p),
                                                    vec_at(in, "point", p), vec_at(in, "n", p)))}};
}
Json f_contact_closing_speed_pair(In in, const std::string& p) {
  return Json{{"v_n", to_json(contact_closing_speed(vec_at(in, "va", p), vec_at(in, "wa", p), vec_at(in, "pa", p),
                                                    vec_at(in, "vb", p), vec_at(in, "wb", p), vec_at(in, "pb", p),
                                                    vec_at(in, "point", p), vec_at(in, "n", p)))}};
}
Json f_support_impact(In in, const std::string& p) {
  return Json{{"impact", support_impact(q16_at(in, "penetration", p), q16_at(in, "v_n", p), params_at(in, p))}};
}
// eqs 125-127: the solver's order (an edge's band, key and colour).
Json f_band_inverse(In in, const std::string& p) {
  return Json{{"inv_band", to_json(band_inverse(q16_at(in, "largest_half", p)))}};
}
Json f_edge_band(In in, const std::string& p) {
  return Json{{"band", edge_band(q16_at(in, "y_lo", p), q16_at(in, "y_hi", p), q16_at(in, "inv_band", p))}};
}
Json f_edge_key(In in, const std::string& p) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx",
                edge_key(static_cast<int>(int_at(in, "lo", p)), static_cast<int>(int_at(in, "hi", p)),
                         static_cast<int>(int_at(in, "band", p))));
  return Json{{"key", std::string(hex)}};
}
Json f_edge_colour(In in, const std::string& p) {
  return Json{{"colour", edge_colour(static_cast<int>(int_at(in, "top_lo", p)), static_cast<int>(int_at(in, "top_hi", p)))}};
}
// eq 112's chain: stage 6's order, and whether a body riding on its support stays over.
Json f_settles_before(In in, const std::string& p) {
  return Json{{"before", settles_before(q16_at(in, "ys", p), static_cast<int>(int_at(in, "s", p)), q16_at(in, "yi", p),
                                        static_cast<int>(int_at(in, "i", p)))}};
}
Json f_over_with_support(In in, const std::string& p) {
  return Json{{"over", over_with_support(bool_at(in, "over", p), bool_at(in, "support_before", p),
                                         bool_at(in, "support_over", p))}};
}
// eq 116: whether friction can hold a body on its support.
Json f_friction_holds(In in, const std::string& p) {
  return Json{{"holds", friction_holds(vec_at(in, "g", p), vec_at(in, "n", p), q16_at(in, "mu", p))}};
}
// eq 116: the slide friction can stop in a frame, and eq 77's limit.
Json f_friction_spare(In in, const std::string& p) {
  return Json{{"spare", to_json(friction_spare(vec_at(in, "g", p), vec_at(in, "n", p), q16_at(in, "mu", p), q16_at(in, "dt", p)))}};
}
Json f_settle_limit(In in, const std::string& p) {
  return Json{{"limit", to_json(settle_limit(bool_at(in, "holds", p), bool_at(in, "spare", p), vec_at(in, "g", p),
                                             vec_at(in, "n", p), q16_at(in, "mu", p), params_at(in, p)))}};
}
// eq 117: the load parent fold, the load's mass and centre, and whether it is over its support.
Json f_fold_load_parent(In in, const std::string& p) {
  return Json{{"state", fold_load_parent(static_cast<int>(int_at(in, "state", p)), static_cast<int>(int_at(in, "other", p)))}};
}
Json f_load_mass_add(In in, const std::string& p) {
  return Json{{"mass", to_json(load_mass_add(q16_at(in, "acc", p), q16_at(in, "m", p), q16_at(in, "cap", p)))}};
}
Json f_load_offset_add(In in, const std::string& p) {
  return Json{{"offset", to_json(load_offset_add(vec_at(in, "acc", p), q16_at(in, "child_mass", p), q16_at(in, "mass", p),
                                                 vec_at(in, "child_p", p), vec_at(in, "child_offset", p),
                                                 vec_at(in, "p", p)))}};
}
Json f_load_over_support(In in, const std::string& p) {
  const Json& rs = member(in, "r", p);
  if (!rs.is_array() || rs.size() > static_cast<std::size_t>(kMaxSupportPoints))
    throw FormatError(p + ".r: expected 0 to 16 lever arms");
  std::vector<V> r;
  for (std::size_t k = 0; k < rs.size(); ++k) r.push_back(vec_at(Json{{"r", rs[k]}}, "r", p + ".r[" + std::to_string(k) + "]"));
  return Json{{"over", load_over_support(r.data(), static_cast<int>(r.size()), vec_at(in, "offset", p), vec_at(in, "n", p),
                                         bool_at(in, "boundary_over", p))}};
}
// eq 117: whether a load tips, whether a body whose children's loads tip rests.
Json f_load_tips(In in, const std::string& p) {
  return Json{{"tips", load_tips(bool_at(in, "over", p), bool_at(in, "child_tips", p))}};
}
Json f_load_rests(In in, const std::string& p) { return Json{{"rests", load_rests(bool_at(in, "child_tips", p))}}; }
// eq 124: a sleeper under a load.
Json f_horizontal(In in, const std::string& p) { return Json{{"h", to_json(horizontal(vec_at(in, "v", p)))}}; }
Json f_sleeper_load_parent(In in, const std::string& p) {
  return Json{{"parent", sleeper_load_parent(bool_at(in, "awake", p), static_cast<int>(int_at(in, "load_parent", p)),
                                             static_cast<int>(int_at(in, "recorded_parent", p)))}};
}
Json f_sleeper_load_over_support(In in, const std::string& p) {
  const Json& rs = member(in, "arms", p);
  if (!rs.is_array() || rs.size() > static_cast<std::size_t>(kMaxSupportPoints))
    throw FormatError(p + ".arms: expected 0 to 16 lever arms");
  std::vector<V> r;
  for (std::size_t k = 0; k < rs.size(); ++k)
    r.push_back(vec_at(Json{{"r", rs[k]}}, "r", p + ".arms[" + std::to_string(k) + "]"));
  return Json{{"over", sleeper_load_over_support(r.data(), static_cast<int>(int_at(in, "count", p)), vec_at(in, "offset", p))}};
}
// eq 115: whether a supported body leans on what holds it beyond its support.
Json f_leans(In in, const std::string& p) {
  return Json{{"leans", leans(bool_at(in, "supported", p), bool_at(in, "held", p), bool_at(in, "over_contacts", p))}};
}
// eq 113: whether one side of a solver visit is converged.
Json f_visit_converged(In in, const std::string& p) {
  return Json{{"converged", visit_converged(vec_at(in, "v0", p), vec_at(in, "w0", p), vec_at(in, "v", p),
                                            vec_at(in, "w", p), q16_at(in, "eps", p))}};
}
Json f_settle_linear(In in, const std::string& p) {
  return Json{{"v", to_json(settle_linear(vec_at(in, "v", p), q16_at(in, "speed", p), params_at(in, p)))}};
}
Json f_combined_restitution(In in, const std::string& p) {
  return Json{{"e", to_json(combined_restitution(q16_at(in, "e1", p), q16_at(in, "e2", p)))}};
}
Json f_low_speed_restitution(In in, const std::string& p) {
  return Json{{"e", to_json(low_speed_restitution(q16_at(in, "e", p), q16_at(in, "v_n", p),
                                                  q16_at(in, "restitution_min_speed", p)))}};
}
Json f_combined_friction(In in, const std::string& p) {
  return Json{{"mu", to_json(combined_friction(q16_at(in, "mu1", p), q16_at(in, "mu2", p)))}};
}
Json f_sleep_candidate(In in, const std::string& p) {
  return Json{{"candidate", sleep_candidate(bool_at(in, "supported", p), q16_at(in, "speed", p), q16_at(in, "spin", p),
                                            q16_at(in, "alignment", p), q16_at(in, "radius", p), params_at(in, p))}};
}
Json f_sleep_stage(In in, const std::string& p) {
  const SleepStage s =
      sleep_stage(static_cast<int>(int_at(in, "counter", p)), static_cast<int>(int_at(in, "drowsy_frames", p)),
                  static_cast<int>(int_at(in, "sleep_frames", p)));
  return Json{{"stage", static_cast<int>(s)}};
}
Json f_wakes(In in, const std::string& p) {
  return Json{{"wakes", wakes(q16_at(in, "v_n", p), q16_at(in, "penetration", p), params_at(in, p))}};
}

Json f_sdf_sample(In in, const std::string& p) {
  std::vector<Q16> values;
  const SdfGrid<Q16> g = sdf_grid_at(in, p, values);
  const V x = vec_at(in, "p", p);
  const V grad = sdf_gradient(g, x);  // eq 34
  const bool valid = length(grad) > Q16{};
  return Json{{"inside", sdf_contains(g, x)},
              {"d", to_json(sdf_distance(g, x))},  // eqs 32-33
              {"grad", to_json(grad)},
              {"normal_valid", valid},
              {"n", to_json(valid ? normalize(grad) : V{})}};  // eq 36
}

// eq 92 through the engine itself: the bodies become a scene, the world is
// built, its state must be exactly the given one, and World::state_hash() is
// the output.
Json f_state_hash(In in, const std::string& p) {
  const Json& bodies = member(in, "bodies", p);
  Scene s;
  s.name = "state_hash";
  auto d = [](const Json& x) { return static_cast<double>(x.get<std::int32_t>()) / 65536.0; };
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Json& b = bodies[i];
    if (!b.is_array() || b.size() != 14)
      throw FormatError(p + ".bodies[" + std::to_string(i) + "]: expected 13 raw values and asleep");
    BodyDesc bd;
    bd.position = {d(b[0]), d(b[1]), d(b[2])};
    bd.orientation = {d(b[3]), d(b[4]), d(b[5]), d(b[6])};
    bd.velocity = {d(b[7]), d(b[8]), d(b[9])};
    bd.angular_velocity = {d(b[10]), d(b[11]), d(b[12])};
    bd.asleep = b[13].get<int>() != 0;
    s.bodies.push_back(bd);
  }
  const World<Q16> w(s);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    Json got = body_state(w.bodies()[i]);
    got.erase(got.size() - 1);  // the sleep counter is not hashed
    if (got != bodies[i])
      throw FormatError(p + ".bodies[" + std::to_string(i) +
                        "]: not a loadable state (its quaternion must be a fixed point "
                        "of eq 10): " +
                        bodies[i].dump());
  }
  return Json{{"hash", hex64(w.state_hash())}};
}

const std::vector<Formula>& formulas() {
  static const std::vector<Formula> all = {
      {"params",
       {91},
       "Appendix A.2: the constants (doubles) converted by eq 22 and the derived values computed in Q16 "
       "(half_dt = dt*0.5, inv_dt = 1/dt, gravity_dt = gravity*dt per component, damping factors "
       "1 - lambda*dt, inv_cell_size = 1/cell_size, kd_dt = kd*dt, support_fade = max(slop, length(gravity_dt)*dt), settle_factor = 1 - settle_damping, "
       "righting_min_axis = 2^-12)",
       f_params},
      {"apply_gravity", {1, 5}, "v + gravity_dt", f_apply_gravity},
      {"apply_damping", {6, 13}, "x * factor, per component", f_apply_damping},
      {"integrate_position", {2}, "p + v * dt (v * dt per component first)", f_integrate_position},
      {"integrate_orientation",
       {7, 8, 9, 10},
       "d = (0, w) (x) q (Hamilton product); q' = normalize(q + d * half_dt) (per component d_i * half_dt, then the "
       "sum)",
       f_integrate_orientation},
      {"box_inverse_inertia",
       {14, 15, 16, 17, 18},
       "xx = hx*hx, ...; I^-1 = (3/(yy + zz) * inv_mass, 3/(xx + zz) * inv_mass, 3/(xx + yy) * inv_mass)",
       f_box_inverse_inertia},
      {"apply_inverse_inertia",
       {90},
       "x * inv_inertia.x when the three entries are equal (a cube); else R * (inv_inertia (.) (R^T x)), (.) the "
       "component-wise product",
       f_apply_inverse_inertia},
      {"rotated_half_extents",
       {31},
       "R = mat3(q); aabb_half_i = dot((|R_i0|, |R_i1|, |R_i2|), half)",
       f_rotated_half_extents},
      {"cell_coord", {26, 82}, "floor_to_int(x * inv_cell_size)", f_cell_coord},
      {"aabb_overlap",
       {38, 39, 40, 41, 42, 43},
       "delta = p1 - p2; overlap_i = h1_i + h2_i - |delta_i|; hit iff every overlap_i > 0; axis = argmin overlap "
       "(ties: "
       "lowest); penetration = overlap[axis]; normal = +-1 on axis (+1 when delta[axis] >= 0)",
       f_aabb_overlap},
      {"aabb_contact_point",
       {85},
       "c_i = (max(p1_i - h1_i, p2_i - h2_i) + min(p1_i + h1_i, p2_i + h2_i)) * 0.5",
       f_aabb_contact_point},
      {"box_corner",
       {84, 93},
       "R = mat3(q); corner k = p + R * (+-hx, +-hy, +-hz), bit 0 of k: x, bit 1: y, bit 2: z, set: +h",
       f_box_corner},
      {"contact_prepare",
       {48, 49, 50, 58, 76, 86},
       "v_n0 = dot(v_a + w_a x r1 - v_b - w_b x r2, n); e = min(e1, e2), 0 unless -v_n0 > restitution_min_speed; "
       "mu = sqrt(mu1 * mu2); k_n = m_a^-1 + m_b^-1 + dot(I_a^-1 (r1 x n), r1 x n) + dot(I_b^-1 (r2 x n), r2 x n)",
       f_contact_prepare},
      {"ground_impulse",
       {48, 49, 53, 86, 87, 94},
       "one solver iteration's normal impulse on a ground contact (body b immovable, r2 = 0): k_n (86); "
       "v_n = dot(v_a + w_a x r1, n) (48-49); dj = -(v_n - target) / k_n, j_n' = max(j_n + dj, 0), applied = "
       "j_n' - j_n (94; target is the contact's target normal velocity, eq 97); if applied != 0: J = n * applied "
       "on a at r1 (87). From j_n = 0 with target = -e v_n this is eq 53",
       f_ground_impulse},
      {"two_body_impulse",
       {48, 49, 53, 86, 87, 94},
       "as ground_impulse with body b movable: -J on b at r2 (87)",
       f_two_body_impulse},
      {"friction_step",
       {56, 86, 87, 95, 128, 129},
       "the contact's rows (eqs 128-129, contact_rows): t1 = normalize((n.z, 0, -n.x)) if |n.x| > |n.y| else "
       "normalize((0, n.z, -n.y)), t2 = n x t1; rt1_a = r1 x t_a, at1_a = I_a^-1 rt1_a (90), the same of b at r2; "
       "k_t = {k11, k12, k22}: k11 = m_a^-1 + m_b^-1 + rt1_0.at1_0 + rt2_0.at2_0, k12 = rt1_0.at1_1 + rt2_0.at2_1, "
       "k22 = m_a^-1 + m_b^-1 + rt1_1.at1_1 + rt2_1.at2_1. vt_a = (v_a - v_b).t_a + w_a.rt1_a - w_b.rt2_a; "
       "r = max(|vt0|, |vt1|); if r > 0: u_a = vt_a / r, q = k11 (u0 u0) + (k12 (u0 u1)) 2 + k22 (u1 u1), and if q > 0: "
       "i = (u0 u0 + u1 u1) / q, j_t' = j_t - (t1 (vt0 i) + t2 (vt1 i)) * 1; else j_t' = j_t; "
       "j_t' scaled by (mu j_n) / |j_t'| when |j_t'| > mu j_n (95); "
       "dJ = j_t' - j_t applied through the rows (87): l'_a = dJ.t_a, v_a += dJ m_a^-1, w_a += at1_0 l'_0 + at1_1 l'_1, "
       "v_b -= dJ m_b^-1, w_b -= at2_0 l'_0 + at2_1 l'_1",
       f_friction_step},
      {"baumgarte_correction",
       {63, 89},
       "c = max(0, penetration - slop) * percent; if c > 0: total = inv_a + inv_b; pa += n * (c * (inv_a / total)); "
       "pb -= n * (c * (inv_b / total))",
       f_baumgarte},
      {"alignment_of",
       {64, 65, 66},
       "R = mat3(q); d = R^T up; best = argmax_i |d_i| (ties: lowest i); axis = column best of R, negated if d[best] < "
       "0; "
       "alignment = |d[best]|; up is the support contact's normal",
       f_alignment},
      {"righting",
       {67, 68, 69, 70, 71},
       "alignment from R and up (64-66); axis = best_axis x up; if length(axis) >= righting_min_axis: r = "
       "normalize(axis); "
       "misalign = 1 - alignment; sf = max(speed_factor_min, speed_factor_max - speed); w_desired = kp * sf * "
       "misalign; "
       "w' = w + r * ((w_desired - dot(w, r)) * kd_dt)",
       f_righting},
      {"regime_damping",
       {72, 73, 74},
       "w * damp_fine if alignment > align_fine, else damp_good if > align_good, else "
       "damp_fair if > align_fair, else w",
       f_regime_damping},
      {"cancel_resting_velocity",
       {75},
       "vn = dot(v - v_support, n); keep = max(min(vn, 0), -gap_speed); v - n * (vn - keep) if |vn| < rest_speed, "
       "else v",
       f_cancel_resting},
      {"support_weight", {98}, "1 if penetration >= 0, 0 if penetration <= -width, else (penetration + width) / width", f_support_weight},
      {"over_support", {112},
       "true if strictly inside (no r[j] has s_jk = cross(r[j], r[k]).n >= 0 for every k, or <= 0 for every k, not all 0; "
       "some s_jk != 0); false if strictly outside (some r[j] has every s_jk > 0, or = 0 and "
       "dot(r[j], r[k]) - (r[j].n)(r[k].n) > 0); else (the boundary) boundary_over. 0 arms: true",
       f_over_support},
      {"holds_off_support", {112}, "n.y < support_normal_min and (immovable or n.y > -support_normal_min)",
       f_holds_off_support},
      {"contact_closing_speed", {112}, "dot(va + cross(wa, point - pa), n)", f_contact_closing_speed},
      {"contact_closing_speed_pair", {112}, "dot(va + cross(wa, point - pa) - (vb + cross(wb, point - pb)), n)",
       f_contact_closing_speed_pair},
      {"support_impact", {112}, "not (penetration > -slop) and v_n < -rest_speed", f_support_impact},
      {"settles_before", {112}, "ys < yi or (ys == yi and s < i): body s settles before body i (stage 6's order)",
       f_settles_before},
      {"band_inverse", {125}, "(1 / max(largest_half * 2, 1/64)) * 8: 1 / the height band (bands of H / 4)", f_band_inverse},
      {"edge_band", {125},
       "m = y_lo * 0.5 + y_hi * 0.5; 0 if m is NaN; L = 16383 / inv_band if inv_band > 1 else 16383; "
       "floor(max(-L, min(m, L)) * inv_band)",
       f_edge_band},
      {"edge_key", {126},
       "x = lo * 0x9E3779B1 ^ hi * 0x85EBCA77; x ^= x >> 15; x *= 0x2C1B3C6D; x ^= x >> 12 (uint32, wrapping); "
       "key = (uint32(band) + 2^31 mod 2^32) << 32 | x, as 16 hex digits",
       f_edge_key},
      {"edge_colour", {127}, "max(top_lo, top_hi) + 1 (-1: the body has no edge before this one)", f_edge_colour},
      {"over_with_support", {112}, "over and not (support_before and not support_over): a body riding on a body that tips tips",
       f_over_with_support},
      {"leans", {115}, "supported and held and not over_contacts: it rests tilted on what holds it (not righted, no alignment test for sleep)",
       f_leans},
      {"settle_linear", {77}, "v * settle_factor if speed < settle_speed, else v", f_settle_linear},
      {"friction_holds", {116},
       "gn = dot(g, n); gt = g - n * gn; false if gn > 0, else not (|gt| > mu * -gn) (|gt| by longer_than)",
       f_friction_holds},
      {"friction_spare", {116}, "(mu * -dot(g, n) - length(g - n * dot(g, n))) * dt", f_friction_spare},
      {"settle_limit", {116},
       "-1 if not holds; settle_speed if not spare; else min(settle_speed, friction_spare(g, n, mu, dt))",
       f_settle_limit},
      {"fold_load_parent", {117},
       "other if state == -1 (kLoadNone), state if state == other, else -2 (kLoadMany); an immovable other side is passed as -2",
       f_fold_load_parent},
      {"load_mass_add", {117}, "cap if m > cap - acc, else acc + m", f_load_mass_add},
      {"load_offset_add", {117}, "acc + ((child_p - p) + child_offset) * (child_mass / mass)", f_load_offset_add},
      {"load_over_support", {117}, "over_support(r[k] - offset for each k, n, boundary_over); 0 or more than 16 arms: true",
       f_load_over_support},
      {"load_tips", {117}, "not over or child_tips", f_load_tips},
      {"load_rests", {117}, "not child_tips", f_load_rests},
      {"horizontal", {124}, "(v.x, 0, v.z)", f_horizontal},
      {"sleeper_load_parent", {124}, "load_parent if awake, else recorded_parent", f_sleeper_load_parent},
      {"sleeper_load_over_support", {124},
       "load_over_support(arms (their first min(count, 16)), count, horizontal(offset), (0, 1, 0), true); count 0 or "
       "more than 16: true",
       f_sleeper_load_over_support},
      {"visit_converged", {113}, "true iff |v_k - v0_k| < eps and |w_k - w0_k| < eps for every component k",
       f_visit_converged},
      {"combined_restitution", {50}, "min(e1, e2)", f_combined_restitution},
      {"low_speed_restitution", {76}, "e if -v_n > restitution_min_speed, else 0", f_low_speed_restitution},
      {"combined_friction", {58}, "sqrt(mu1 * mu2)", f_combined_friction},
      {"sleep_candidate",
       {78},
       "supported and speed < sleep_linear and (spin * radius < sleep_corner_speed if radius < sleep_small_radius, "
       "else spin < sleep_angular) and alignment > sleep_alignment",
       f_sleep_candidate},
      {"sleep_stage",
       {79, 80},
       "2 (asleep) if counter >= sleep_frames, 1 (drowsy) if counter >= drowsy_frames, else 0",
       f_sleep_stage},
      {"wakes", {81}, "-v_n > wake_speed or penetration > wake_penetration", f_wakes},
      {"sdf_sample",
       {32, 33, 34, 36, 93},
       "inside: min <= p <= max per axis; d: per axis u = (clamp(p_a, min_a, max_a) - min_a) * inv_spacing_a, "
       "i = clamp(floor(u), 0, n_a - 2), f = u - i; trilinear along x, then y, then z with lerp(a, b, t) = a + (b - a) "
       "* t; "
       "grad_a = (d(p + spacing_a e_a) - d(p - spacing_a e_a)) * inv_spacing_a; n = normalize(grad) when |grad| > 0",
       f_sdf_sample},
      {"state_hash",
       {92},
       "FNV-1a 64 over, per body: raw int32 of p.x p.y p.z q.w q.x q.y q.z v.x v.y v.z w.x w.y w.z as 4 bytes "
       "little-endian each, then 1 byte asleep",
       f_state_hash},
      {"contact_target_velocity",
       {97},
       "the target normal velocity of eq 94: v = min(v_n0, 0); touching (penetration >= 0): -(e * v); "
       "else gap = -penetration; if not e > 0 or not -(v * dt) > gap (the gap does not close this frame): "
       "penetration * inv_dt; else ev = -(e * v), rise = sqrt(max(g_n, 0) * gap * 2 * (1 - e * e)); 0 if not "
       "ev > rise; ev if ev > 128; else sqrt((ev - rise) * (ev + rise)), i.e. sqrt(e^2 (v^2 + 2 g_n gap) - "
       "2 g_n gap), the bounce at the surface risen back to the gap, without the "
       "overflow of ev^2. g_n is the gravity pressing the contact shut (-dot(gravity, n) against an immovable "
       "side when gravity is on, else 0)",
       f_contact_target_velocity},
      {"manifold_visit",
       {48, 49, 53, 56, 57, 60, 86, 87, 88, 94, 95, 97, 99},
       "one solver iteration's visit of a manifold: body a's points of contact with one immovable side (ground "
       "corners, the samples of one SDF volume; r2 = 0, b the immovable view), in points order. k_n,k = (86) of a at "
       "r1_k along n_k. eq 99: with more than one point, o = sum_k (m_a^-1 + 0) / k_n,k in points order and "
       "split = o if o > 1, else 1; with one point split = 1. Normal pass (Jacobi): for every point from the "
       "velocities at the start of the visit, v_n = dot(v_a + w_a x r1, n) (48-49), target = eq 97 with "
       "min(v_n0, 0) and g_n = -dot(gravity, n) if effect_gravity else 0, then (94) with the effective mass "
       "m_n * (1/split) (m_n = 1/k_n, eq 114; 1/split only when split != 1); with more than one point the "
       "proposals are scaled by the step length of (99) (normal_manifold_step), then applied in points order "
       "through the normal rows (87, 114). Friction: the cone pull-back of (99) step 5, then from the velocities "
       "after the normal pass, for every point with j_n > 0 or j_t != 0: friction_step's proposal (95, 128-129) "
       "with the tangent mass times 1/split; with more than one point scaled by the step length of (99) "
       "(friction_manifold_step), then applied in points order through the tangent rows. Counts: points visited, "
       "normal and friction impulses applied",
       f_manifold_visit},
      {"box_box_manifold",
       {100, 101, 102, 103, 104, 105, 106},
       "docs/SPEC.md 2.4: separating axes (100) on a's 3 face axes, b's 3, then the 9 edge pairs A_i x B_j "
       "(i outer; skipped when |A_i x B_j| <= 1/64), any s > tol: count 0; a's face unless b's separates by "
       "0.05 |s_a| + 0.0005 more (101); an edge pair only if it separates by that margin more than the face (102). "
       "Face: the incident face (103) clipped against the reference face's side planes +a1, -a1, +a2, -a2 (104) "
       "with feature ids, points with depth > -tol kept, at most 4 (105), each halfway to the reference face. "
       "Edge: one point midway between the closest points of the two edges (106), penetration -s_e",
       f_box_box_manifold},
      {"speculative_reach",
       {107},
       "(min(max_abs(v), 64) + (max_abs(w) > 64 / (3 max_abs(h)) ? 64 : max_abs(w) * (3 max_abs(h)))) * dt",
       f_speculative_reach},
      {"immovable_tolerance",
       {97, 107},
       "(growth - half_tol) + tol: a body's ground corners are contacts within it (oriented-box "
       "model; growth = half_tol + speculative_reach as the broadphase formed it)",
       f_immovable_tolerance},
      {"support_moved",
       {108},
       "max_abs((p + R * local) - rest) > distance",
       f_support_moved},
      {"support_moving",
       {108},
       "now = p + R * local; moving = max_abs(now - last) > step (step = sleep_linear * dt)",
       f_support_moving},
      {"correct_manifold_point",
       {111},
       "d = penetration - dot((a.v + a.w x r1) - (b.v + b.w x r2), n); c = (d - slop) * percent; if c > 0 and "
       "k = (86) at r1, r2 along n > 0: P = n * (c / k); a.v += P * a.inv_mass, a.w += (87)'s I_a^-1 (r1 x P); "
       "b.v -= P * b.inv_mass, b.w -= I_b^-1 (r2 x P). a.v, a.w, b.v, b.w are displacements (m) and turns (rad)",
       f_correct_manifold_point},
  };
  return all;
}

const Formula* find_formula(const std::string& name) {
  for (const Formula& f : formulas())
    if (name == f.function) return &f;
  return nullptr;
}

// ---------------------------------------------------------------------------
// Case generation
// ---------------------------------------------------------------------------

struct Case {
  Json in;
  std::string comment;
  std::vector<std::string> flags;
};

View random_view(Rng& rng) {
  View v;
  v.v = rng.vec(-5, 5);
  v.w = rng.vec(-3, 3);
  v.inv_mass = Q16::from_int(1) / rng.q16(0.5, 10);
  v.R = rotation_matrix(rng.unit_quat());
  v.inv_inertia = box_inverse_inertia(rng.vec(0.1, 2), v.inv_mass, Q16::from_int(3));
  return v;
}

Json random_raw_vec(Rng& rng, double lo, double hi) { return to_json(rng.vec(lo, hi)); }

// A unit normal within about 40 degrees of up (an SDF slope's support normal).
V slope_normal(Rng& rng) { return normalize(V{rng.q16(-0.8, 0.8), Q16::from_int(1), rng.q16(-0.8, 0.8)}); }

// A unit quaternion that eq 10 leaves unchanged (so a scene can load it exactly).
Qt fixed_point_quat(Rng& rng) {
  for (;;) {
    Qt q = rng.unit_quat();
    for (int k = 0; k < 8; ++k) {
      const Qt n = normalize(q);
      if (n == q) return q;
      q = n;
    }
  }
}

std::vector<Case> cases_for(const std::string& fn, Rng& rng) {
  std::vector<Case> out;
  auto add = [&](Json in, std::string comment = "", std::vector<std::string> flags = {"Random"}) {
    out.push_back({std::move(in), std::move(comment), std::move(flags)});
  };
  const Params<Q16> P = Params<Q16>::from(Constants{});
  const int n = 24;
  const Json zero = Json::array({0, 0, 0});
  const Json up = Json::array({0, kOne, 0});
  if (fn == "params") {
    add(constants_to_json(Constants{}), "the defaults of Appendix A", {"Defaults"});
    Constants c;
    c.dt = 1.0 / 120.0;
    c.gravity = {0.5, -1.62, 0.25};
    c.linear_damping = 0.1;
    c.angular_damping = 0.3;
    c.cell_size = 3.0;
    c.kd = 7.5;
    c.settle_damping = 0.25;
    c.solver_iterations = 8;
    add(constants_to_json(c), "dt 1/120, lunar gravity with a tilt, other rates", {"Modified"});
    return out;
  }
  for (int k = 0; k < n; ++k) {
    Json in;
    if (fn == "apply_gravity") {
      in = {{"v", random_raw_vec(rng, -20, 20)}, {"gravity_dt", to_json(P.gravity_dt)}};
    } else if (fn == "apply_damping") {
      in = {{"x", random_raw_vec(rng, -20, 20)},
            {"factor", to_json(k % 2 ? P.angular_damping_factor : P.linear_damping_factor)}};
    } else if (fn == "integrate_position") {
      in = {{"p", random_raw_vec(rng, -100, 100)}, {"v", random_raw_vec(rng, -20, 20)}, {"dt", to_json(P.dt)}};
    } else if (fn == "integrate_orientation") {
      in = {{"q", to_json(rng.unit_quat())}, {"w", random_raw_vec(rng, -10, 10)}, {"half_dt", to_json(P.half_dt)}};
    } else if (fn == "box_inverse_inertia") {
      in = {{"half", random_raw_vec(rng, 0.05, 3)}, {"inv_mass", to_json(Q16::from_int(1) / rng.q16(0.1, 100))}};
    } else if (fn == "apply_inverse_inertia") {
      View v = random_view(rng);
      if (k % 3 == 0)
        v.inv_inertia = box_inverse_inertia(V{Q16::from_raw(32768), Q16::from_raw(32768), Q16::from_raw(32768)},
                                            v.inv_mass, Q16::from_int(3));  // a cube: the shortcut
      in = {{"R", to_json(v.R)}, {"inv_inertia", to_json(v.inv_inertia)}, {"x", random_raw_vec(rng, -3, 3)}};
    } else if (fn == "rotated_half_extents") {
      in = {{"q", to_json(rng.unit_quat())}, {"half", random_raw_vec(rng, 0.05, 3)}};
    } else if (fn == "cell_coord") {
      in = {{"x", to_json(rng.q16(-200, 200))}, {"inv_cell_size", to_json(P.inv_cell_size)}};
    } else if (fn == "aabb_overlap" || fn == "aabb_contact_point") {
      const Json p1 = random_raw_vec(rng, -1, 1);
      const Json p2 = random_raw_vec(rng, -1, 1);
      in = {{"p1", p1}, {"h1", random_raw_vec(rng, 0.1, 1)}, {"p2", p2}, {"h2", random_raw_vec(rng, 0.1, 1)}};
    } else if (fn == "box_corner") {
      in = {{"p", random_raw_vec(rng, -10, 10)},
            {"q", to_json(rng.unit_quat())},
            {"half", random_raw_vec(rng, 0.1, 2)},
            {"k", k % 8}};
    } else if (fn == "contact_prepare") {
      const bool ground = k % 3 == 0;
      const View A = random_view(rng);
      const View B = ground ? immovable() : random_view(rng);
      const Json n_json = ground ? up : to_json(normalize(rng.vec(-1, 1)));
      in = {{"a", view_json(A)},
            {"b", view_json(B)},
            {"r1", random_raw_vec(rng, -1, 1)},
            {"r2", ground ? zero : random_raw_vec(rng, -1, 1)},
            {"n", n_json},
            {"e1", to_json(rng.q16(0, 1))},
            {"e2", to_json(rng.q16(0, 1))},
            {"mu1", to_json(rng.q16(0, 1))},
            {"mu2", to_json(rng.q16(0, 1))},
            {"restitution_min_speed", to_json(P.restitution_min_speed)}};
      add(in, ground ? "body b is the ground (immovable)" : "two bodies");
      continue;
    } else if (fn == "ground_impulse" || fn == "two_body_impulse") {
      const View A = random_view(rng);
      const View B = fn == "ground_impulse" ? immovable() : random_view(rng);
      const V r1 = rng.vec(-1, 1);
      const V r2 = fn == "ground_impulse" ? V{} : rng.vec(-1, 1);
      const V nn = fn == "ground_impulse" ? V{Q16{}, Q16::from_raw(kOne), Q16{}} : normalize(rng.vec(-1, 1));
      const Q16 v_n = dot(relative_velocity(A, r1, B, r2), nn);
      const bool first = k % 2 == 0;  // first iteration: j_n = 0, target = -e v_n (exactly eq 53)
      in = {{"a", view_json(A)}};
      if (fn == "two_body_impulse") in["b"] = view_json(B);
      in["r1"] = to_json(r1);
      if (fn == "two_body_impulse") in["r2"] = to_json(r2);
      in["n"] = to_json(nn);
      const Q16 e = rng.q16(0, 1);
      const Q16 later_target = rng.q16(-0.2, 2);
      in["target"] = to_json(first ? -(e * min(v_n, Q16{})) : later_target);
      in["j_n"] = to_json(first ? Q16{} : rng.q16(0, 3));
      add(in, first ? "first iteration: j_n = 0, target -e v_n (eq 53)" : "later iteration: accumulated j_n");
      continue;
    } else if (fn == "friction_step") {
      const bool ground = k % 3 == 0;
      const View A = random_view(rng);
      const View B = ground ? immovable() : random_view(rng);
      in = {{"a", view_json(A)},
            {"b", view_json(B)},
            {"r1", random_raw_vec(rng, -1, 1)},
            {"r2", ground ? zero : random_raw_vec(rng, -1, 1)},
            {"n", ground ? up : to_json(normalize(rng.vec(-1, 1)))},
            {"mu", to_json(rng.q16(0, 1))},
            {"j_n", to_json(rng.q16(0, 3))},
            {"j_t", k % 2 ? random_raw_vec(rng, -0.5, 0.5) : zero}};
      add(in, ground ? "against the ground" : "two bodies");
      continue;
    } else if (fn == "baumgarte_correction") {
      const bool ground = k % 3 == 0;
      in = {{"pa", random_raw_vec(rng, -10, 10)},
            {"pb", random_raw_vec(rng, -10, 10)},
            {"n", ground ? up : to_json(normalize(rng.vec(-1, 1)))},
            {"penetration", to_json(rng.q16(0, 0.2))},
            {"inv_mass_a", to_json(Q16::from_int(1) / rng.q16(0.5, 10))},
            {"inv_mass_b", ground ? Json(0) : to_json(Q16::from_int(1) / rng.q16(0.5, 10))},
            {"slop", to_json(P.slop)},
            {"percent", to_json(P.baumgarte)}};
      add(in, ground ? "against the ground (inv_mass_b = 0)" : "two bodies");
      continue;
    } else if (fn == "alignment_of") {
      const Json q = to_json(rng.unit_quat());
      in = {{"q", q}, {"up", k % 3 ? up : to_json(slope_normal(rng))}};
    } else if (fn == "righting") {
      // Tilted a little (the case righting is for) or anywhere; on the ground or a slope.
      Qt q =
          k % 2 ? rng.unit_quat() : normalize(Qt{Q16::from_raw(kOne), rng.q16(-0.2, 0.2), Q16{}, rng.q16(-0.2, 0.2)});
      const Json w = random_raw_vec(rng, -3, 3);
      const Json speed = to_json(rng.q16(0, 3));
      in = {{"R", to_json(rotation_matrix(q))},
            {"w", w},
            {"up", k % 3 ? up : to_json(slope_normal(rng))},
            {"speed", speed}};
    } else if (fn == "regime_damping") {
      in = {{"w", random_raw_vec(rng, -3, 3)}, {"alignment", to_json(rng.q16(0.9, 1))}};
    } else if (fn == "cancel_resting_velocity") {
      in = {{"v", random_raw_vec(rng, -0.5, 0.5)},
            {"v_support", k % 2 ? random_raw_vec(rng, -0.3, 0.3) : zero},
            {"n", k % 3 ? up : to_json(normalize(rng.vec(-1, 1)))},
            {"gap_speed", to_json(k % 4 ? rng.q16(0, 0.1) : Q16{})},
            {"rest_speed", to_json(P.rest_speed)}};
    } else if (fn == "support_weight") {
      in = {{"penetration", to_json(k % 3 ? -rng.q16(0, 0.003) : rng.q16(0, 0.01))}, {"width", to_json(P.support_fade)}};
    } else if (fn == "over_support") {
      // A box's bottom corners (or some of them) under a tilted or shifted
      // centre: 1-4 arms, some cases with the centre beyond them.
      const V h{rng.q16(0.1, 1), rng.q16(0.1, 1), rng.q16(0.1, 1)};
      const V shift{rng.q16(-1.2, 1.2) * h.x, Q16{}, rng.q16(-1.2, 1.2) * h.z};
      Json r = Json::array();
      const int count = 1 + k % 4;
      for (int c = 0; c < count; ++c)
        r.push_back(to_json(V{(c & 1 ? h.x : -h.x) + shift.x, -h.y, (c & 2 ? h.z : -h.z) + shift.z}));
      in = {{"r", r}, {"n", k % 3 ? up : to_json(normalize(V{rng.q16(-0.3, 0.3), Q16::from_int(1), rng.q16(-0.3, 0.3)}))},
            {"boundary_over", k % 2 == 0}};
    } else if (fn == "holds_off_support") {
      // A contact normal (towards the body) from any direction, from an awake or an immovable other side.
      in = {{"n", to_json(normalize(rng.vec(-1, 1)))}, {"immovable", k % 2 == 0},
            {"support_normal_min", to_json(P.support_normal_min)}};
    } else if (fn == "contact_closing_speed" || fn == "contact_closing_speed_pair") {
      // A point on a box (up to 1 m from its centre) anywhere in the scene;
      // the ground's normal or any other; b rising, turning, or at rest.
      const V pa = rng.vec(-5, 5), point = pa + rng.vec(-1, 1);
      in = {{"va", random_raw_vec(rng, -3, 3)}, {"wa", random_raw_vec(rng, -3, 3)}, {"pa", to_json(pa)},
            {"point", to_json(point)}, {"n", k % 3 ? up : to_json(normalize(rng.vec(-1, 1)))}};
      if (fn == "contact_closing_speed_pair") {
        in["vb"] = k % 4 ? random_raw_vec(rng, -3, 3) : zero;
        in["wb"] = k % 4 ? random_raw_vec(rng, -3, 3) : zero;
        in["pb"] = to_json(point + rng.vec(-1, 1));
      }
    } else if (fn == "support_impact") {
      // Gaps within support_fade and beyond slop, touching or penetrating
      // contacts; closing and separating speeds about rest_speed.
      in = {{"penetration", to_json(k % 3 ? -rng.q16(0, 0.003) : rng.q16(-0.0015, 0.001))},
            {"v_n", to_json(rng.q16(-0.6, 0.3))}};
    } else if (fn == "band_inverse") {
      // Half extents from tiny (the 1/64 m floor) to large.
      in = {{"largest_half", to_json(k % 4 == 0 ? rng.q16(0.001, 0.01) : rng.q16(0.01, 40))}};
    } else if (fn == "edge_band") {
      // Heights anywhere in Q16.16's range (the clamp), bands from fine to coarse.
      const double reach = k % 5 == 0 ? 32000 : 50;
      in = {{"y_lo", to_json(rng.q16(-reach, reach))}, {"y_hi", to_json(rng.q16(-reach, reach))},
            {"inv_band", to_json(band_inverse(k % 3 == 0 ? rng.q16(0.001, 0.02) : rng.q16(0.02, 40)))}};
    } else if (fn == "edge_key") {
      in = {{"lo", k * 37 % 1000}, {"hi", 1000 + k * 101 % 50000}, {"band", (k % 7 == 0 ? -16384 : 0) + k * 13 % 4000 - 2000}};
    } else if (fn == "edge_colour") {
      in = {{"top_lo", k % 6 - 1}, {"top_hi", (k / 6) % 6 - 1}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "settles_before") {
      // Two heights, often equal (the index decides), and two indices.
      const Q16 ys = rng.q16(-2, 2);
      in = {{"ys", to_json(ys)}, {"s", k % 5}, {"yi", to_json(k % 3 == 0 ? ys : rng.q16(-2, 2))}, {"i", (k / 5) % 5}};
    } else if (fn == "over_with_support") {
      in = {{"over", (k & 1) != 0}, {"support_before", (k & 2) != 0}, {"support_over", (k & 4) != 0}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "friction_holds") {
      // A ramp's normal (tilted 0-45 degrees about a random horizontal
      // axis), gravity down (or zero, or sideways), friction around tan a.
      const Q16 tilt = rng.q16(0, 1);
      const Q16 dir = rng.q16(-1, 1);
      const V ramp = normalize(V{tilt * dir, Q16::from_int(1), tilt * (Q16::from_int(1) - Num<Q16>::abs(dir))});
      const V g = k % 7 == 0 ? V{} : (k % 5 == 0 ? rng.vec(-10, 10) : V{Q16{}, Q16::from_double(-9.81), Q16{}});
      in = {{"g", to_json(g)}, {"n", to_json(ramp)}, {"mu", to_json(rng.q16(0, 1.2))}};
    } else if (fn == "friction_spare" || fn == "settle_limit") {
      const Q16 tilt = rng.q16(0, 1);
      const Q16 dir = rng.q16(-1, 1);
      const V ramp = normalize(V{tilt * dir, Q16::from_int(1), tilt * (Q16::from_int(1) - Num<Q16>::abs(dir))});
      const V g = k % 7 == 0 ? V{} : V{Q16{}, Q16::from_double(-9.81), Q16{}};
      in = {{"g", to_json(g)}, {"n", to_json(k % 4 == 0 ? V{Q16{}, Q16::from_int(1), Q16{}} : ramp)},
            {"mu", to_json(rng.q16(0, 1.2))}};
      if (fn == "friction_spare") in["dt"] = to_json(P.dt);
      if (fn == "settle_limit") {
        in["holds"] = k % 5 != 0;
        in["spare"] = k % 3 != 0;
      }
    } else if (fn == "fold_load_parent") {
      in = {{"state", k % 4 == 0 ? -1 : (k % 4 == 1 ? -2 : k % 3)}, {"other", k % 5 == 0 ? -2 : (k / 4) % 3}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "load_mass_add") {
      const Q16 cap = Q16::from_double(kLoadMassCap);
      in = {{"acc", to_json(k % 4 == 0 ? rng.q16(16000, 16384) : rng.q16(0.5, 20))},
            {"m", to_json(k % 3 == 0 ? rng.q16(100, 10000) : rng.q16(0.5, 20))}, {"cap", to_json(cap)}};
    } else if (fn == "load_offset_add") {
      // A child cube up to 1.5 m above and beside its parent, its own load's offset, a few kg.
      const V p0 = rng.vec(-5, 5);
      const Q16 cm = rng.q16(0.5, 8);
      in = {{"acc", to_json(rng.vec(-0.5, 0.5))}, {"child_mass", to_json(cm)}, {"mass", to_json(cm + rng.q16(0.5, 8))},
            {"child_p", to_json(p0 + V{rng.q16(-0.6, 0.6), rng.q16(0.5, 1.5), rng.q16(-0.6, 0.6)})},
            {"child_offset", to_json(rng.vec(-0.5, 0.5))}, {"p", to_json(p0)}};
    } else if (fn == "load_over_support") {
      // A box's bottom corners and a load's centre up to 1.2 half extents off
      // the body's centre: often beyond the edge.
      const V h{rng.q16(0.1, 1), rng.q16(0.1, 1), rng.q16(0.1, 1)};
      Json r = Json::array();
      const int count = 1 + k % 4;
      for (int c = 0; c < count; ++c) r.push_back(to_json(V{c & 1 ? h.x : -h.x, -h.y, c & 2 ? h.z : -h.z}));
      const V offset{rng.q16(-1.2, 1.2) * h.x, rng.q16(0, 2), rng.q16(-1.2, 1.2) * h.z};
      in = {{"r", r}, {"offset", to_json(offset)}, {"n", up}, {"boundary_over", k % 2 == 0}};
    } else if (fn == "leans") {
      in = {{"supported", (k & 1) != 0}, {"held", (k & 2) != 0}, {"over_contacts", (k & 4) != 0}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "load_tips") {
      in = {{"over", (k & 1) != 0}, {"child_tips", (k & 2) != 0}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "load_rests") {
      in = {{"child_tips", (k & 1) != 0}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "horizontal") {
      in = {{"v", random_raw_vec(rng, -40, 40)}};
    } else if (fn == "sleeper_load_parent") {
      in = {{"awake", (k & 1) != 0}, {"load_parent", k % 3 == 0 ? -1 : (k % 3 == 1 ? -2 : k % 7)},
            {"recorded_parent", k % 5 == 0 ? -1 : k % 11}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "sleeper_load_over_support") {
      // A sleeper's recorded bottom corners (horizontal parts) and a load's
      // centre up to 1.2 half extents off its centre: often beyond the edge.
      const V h{rng.q16(0.1, 1), rng.q16(0.1, 1), rng.q16(0.1, 1)};
      Json r = Json::array();
      const int count = 1 + k % 4;
      for (int c = 0; c < count; ++c) r.push_back(to_json(V{c & 1 ? h.x : -h.x, Q16{}, c & 2 ? h.z : -h.z}));
      const V offset{rng.q16(-1.2, 1.2) * h.x, rng.q16(0, 2), rng.q16(-1.2, 1.2) * h.z};
      in = {{"arms", r}, {"count", count}, {"offset", to_json(offset)}};
    } else if (fn == "visit_converged") {
      // A side's velocities before and after: each component within about
      // converged_speed of its old value, some beyond it.
      const V v0 = rng.vec(-3, 3), w0 = rng.vec(-3, 3);
      const Q16 e = Q16::from_double(1.0 / 32.0);  // an eps in use (the default, 0, never converges)
      const V dv{rng.q16(-1.3, 1.3) * e, rng.q16(-1.3, 1.3) * e, rng.q16(-1.3, 1.3) * e};
      const V dw{rng.q16(-1.3, 1.3) * e, rng.q16(-1.3, 1.3) * e, rng.q16(-1.3, 1.3) * e};
      in = {{"v0", to_json(v0)}, {"w0", to_json(w0)}, {"v", to_json(v0 + dv)}, {"w", to_json(w0 + dw)}, {"eps", to_json(e)}};
    } else if (fn == "settle_linear") {
      in = {{"v", random_raw_vec(rng, -0.4, 0.4)}, {"speed", to_json(rng.q16(0, 0.6))}};
    } else if (fn == "combined_restitution") {
      in = {{"e1", to_json(rng.q16(0, 1))}, {"e2", to_json(rng.q16(0, 1))}};
    } else if (fn == "low_speed_restitution") {
      in = {{"e", to_json(rng.q16(0, 1))},
            {"v_n", to_json(rng.q16(-2, 0.5))},
            {"restitution_min_speed", to_json(P.restitution_min_speed)}};
    } else if (fn == "combined_friction") {
      in = {{"mu1", to_json(rng.q16(0, 4))}, {"mu2", to_json(rng.q16(0, 4))}};
    } else if (fn == "sleep_candidate") {
      in = {{"supported", k % 4 != 0},
            {"speed", to_json(rng.q16(0, 0.07))},
            {"spin", to_json(k % 3 == 0 ? rng.q16(0, 3) : rng.q16(0, 0.07))},
            {"alignment", to_json(rng.q16(0.985, 1))},
            {"radius", to_json(k % 3 == 0 ? rng.q16(0.005, 0.6) : rng.q16(0.3, 2))}};
    } else if (fn == "sleep_stage") {
      in = {{"counter", k + 4 * (k / 6)}, {"drowsy_frames", P.drowsy_frames}, {"sleep_frames", P.sleep_frames}};
      add(in, "", {"Sweep"});
      continue;
    } else if (fn == "box_box_manifold") {
      // Two boxes near each other: resting tilted on top (face contacts), or
      // anywhere around (faces and edges), some beyond the tolerance.
      const V ha = rng.vec(0.1, 1), hb = rng.vec(0.1, 1);
      const bool stacked = k % 2 == 0;
      const Qt qa = stacked ? normalize(Qt{Q16::from_raw(kOne), rng.q16(-0.02, 0.02), rng.q16(-0.5, 0.5), rng.q16(-0.02, 0.02)})
                            : rng.unit_quat();
      const Qt qb = stacked ? normalize(Qt{Q16::from_raw(kOne), rng.q16(-0.02, 0.02), rng.q16(-0.5, 0.5), rng.q16(-0.02, 0.02)})
                            : rng.unit_quat();
      const V pa = rng.vec(-3, 3);
      const V pb = stacked ? pa + V{rng.q16(-0.2, 0.2), ha.y + hb.y + rng.q16(-0.03, 0.012), rng.q16(-0.2, 0.2)}
                           : pa + rng.vec(-1.6, 1.6);
      in = {{"pa", to_json(pa)}, {"Ra", to_json(rotation_matrix(qa))}, {"ha", to_json(ha)},
            {"pb", to_json(pb)}, {"Rb", to_json(rotation_matrix(qb))}, {"hb", to_json(hb)},
            {"tol", to_json(k % 3 == 0 ? rng.q16(0.01, 0.2) : P.contact_tolerance)}};
      add(in, stacked ? "b resting on a, tilted" : "b anywhere around a");
      continue;
    } else if (fn == "speculative_reach") {
      in = {{"v", random_raw_vec(rng, -80, 80)}, {"w", random_raw_vec(rng, k % 2 ? -200 : -5, k % 2 ? 200 : 5)},
            {"h", to_json(k % 4 == 3 ? rng.vec(100, 1000) : rng.vec(0.01, 2))}, {"dt", to_json(P.dt)}};
    } else if (fn == "immovable_tolerance") {
      const Q16 half_tol = P.contact_tolerance * Q16::from_double(0.5);
      const Q16 reach = speculative_reach(rng.vec(-80, 80), rng.vec(-20, 20), rng.vec(0.01, 2), P.dt);
      in = {{"growth", to_json(half_tol + reach)}, {"half_tol", to_json(half_tol)}, {"tol", to_json(P.contact_tolerance)}};
    } else if (fn == "support_moved") {
      const Qt q = rng.unit_quat();
      const V local = rng.vec(-1, 1), p0 = rng.vec(-10, 10);
      const V rest = p0 + rotation_matrix(q) * local;
      const V moved = p0 + V{rng.q16(-0.01, 0.01), rng.q16(-0.01, 0.01), rng.q16(-0.01, 0.01)};
      in = {{"p", to_json(k % 3 == 0 ? p0 : moved)}, {"R", to_json(rotation_matrix(q))}, {"local", to_json(local)},
            {"rest", to_json(rest)}, {"distance", to_json(P.wake_support_distance)}};
    } else if (fn == "support_moving") {
      const Qt q = rng.unit_quat();
      const V local = rng.vec(-1, 1), p0 = rng.vec(-10, 10);
      const V last = p0 + rotation_matrix(q) * local;
      const V moved = p0 + V{rng.q16(-0.002, 0.002), rng.q16(-0.002, 0.002), rng.q16(-0.002, 0.002)};
      in = {{"p", to_json(k % 3 == 0 ? p0 : moved)}, {"R", to_json(rotation_matrix(q))}, {"local", to_json(local)},
            {"last", to_json(last)}, {"step", to_json(P.sleep_linear * P.dt)}};
    } else if (fn == "correct_manifold_point") {
      // A resting pair: b's side immovable a third of the time (a support
      // pair's lower side), displacements of millimetres, depths -1..+30 mm.
      View A = random_view(rng);
      View B = k % 3 == 0 ? immovable() : random_view(rng);
      A.v = rng.vec(-0.005, 0.005);
      A.w = rng.vec(-0.01, 0.01);
      if (k % 3 != 0) B.v = rng.vec(-0.005, 0.005), B.w = rng.vec(-0.01, 0.01);
      in = {{"a", view_json(A)},
            {"b", view_json(B)},
            {"r1", random_raw_vec(rng, -1, 1)},
            {"r2", random_raw_vec(rng, -1, 1)},
            {"n", to_json(normalize(V{rng.q16(-0.2, 0.2), Q16::from_int(1), rng.q16(-0.2, 0.2)}))},
            {"penetration", to_json(rng.q16(-0.001, 0.03))},
            {"slop", to_json(P.slop)},
            {"percent", to_json(P.baumgarte)}};
      add(in, k % 3 == 0 ? "b immovable (a support pair's lower side)" : "both sides move");
      continue;
    } else if (fn == "wakes") {
      in = {{"v_n", to_json(rng.q16(-0.5, 0.2))}, {"penetration", to_json(rng.q16(0, 0.04))}};
    } else if (fn == "sdf_sample") {
      // Inside the shared grid [-1, 1] x [-0.5, 1] x [-1.5, 1.5] mostly; a quarter beyond it (clamped).
      in = {{"p", k % 4 == 3 ? random_raw_vec(rng, -2.5, 2.5)
                             : Json::array({rng.q16(-1, 1).raw(), rng.q16(-0.5, 1).raw(), rng.q16(-1.5, 1.5).raw()})}};
    } else if (fn == "state_hash") {
      Json bodies = Json::array();
      const int count = 1 + k % 4;
      for (int b = 0; b < count; ++b) {
        const V p = rng.vec(-50, 50), v = rng.vec(-5, 5), w = rng.vec(-3, 3);
        const Qt q = fixed_point_quat(rng);
        const int asleep = static_cast<int>(rng.range(0, 1));
        bodies.push_back(Json::array({p.x.raw(), p.y.raw(), p.z.raw(), q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw(),
                                      v.x.raw(), v.y.raw(), v.z.raw(), w.x.raw(), w.y.raw(), w.z.raw(), asleep}));
      }
      in = {{"bodies", bodies}};
    } else if (fn == "contact_target_velocity") {
      // Touching, a speculative gap that stays open, and one that closes
      // within the frame (a bounce from the gap); on the ground (g_n = 9.81)
      // or between two falling bodies (g_n = 0).
      const int kind = k % 3;
      const Q16 v = rng.q16(kind == 2 ? -3 : -2, kind == 0 ? 0.5 : 0);
      const Q16 gap = kind == 2 ? rng.q16(0.0001, 1) * Num<Q16>::min(-(v * P.dt), P.contact_tolerance)
                                : rng.q16(0.0001, 0.01);
      in = {{"penetration", to_json(kind == 0 ? rng.q16(0, 0.05) : -gap)},
            {"e", to_json(k % 4 == 3 ? Q16{} : rng.q16(0, 1))},
            {"v_n0", to_json(v)},
            {"g_n", to_json(k % 5 == 4 ? Q16{} : -P.gravity.y)}};
      add(in, kind == 0                ? "touching"
              : -(v * P.dt) > gap ? "speculative gap closing this frame"
                                  : "speculative gap staying open this frame");
      continue;
    } else if (fn == "manifold_visit") {
      // A box on the ground (its lowest 1..8 corners, n up) or on an SDF
      // surface (9 samples with their own normals), as the narrowphase finds them.
      const bool sdf = k % 3 == 2;
      const V half = rng.vec(0.1, 1.5);
      const Qt q =
          k % 2 ? rng.unit_quat() : normalize(Qt{Q16::from_raw(kOne), rng.q16(-0.1, 0.1), Q16{}, rng.q16(-0.1, 0.1)});
      View A;
      A.inv_mass = Q16::from_int(1) / rng.q16(0.5, 10);
      A.R = rotation_matrix(q);
      A.inv_inertia = box_inverse_inertia(half, A.inv_mass, Q16::from_int(3));
      A.v = V{rng.q16(-1, 1), rng.q16(-3, 0.2), rng.q16(-1, 1)};
      A.w = rng.vec(-2, 2);
      std::vector<V> arms;
      if (sdf) {
        for (int i = 0; i < 9; ++i) arms.push_back(A.R * V{rng.q16(-1, 1) * half.x, -half.y, rng.q16(-1, 1) * half.z});
      } else {
        for (int c = 0; c < 8; ++c)
          arms.push_back(A.R * V{c & 1 ? half.x : -half.x, c & 2 ? half.y : -half.y, c & 4 ? half.z : -half.z});
        std::stable_sort(arms.begin(), arms.end(), [](const V& x, const V& y) { return x.y < y.y; });
        arms.resize(static_cast<std::size_t>(1 + k % 8));
      }
      Json pts = Json::array();
      for (const V& r1 : arms) {
        const V normal = sdf ? slope_normal(rng) : V{Q16{}, Q16::from_int(1), Q16{}};
        pts.push_back(Json{{"r1", to_json(r1)},
                           {"n", to_json(normal)},
                           {"penetration", to_json(rng.q16(-0.01, 0.05))},
                           {"v_n0", to_json(dot(relative_velocity(A, r1, immovable(), V{}), normal))},
                           {"e", to_json(k % 4 == 0 ? rng.q16(0, 0.8) : Q16{})},
                           {"mu", to_json(rng.q16(0, 1))},
                           {"j_n", to_json(k % 2 ? rng.q16(0, 0.5) : Q16{})},
                           {"j_t", k % 5 == 1 ? random_raw_vec(rng, -0.05, 0.05) : zero}});
      }
      in = {{"a", view_json(A)}, {"points", pts}, {"effect_friction", k % 4 != 3}, {"effect_gravity", k % 5 != 4}};
      add(in, sdf ? "9 SDF samples" : std::to_string(arms.size()) + " ground corner(s)");
      continue;
    } else {
      throw std::logic_error("no case generator for formula " + fn);
    }
    add(in);
  }
  // Edge cases.
  if (fn == "aabb_overlap" || fn == "aabb_contact_point") {
    const Json h = Json::array({32768, 32768, 32768});
    add({{"p1", Json::array({0, kOne, 0})}, {"h1", h}, {"p2", zero}, {"h2", h}}, "touching faces: overlap 0, no hit",
        {"Edge"});
    add({{"p1", Json::array({0, kOne - 1, 0})}, {"h1", h}, {"p2", zero}, {"h2", h}}, "1 ulp overlap on y", {"Edge"});
    add({{"p1", zero}, {"h1", h}, {"p2", zero}, {"h2", h}}, "coincident: equal overlaps, axis 0, sign(0) = +1",
        {"Edge"});
    add({{"p1", Json::array({-100, -100, -200})}, {"h1", h}, {"p2", zero}, {"h2", h}}, "negative delta: normal -1",
        {"Edge"});
  } else if (fn == "integrate_orientation") {
    add({{"q", Json::array({kOne, 0, 0, 0})}, {"w", zero}, {"half_dt", to_json(P.half_dt)}}, "no spin: identity stays",
        {"Edge"});
  } else if (fn == "cell_coord") {
    for (std::int32_t x : {-1, 0, 4 * kOne - 1, 4 * kOne, -4 * kOne, -4 * kOne - 1})
      add({{"x", x}, {"inv_cell_size", to_json(P.inv_cell_size)}}, "cell boundary (floor)", {"Edge"});
  } else if (fn == "friction_step") {
    const View A = immovable();
    add({{"a", view_json(A)},
         {"b", view_json(A)},
         {"r1", zero},
         {"r2", zero},
         {"n", up},
         {"mu", 32768},
         {"j_n", kOne},
         {"j_t", zero}},
        "no tangential velocity: no step", {"Edge"});
  } else if (fn == "righting") {
    add({{"R", to_json(identity())}, {"w", Json::array({100, -200, 300})}, {"up", up}, {"speed", 0}},
        "aligned: axis below 2^-12, w unchanged", {"Edge"});
  } else if (fn == "sdf_sample") {
    add({{"p", Json::array({-kOne, -32768, -3 * 32768})}}, "the grid's min corner", {"Edge"});
    add({{"p", Json::array({kOne, kOne, 3 * 32768})}}, "the grid's max corner", {"Edge"});
  } else if (fn == "holds_off_support") {
    const Q16 m = P.support_normal_min;
    for (const bool imm : {false, true}) {
      add({{"n", to_json(V{Q16{}, m, Q16{}})}, {"immovable", imm}, {"support_normal_min", to_json(m)}},
          "n.y exactly support_normal_min: a support", {"Edge"});
      add({{"n", to_json(V{Q16{}, -m, Q16{}})}, {"immovable", imm}, {"support_normal_min", to_json(m)}},
          "n.y exactly -support_normal_min: from above", {"Edge"});
    }
  } else if (fn == "regime_damping") {
    for (const Q16 a : {P.align_fine, P.align_good, P.align_fair})
      add({{"w", Json::array({kOne, -kOne, 3})}, {"alignment", to_json(a)}},
          "alignment exactly at a threshold (strict >)", {"Edge"});
  } else if (fn == "sleep_candidate") {
    const Json r1 = to_json(Q16::from_int(1));
    add({{"supported", true}, {"speed", to_json(P.sleep_linear)}, {"spin", 0}, {"alignment", kOne}, {"radius", r1}},
        "speed exactly sleep_linear (strict <)", {"Edge"});
    add({{"supported", true}, {"speed", 0}, {"spin", 0}, {"alignment", to_json(P.sleep_alignment)}, {"radius", r1}},
        "alignment exactly sleep_alignment (strict >)", {"Edge"});
    add({{"supported", true}, {"speed", 0}, {"spin", 0}, {"alignment", kOne}, {"radius", r1}}, "at rest and flat", {"Edge"});
    add({{"supported", true}, {"speed", 0}, {"spin", to_json(P.sleep_angular)}, {"alignment", kOne},
         {"radius", to_json(P.sleep_small_radius)}},
        "radius exactly sleep_small_radius: the |w| test (strict <)", {"Edge"});
    add({{"supported", true}, {"speed", 0}, {"spin", to_json(Q16::from_int(2))}, {"alignment", kOne},
         {"radius", to_json(Q16::from_double(0.0125))}},
        "a small body: |w| r exactly sleep_corner_speed (strict <)", {"Edge"});
  } else if (fn == "wakes") {
    add({{"v_n", to_json(-P.wake_speed)}, {"penetration", 0}}, "approach exactly wake_speed (strict >)", {"Edge"});
    add({{"v_n", 0}, {"penetration", to_json(P.wake_penetration)}}, "penetration exactly wake_penetration (strict >)",
        {"Edge"});
  } else if (fn == "friction_holds") {
    // tan(a) = mu exactly: a 3-4-5 ramp (n = (-3/5, 4/5, 0)), g = (0, -10, 0): |gt| = 6, -gn = 8.
    const Json n345 = to_json(V{Q16::from_double(-0.6), Q16::from_double(0.8), Q16{}});
    const Json g10 = to_json(V{Q16{}, Q16::from_int(-10), Q16{}});
    add({{"g", g10}, {"n", n345}, {"mu", to_json(Q16::from_double(0.75))}}, "friction exactly tan a: holds (<=)", {"Edge"});
    add({{"g", g10}, {"n", n345}, {"mu", to_json(Q16::from_double(0.75) - Q16::from_raw(1))}},
        "friction 1 ulp below tan a: driven", {"Edge"});
    add({{"g", to_json(V{})}, {"n", n345}, {"mu", 0}}, "no gravity: holds", {"Edge"});
    add({{"g", g10}, {"n", up}, {"mu", 0}}, "flat, frictionless: holds (nothing pulls along it)", {"Edge"});
    add({{"g", to_json(V{Q16{}, Q16::from_int(10), Q16{}})}, {"n", up}, {"mu", kOne}}, "gravity pulls it off: not held",
        {"Edge"});
  } else if (fn == "load_mass_add") {
    const Q16 cap = Q16::from_double(kLoadMassCap);
    add({{"acc", to_json(cap - Q16::from_int(2))}, {"m", to_json(Q16::from_int(2))}, {"cap", to_json(cap)}},
        "reaches the cap exactly", {"Edge"});
    add({{"acc", to_json(cap - Q16::from_int(2))}, {"m", to_json(Q16::from_int(2) + Q16::from_raw(1))}, {"cap", to_json(cap)}},
        "1 ulp beyond the cap: the cap", {"Edge"});
  } else if (fn == "sleeper_load_over_support") {
    const Q16 h = Q16::from_double(0.5);
    Json square = Json::array();
    for (int c = 0; c < 4; ++c) square.push_back(to_json(V{c & 1 ? h : -h, Q16{}, c & 2 ? h : -h}));
    add({{"arms", square}, {"count", 4}, {"offset", to_json(V{h, Q16::from_int(1), Q16{}})}},
        "the load's centre on the edge: over (a sleeper does not turn)", {"Edge"});
    add({{"arms", square}, {"count", 4}, {"offset", to_json(V{h + Q16::from_raw(1), Q16{}, Q16{}})}},
        "1 ulp beyond the edge: not over", {"Edge"});
    add({{"arms", square}, {"count", 17}, {"offset", to_json(V{Q16::from_int(3), Q16{}, Q16{}})}},
        "more than 16 points (many): over", {"Edge"});
    add({{"arms", Json::array()}, {"count", 0}, {"offset", to_json(V{Q16::from_int(3), Q16{}, Q16{}})}},
        "no points recorded: over", {"Edge"});
  } else if (fn == "support_impact") {
    add({{"penetration", to_json(-P.slop)}, {"v_n", to_json(-P.rest_speed - Q16::from_raw(1))}},
        "a gap of exactly slop is speculative; 1 ulp faster than rest_speed: an impact", {"Edge"});
    add({{"penetration", to_json(-P.slop - Q16::from_raw(1))}, {"v_n", to_json(-P.rest_speed)}},
        "closing at exactly rest_speed (strict <): a support point", {"Edge"});
    add({{"penetration", to_json(Q16::from_raw(1) - P.slop)}, {"v_n", to_json(-Q16::from_int(5))}},
        "1 ulp within slop: touching, a support point however fast", {"Edge"});
  } else if (fn == "support_weight") {
    add({{"penetration", 0}, {"width", to_json(P.support_fade)}}, "touching: weight 1", {"Edge"});
    add({{"penetration", to_json(Q16::from_raw(1) - P.support_fade)}, {"width", to_json(P.support_fade)}},
        "1 ulp inside the width: the smallest weight", {"Edge"});
    add({{"penetration", to_json(-P.support_fade)}, {"width", to_json(P.support_fade)}},
        "a gap of exactly the width: weight 0", {"Edge"});
    add({{"penetration", 1}, {"width", 0}}, "width 0: a touching contact weighs 1 (no division)", {"Edge"});
    add({{"penetration", -1}, {"width", 0}}, "width 0: a gap weighs 0 (no division)", {"Edge"});
  } else if (fn == "visit_converged") {
    const Json z = to_json(V{});
    const Q16 e = Q16::from_double(1.0 / 32.0);
    const Json eps = to_json(e);
    add({{"v0", z}, {"w0", z}, {"v", to_json(V{e, Q16{}, Q16{}})}, {"w", z}, {"eps", eps}},
        "a change of exactly eps: not converged (strict <)", {"Edge"});
    add({{"v0", z}, {"w0", z}, {"v", z}, {"w", to_json(V{Q16{}, Q16{}, e - Q16::from_raw(1)})}, {"eps", eps}},
        "a spin change 1 ulp below eps: converged", {"Edge"});
    add({{"v0", z}, {"w0", z}, {"v", z}, {"w", z}, {"eps", 0}}, "eps 0: never converged", {"Edge"});
  } else if (fn == "over_support") {
    const Json a = Json::array({kOne / 2, -kOne / 2, kOne / 2}), b = Json::array({-kOne / 2, -kOne / 2, -kOne / 2});
    const Json c = Json::array({kOne / 2, -kOne / 2, -kOne / 2});
    for (const bool bo : {false, true}) {
      const std::string on = bo ? "over (boundary, boundary_over)" : "not over (boundary)";
      add({{"r", Json::array({a, b})}, {"n", up}, {"boundary_over", bo}}, "the centre on the segment between two arms: " + on,
          {"Edge"});
      add({{"r", Json::array({Json::array({0, -kOne / 2, 0})})}, {"n", up}, {"boundary_over", bo}},
          "one arm straight below the centre: " + on, {"Edge"});
      add({{"r", Json::array({a, b, c})}, {"n", up}, {"boundary_over", bo}},
          "the centre on an edge of the triangle of three arms: " + on, {"Edge"});
      add({{"r", Json::array({a})}, {"n", up}, {"boundary_over", bo}}, "one arm beside the centre: not over", {"Edge"});
    }
    add({{"r", Json::array({Json::array({0, -kOne / 2, 0}), a, Json::array({-kOne / 2, -kOne / 2, kOne / 2}),
                            Json::array({0, -kOne / 2, -kOne / 2})})},
         {"n", up}, {"boundary_over", false}},
        "an arm straight below the centre, three around it: over", {"Edge"});
    add({{"r", Json::array()}, {"n", up}, {"boundary_over", false}}, "no arms: over (nothing to tip about)", {"Edge"});
  } else if (fn == "cancel_resting_velocity") {
    add({{"v", Json::array({3, -kOne / 10, 0})}, {"v_support", zero}, {"n", up}, {"gap_speed", kOne / 20},
         {"rest_speed", to_json(P.rest_speed)}},
        "approach faster than the gap closes: kept at -gap_speed", {"Edge"});
  } else if (fn == "low_speed_restitution") {
    add({{"e", 32768},
         {"v_n", to_json(-P.restitution_min_speed)},
         {"restitution_min_speed", to_json(P.restitution_min_speed)}},
        "approach exactly restitution_min_speed (strict >): no bounce", {"Edge"});
  } else if (fn == "contact_target_velocity") {
    const Q16 g = -P.gravity.y, one = Q16::from_int(1), half = Q16::from_double(0.5), v = -half;
    const Q16 closes = -(v * P.dt);  // the gap -(v_n0 dt) that closes exactly this frame (below contact_tolerance)
    auto tv = [](Q16 pen, Q16 e, Q16 v_n0, Q16 g_n) {
      return Json{{"penetration", to_json(pen)}, {"e", to_json(e)}, {"v_n0", to_json(v_n0)}, {"g_n", to_json(g_n)}};
    };
    add(tv(Q16{}, half, v, g), "penetration exactly 0: touching, target -e v_n0", {"Edge"});
    add(tv(Q16{}, half, one, g), "separating (v_n0 > 0, clamped to 0): target 0", {"Edge"});
    add(tv(Q16::from_raw(-1), half, Q16::from_raw(-1), g), "gap of 1 ulp, -(v_n0 dt) = 1 ulp: stays open",
        {"Edge"});
    add(tv(-closes, one, v, g), "gap exactly -(v_n0 dt) (strict >): stays open, penetration * inv_dt", {"Edge"});
    add(tv(-closes + Q16::from_raw(1), one, v, g), "gap 1 ulp below -(v_n0 dt): bounces from the gap", {"Edge"});
    add(tv(-closes + Q16::from_raw(1), one, v, Q16{}), "bounce from the gap between falling bodies (g_n = 0): ev",
        {"Edge"});
    add(tv(-closes + Q16::from_raw(1), Q16{}, v, g), "closing gap, e = 0: penetration * inv_dt", {"Edge"});
    add(tv(Q16::from_double(-0.01), Q16::from_double(0.05), -one, g),
        "rise from the gap above e |v_n0|: target 0 (a bounce from a gap adds no energy)", {"Edge"});
    add(tv(Q16::from_double(-0.01), one, Q16::from_int(-200), g), "e |v_n0| above 128 m/s: ev, uncorrected",
        {"Edge"});
    add(tv(Q16::from_double(-0.005), half, Q16::from_int(-2), Q16::from_int(-5)),
        "negative g_n counts as 0: target -e v_n0", {"Edge"});
  } else if (fn == "manifold_visit") {
    // A box resting on the ground, level: the corners with y = -half.y (or all
    // 8, sunk) at 1 mm penetration, landing at gravity * dt, nothing accumulated.
    auto resting = [&](const V& half, int corners, bool friction) {
      View A;
      A.R = identity();
      A.inv_mass = Q16::from_int(1);
      A.inv_inertia = box_inverse_inertia(half, A.inv_mass, Q16::from_int(3));
      A.v = P.gravity_dt;
      Json pts = Json::array();
      for (int c = 0; c < corners; ++c) {
        const V r1{c & 1 ? half.x : -half.x, c & 4 ? half.y : -half.y, c & 2 ? half.z : -half.z};
        pts.push_back(Json{{"r1", to_json(r1)},
                           {"n", up},
                           {"penetration", to_json(Q16::from_double(0.001))},
                           {"v_n0", to_json(A.v.y)},
                           {"e", 0},
                           {"mu", 32768},
                           {"j_n", 0},
                           {"j_t", zero}});
      }
      return Json{{"a", view_json(A)}, {"points", pts}, {"effect_friction", friction}, {"effect_gravity", true}};
    };
    const V cube = Q16::from_double(0.5) * V{Q16::from_int(1), Q16::from_int(1), Q16::from_int(1)};
    const V tall{Q16::from_double(0.1), Q16::from_int(1), Q16::from_double(0.1)};
    add(resting(cube, 1, true), "one point: split 1", {"Edge"});
    add(resting(cube, 2, true), "unit cube on an edge: o = 0.5, split 1 (max(1, o))", {"Edge"});
    add(resting(cube, 4, false), "unit cube flat: o = 1 exactly, split 1", {"Edge"});
    add(resting(cube, 4, true), "unit cube flat, with friction", {"Edge"});
    add(resting(cube, 8, true), "unit cube, all 8 corners sunk: o = 2", {"Edge"});
    add(resting(tall, 4, true), "tall thin box (0.2 x 2 x 0.2 m) standing: o about 3.8", {"Edge"});
  } else if (fn == "baumgarte_correction") {
    add({{"pa", zero},
         {"pb", zero},
         {"n", up},
         {"penetration", to_json(P.slop)},
         {"inv_mass_a", kOne},
         {"inv_mass_b", 0},
         {"slop", to_json(P.slop)},
         {"percent", to_json(P.baumgarte)}},
        "penetration = slop: no correction", {"Edge"});
  }
  return out;
}

// Shared inputs of a group: the Params fields its formula reads, or the grid.
Json shared_for(const std::string& fn) {
  if (fn == "righting")
    return shared_params({"kp", "kd_dt", "speed_factor_min", "speed_factor_max", "righting_min_axis"});
  if (fn == "regime_damping")
    return shared_params({"align_fine", "align_good", "align_fair", "damp_fine", "damp_good", "damp_fair"});
  if (fn == "settle_linear") return shared_params({"settle_speed", "settle_factor"});
  if (fn == "sleep_candidate")
    return shared_params({"sleep_linear", "sleep_angular", "sleep_alignment", "sleep_small_radius", "sleep_corner_speed"});
  if (fn == "support_impact") return shared_params({"slop", "rest_speed"});
  if (fn == "settle_limit") return shared_params({"settle_speed", "dt"});
  if (fn == "wakes") return shared_params({"wake_speed", "wake_penetration"});
  if (fn == "contact_target_velocity") return shared_params({"dt", "inv_dt"});
  if (fn == "manifold_visit") return shared_params({"dt", "inv_dt", "gravity"});
  if (fn == "sdf_sample") {
    // A 5 x 4 x 7 grid over [-1, 1] x [-0.5, 1] x [-1.5, 1.5]; values: the
    // distance to a sphere of radius 0.8 at (0.1, 0.2, -0.3), in Q16.
    const V lo{Q16::from_double(-1), Q16::from_double(-0.5), Q16::from_double(-1.5)};
    const V hi{Q16::from_double(1), Q16::from_double(1), Q16::from_double(1.5)};
    const std::array<int, 3> nn = {5, 4, 7};
    Json grid = sdf_grid_json(lo, hi, nn);
    const V spacing = vec_at(grid, "spacing", "sdf_sample");
    const V c{Q16::from_double(0.1), Q16::from_double(0.2), Q16::from_double(-0.3)};
    Json values = Json::array();
    for (int k = 0; k < nn[2]; ++k)
      for (int j = 0; j < nn[1]; ++j)
        for (int i = 0; i < nn[0]; ++i) {
          const V p{lo.x + spacing.x * Q16::from_int(i), lo.y + spacing.y * Q16::from_int(j),
                    lo.z + spacing.z * Q16::from_int(k)};
          values.push_back((length(p - c) - Q16::from_double(0.8)).raw());
        }
    grid["values"] = std::move(values);
    return grid;
  }
  return Json::object();
}

Json merged(const Json& shared, const Json& in) {
  Json m = shared.is_object() ? shared : Json::object();
  for (auto it = in.begin(); it != in.end(); ++it) m[it.key()] = it.value();
  return m;
}

}  // namespace

std::vector<std::string> formula_functions() {
  std::vector<std::string> names;
  for (const Formula& f : formulas()) names.emplace_back(f.function);
  return names;
}

Json compute_formula(const std::string& function, const Json& in, const std::string& path) {
  const Formula* f = find_formula(function);
  if (f == nullptr) throw FormatError(path + ": unknown formula \"" + function + "\"");
  q16_clear_status();
  Json out = f->compute(in, path + ".in");
  const std::uint32_t status = q16_take_status();
  return Json{{"out", std::move(out)}, {"status", status_to_json(status)}};
}

Json generate_formulas() {
  Rng rng(0x666f726d756c6173ULL);  // "formulas"
  Json groups = Json::array();
  long id = 0;
  for (const Formula& f : formulas()) {
    const Json shared = shared_for(f.function);
    Json tests = Json::array();
    for (Case& c : cases_for(f.function, rng)) {
      const Json res = compute_formula(f.function, merged(shared, c.in), f.function);
      Json t;
      t["tcId"] = ++id;
      t["comment"] = c.comment;
      t["flags"] = c.flags;
      t["in"] = c.in;
      t["out"] = res["out"];
      t["status"] = res["status"];
      tests.push_back(std::move(t));
    }
    Json g;
    g["type"] = "Formula";
    g["function"] = f.function;
    g["equations"] = f.equations;
    g["description"] = f.description;
    g["shared"] = shared;
    g["tests"] = std::move(tests);
    groups.push_back(std::move(g));
  }
  Json doc;
  doc["algorithm"] = "lockstep physics formulas (Q16.16)";
  doc["level"] = 2;
  doc["schema"] = "lockstep_formulas_schema_v1.json";
  doc["schemaVersion"] = kSchemaVersion;
  doc["generatorVersion"] = generator_version();
  doc["numberOfTests"] = id;
  doc["header"] = Json::array(
      {"Level 2 of the lockstep test vectors: single equations of docs/SPEC.md on the fixed engine, bit for bit.",
       "Each group is one function (its equations, and its computation in order in description); a test's inputs",
       "are its in object merged over the group's shared object. Raw Q16.16 as integers, as in arithmetic.json.",
       "A body view (a, b) is {v, w, inv_mass, R, inv_inertia}: the contact-side view of SPEC 0.1; the ground is",
       "the immovable view (zeros, R = identity). Every intermediate is Q16 with the rules of arithmetic.json."});
  doc["notes"] = Json{{"Random", "Pseudo-random inputs in the physical ranges of the built-in scenes."},
                      {"Edge", "A boundary of the formula (a tie, touching boxes, a threshold, an undefined axis)."},
                      {"Defaults", "The default constants of Appendix A."},
                      {"Modified", "Constants other than the defaults."},
                      {"Sweep", "Consecutive integer inputs across the thresholds."}};
  doc["testGroups"] = std::move(groups);
  return doc;
}

Verdict verify_formulas(const Json& doc, const std::string& file_name) {
  Verdict v;
  v.file = file_name;
  try {
    if (int_at(doc, "schemaVersion", "") != kSchemaVersion)
      throw FormatError("schemaVersion " + member(doc, "schemaVersion", "").dump() + " is not supported");
    const Json& groups = member(doc, "testGroups", "");
    std::size_t count = 0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const std::string gp = "testGroups[" + std::to_string(g) + "]";
      const std::string fn = string_at(groups[g], "function", gp);
      const Json shared = groups[g].contains("shared") ? groups[g]["shared"] : Json::object();
      const Json& tests = member(groups[g], "tests", gp);
      for (std::size_t t = 0; t < tests.size(); ++t) {
        const std::string tp = gp + ".tests[" + std::to_string(t) + "]";
        const Json& test = tests[t];
        const long id = static_cast<long>(int_at(test, "tcId", tp));
        const Json got = compute_formula(fn, merged(shared, member(test, "in", tp)), tp);
        const Json expected{{"out", member(test, "out", tp)}, {"status", member(test, "status", tp)}};
        const Difference d = first_difference(expected, got, "");
        ++count;
        if (d.found) {
          v.ok = false;
          v.tc_id = id;
          v.field = d.path;
          v.message = file_name + ": tcId " + std::to_string(id) + " (" + fn + "): " + d.path + " expected " +
                      d.expected + ", got " + d.actual;
          v.checked = count;
          return v;
        }
      }
    }
    if (count != static_cast<std::size_t>(int_at(doc, "numberOfTests", "")))
      throw FormatError("numberOfTests is " + doc["numberOfTests"].dump() + " but the file holds " +
                        std::to_string(count) + " tests");
    v.checked = count;
  } catch (const FormatError& e) {
    v.ok = false;
    v.message = file_name + ": malformed: " + e.what();
  } catch (const nlohmann::json::exception& e) {
    v.ok = false;
    v.message = file_name + ": malformed: " + e.what();
  }
  return v;
}

}  // namespace lockstep::vectors
