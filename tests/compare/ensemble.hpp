// A chaotic scene and how it is judged (tests/compare: AgreementProp,
// ValidationTest). Chaotic: the scene's outcome (rest position, face up,
// supports, sleep frame of a body) changes when double starts it from states
// nudged by the differences the engines under test start to differ by, or
// double parts from the mp truth. Then no engine can be asked to follow
// double body by body; each engine must end every body as some member of the
// ensemble ends it.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/compare/resting.hpp"
#include "lockstep/fixed/q16.hpp"
#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/scene.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep_test {

using namespace lockstep;
using namespace lockstep::compare;

// The scene as the fixed engine sees it: every constant rounded to Q16.16
// (eq 22), as the bodies' values already are (scene_gen.hpp), so that double
// and mp run the same model (Δt = 1092/65536 s, g = 642908/65536 m/s^2, ...)
// and the property judges the number types, not the fixed engine's model
// difference (docs/SPEC.md 7.1, Fix 5).
inline lockstep::Scene as_fixed_sees_it(lockstep::Scene s) {
  auto q = [](double& x) { x = lockstep::Q16::from_double(x).to_double(); };
  lockstep::Constants& c = s.constants;
  for (double* x : {&c.dt, &c.linear_damping, &c.angular_damping, &c.cell_size, &c.slop, &c.baumgarte, &c.contact_tolerance, &c.converged_speed, &c.kp, &c.kd, &c.speed_factor_min, &c.speed_factor_max, &c.support_normal_min, &c.align_fine, &c.align_good, &c.align_fair, &c.damp_fine, &c.damp_good, &c.damp_fair, &c.rest_speed, &c.restitution_min_speed, &c.settle_speed, &c.settle_damping, &c.sleep_linear, &c.sleep_angular, &c.sleep_alignment, &c.drowsy_damping, &c.wake_speed, &c.wake_penetration, &c.wake_support_distance, &c.gravity.x, &c.gravity.y, &c.gravity.z}) q(*x);
  q(s.ground.height);
  return s;
}

// The scene the IEEE engines (double, mp and the ensemble) run: the fixed
// engine's per-frame products as constants. The fixed engine applies g dt,
// 1 - lambda dt and kd dt (Params::from) rounded to Q16.16 once, not g and dt:
// its velocity steps by round(g dt) = 10713 ulps a frame where double's steps
// by 10712.517 (9.8104 against 9.8100 m/s^2), so a box dropped 1.7 m lands
// 1.4e-4 m lower and 8e-4 m/s faster in fixed, every time, the same way. That
// is the fixed model, not a rounding: double runs it here (g' = round(g dt)/dt,
// lambda' = (1 - round(1 - lambda dt))/dt, kd' = round(kd dt)/dt), as it runs
// the constants rounded to Q16.16 (as_fixed_sees_it). What is left between the
// two is the rounding of the state each frame, which the ensemble spans.
inline Scene ieee_model_of(const Scene& scene) {
  Scene s = scene;
  const Params<Q16> P = Params<Q16>::from(scene.constants);
  Constants& c = s.constants;
  const double dt = P.dt.to_double();
  c.gravity = {P.gravity_dt.x.to_double() / dt, P.gravity_dt.y.to_double() / dt, P.gravity_dt.z.to_double() / dt};
  c.linear_damping = (1.0 - P.linear_damping_factor.to_double()) / dt;
  c.angular_damping = (1.0 - P.angular_damping_factor.to_double()) / dt;
  c.kd = P.kd_dt.to_double() / dt;
  return s;
}

// The findings of `engine` against `reference` (two tracks of the same scene,
// however each was started) that fail the per-body checks: rest position,
// face up, supports and sleep frame. Trajectory findings are left out: the
// tracks' frame statistics were recorded against different baselines.
inline std::vector<Finding> per_body_failures(const Scene& scene, const EngineTrack& reference, const EngineTrack& engine,
                                       const CompareTolerances& t) {
  Recording r;
  r.scene = scene;
  r.frames = scene.frames;
  r.baseline = 0;
  r.engines = {reference, engine};
  CompareTolerances bodies = t;
  bodies.judge = Judge::bodies;
  std::vector<Finding> out;
  for (const Finding& f : judge(r, bodies).failures())
    if (f.check != "trajectory") out.push_back(f);
  return out;
}

// The ensemble a chaotic scene is judged against: double from the scene as
// given, the mp truth, and double from the scene with every body's position,
// orientation, velocity and spin nudged, 16 sign patterns at each of four
// scales: 2^-22 (float's rounding of a state of a few metres), 2^-16 (one
// Q16.16 ulp, the fixed engine's resolution), 2^-13 and 2^-10 (8 and 64 ulps:
// what the fixed engine's state comes to differ from double's by before a
// knife edge, e.g. 1.4e-4 m and 8e-4 m/s after a 1.7 m drop, the rounding
// of the state each frame accumulating). A knife edge that such a difference
// crosses is decided by the rounding, and each side of it is a right answer:
// a landing corner 1.6e-4 m inside or outside the speculative distance
// (contact_tolerance, eq 97) sends a box off at 1.35 or 1.67 m/s; a landing
// alignment within 2e-5 of align_fine (eq 72) damps the spin by 0.4 or 0.7;
// the last hops of a bouncing box (bounce) end 327 to 415 frames in when its
// height is nudged by 1.5e-5 m.
struct Ensemble {
  std::vector<EngineTrack> members;  // members[0]: double; members[1]: mp; then the nudged runs
  std::vector<std::string> labels;
};

inline Scene nudged(const Scene& scene, double scale, int member) {
  Scene s = scene;
  // A fixed sign pattern per member, body and component (no randomness: a
  // case reproduces from its scene alone).
  // splitmix64 of (member, body, component): every member a different pattern.
  auto sign = [&](std::size_t body, int component) {
    std::uint64_t z = (static_cast<std::uint64_t>(member) << 40) ^ (static_cast<std::uint64_t>(body) << 8) ^
                      static_cast<std::uint64_t>(component);
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (z >> 63) ? scale : -scale;
  };
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    BodyDesc& b = s.bodies[i];
    b.position.x += sign(i, 0);
    b.position.y += sign(i, 1);  // down: a corner may start 2^-10 m in the floor (the slop is 2^-10)
    b.position.z += sign(i, 2);
    b.orientation.x += sign(i, 3);
    b.orientation.y += sign(i, 4);
    b.orientation.z += sign(i, 5);
    b.velocity.x += sign(i, 6);
    b.velocity.y += sign(i, 7);
    b.velocity.z += sign(i, 8);
    b.angular_velocity.x += sign(i, 9);
    b.angular_velocity.y += sign(i, 10);
    b.angular_velocity.z += sign(i, 11);
  }
  return s;
}

// `recorder(scene, engines)` records the scene on the engines with double as
// the baseline (record(), or a recorder that runs double on another model).
using Recorder = std::function<Recording(const Scene&, const std::vector<std::string>&)>;
// With `around_fixed_model`, the nudges are made around the scene and around
// the fixed engine's model of it (for a recorder that runs double on the
// scene as given).
inline Ensemble ensemble_of(const Scene& scene, const Recorder& recorder, bool around_fixed_model) {
  Ensemble e;
  const Recording truth = recorder(scene, {"double", "mp"});
  e.members = truth.engines;
  e.labels = {"double", "mp"};
  constexpr int kMembersPerScale = 16;
  // Around the scene and, where it differs, around the fixed engine's model
  // of it (its constants and per-frame products rounded to Q16.16): the
  // engines also differ by that much (docs/SPEC.md 7.1).
  std::vector<Scene> centres{scene};
  const Scene fixed_model = ieee_model_of(as_fixed_sees_it(scene));
  if (around_fixed_model && !scene_difference(scene, fixed_model).empty()) centres.push_back(fixed_model);
  for (const Scene& centre : centres)
  for (const double scale : {0x1p-22, 0x1p-16, 0x1p-13, 0x1p-10}) {
    for (int k = 0; k < kMembersPerScale; ++k) {
      e.members.push_back(recorder(nudged(centre, scale, k), {"double"}).engines[0]);
      e.labels.push_back("double nudged by 2^" + std::to_string(std::ilogb(scale)) + " (pattern " + std::to_string(k) +
                         ")");
    }
  }
  return e;
}

// Chaotic: some member of the ensemble parts from double itself (a rest
// position, face, support or sleep frame beyond the property's tolerances).
inline bool chaotic(const Scene& scene, const Ensemble& e, const CompareTolerances& t) {
  for (std::size_t m = 1; m < e.members.size(); ++m)
    if (!per_body_failures(scene, e.members[0], e.members[m], t).empty()) return true;
  return false;
}

// A chaotic scene, judged by the statistics of its ensemble: every body of
// the engine must end within the spread of the members' outcomes for that
// body: its rest position within the members' range on each axis widened by
// the rest tolerance, a face up and supports that some member ends with, and
// asleep at a frame within the members' range of sleep frames widened by the
// sleep tolerance (or awake at the end, as some member is). The outcomes of
// a chaotic scene spread continuously (a box that lands on another corner
// slides further: members end 0.51-0.54 m in x, -0.78 to -0.85 m in z), so
// the range, not the nearest member, is what a finite ensemble measures. It
// fails when the engine ends a body outside that spread (it gains energy,
// sinks, slides too far, sleeps late or never).
inline std::vector<std::string> outside_ensemble(const Scene& scene, const Ensemble& e, const EngineTrack& engine,
                                                 const CompareTolerances& t) {
  auto fmt = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", x);
    return std::string(buf);
  };
  std::vector<std::string> out;
  const auto mine = resting_states(scene, engine.final_bodies, t.support_gap, t.flat_alignment);
  std::vector<std::vector<RestingState>> members;
  for (const EngineTrack& m : e.members)
    members.push_back(resting_states(scene, m.final_bodies, t.support_gap, t.flat_alignment));
  for (std::size_t i = 0; i < mine.size(); ++i) {
    const std::string body = engine.name + ": body " + std::to_string(i) + " ";
    for (int a = 0; a < 3; ++a) {
      double lo = members[0][i].p[a], hi = lo;
      for (const auto& m : members) {
        lo = std::min(lo, m[i].p[a]);
        hi = std::max(hi, m[i].p[a]);
      }
      if (mine[i].p[a] < lo - t.rest_position || mine[i].p[a] > hi + t.rest_position)
        out.push_back(body + "rests at " + "xyz"[a] + " = " + fmt(mine[i].p[a]) + " m, outside the ensemble's [" + fmt(lo) +
                      ", " + fmt(hi) + "] m +- " + fmt(t.rest_position) + " m");
    }
    bool face = false, supports = false;
    for (const auto& m : members) {
      face = face || m[i].face.label == mine[i].face.label;
      supports = supports || m[i].supports == mine[i].supports;
    }
    if (!face) out.push_back(body + "ends with face " + mine[i].face.label + " up, which no member of the ensemble does");
    if (!supports)
      out.push_back(body + "rests on " + supports_label(mine[i].supports) + ", which no member of the ensemble does");
    const BodySnapshot& b = engine.final_bodies[i];
    int lo = -1, hi = -1;
    bool awake = false;
    for (const EngineTrack& m : e.members) {
      const BodySnapshot& x = m.final_bodies[i];
      if (!x.asleep) {
        awake = true;
        continue;
      }
      lo = lo < 0 ? x.sleep_frame : std::min(lo, x.sleep_frame);
      hi = std::max(hi, x.sleep_frame);
    }
    if (!b.asleep && !awake)
      out.push_back(body + "is awake at the end; every member of the ensemble sleeps, at frames " + std::to_string(lo) +
                    "-" + std::to_string(hi));
    if (b.asleep && (lo < 0 || b.sleep_frame < lo - t.sleep_frames || b.sleep_frame > hi + t.sleep_frames))
      out.push_back(body + "falls asleep at frame " + std::to_string(b.sleep_frame) + ", outside the ensemble's " +
                    (lo < 0 ? std::string("(no member sleeps)") : std::to_string(lo) + "-" + std::to_string(hi)) +
                    " +- " + std::to_string(t.sleep_frames));
  }
  return out;
}

}  // namespace lockstep_test
