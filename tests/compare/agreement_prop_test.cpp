// Property-based agreement: on random simple scenes (scene_gen.hpp) the
// fixed, double and (when built) gpu engines agree on every body's resting
// state and sleep frame within kPropTolerances. A failing case is shrunk by
// RapidCheck to a minimal scene and written as a scene file (scene_to_json)
// whose path the failure message prints, with the property's tolerances
// beside it: `lockstep compare FILE --tolerances FILE.tolerances.json`
// reproduces it.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/scene_json.hpp"
#include <cmath>

#include "lockstep/fixed/q16.hpp"
#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/physics/params.hpp"
#include "scene_gen.hpp"

#ifndef LOCKSTEP_FAILURE_DEFAULT_DIR
#error "LOCKSTEP_FAILURE_DEFAULT_DIR: set by tests/compare/CMakeLists.txt to a directory of the build tree"
#endif

#ifndef LOCKSTEP_PROP_CASES
#define LOCKSTEP_PROP_CASES 60
#endif

namespace {

using namespace lockstep;
using namespace lockstep::compare;

// double, fixed and, where it runs the scene's pair model (engine_limitation),
// gpu.
std::vector<std::string> engines_under_test(const Scene& scene) {
  std::vector<std::string> e{"double", "fixed"};
  for (const std::string& n : engine_names_for(scene))
    if (n == "gpu") e.push_back(n);
  return e;
}

// What the property asks: rest and sleep only (trajectories of a tipping
// box part by design of the number types; the harness still reports them).
CompareTolerances prop_tolerances() {
  CompareTolerances t;
  t.judge = Judge::bodies;
  t.rest_position = 0.05;
  t.sleep_frames = 15;
  return t;
}

// Where a failing case is written: $LOCKSTEP_FAILURE_DIR, else the test's
// directory in the build tree (tests/compare/CMakeLists.txt), never the
// working directory (a run from the source tree would write into it).
std::string failure_dir() {
  const char* d = std::getenv("LOCKSTEP_FAILURE_DIR");
  return d && *d ? d : LOCKSTEP_FAILURE_DEFAULT_DIR;
}

// The scene as the fixed engine sees it: every constant rounded to Q16.16
// (eq 22), as the bodies' values already are (scene_gen.hpp), so that double
// and mp run the same model (Δt = 1092/65536 s, g = 642908/65536 m/s^2, ...)
// and the property judges the number types, not the fixed engine's model
// difference (docs/SPEC.md 7.1, Fix 5).
lockstep::Scene as_fixed_sees_it(lockstep::Scene s) {
  auto q = [](double& x) { x = lockstep::Q16::from_double(x).to_double(); };
  lockstep::Constants& c = s.constants;
  for (double* x : {&c.dt, &c.linear_damping, &c.angular_damping, &c.cell_size, &c.slop, &c.baumgarte, &c.contact_tolerance, &c.kp, &c.kd, &c.speed_factor_min, &c.speed_factor_max, &c.support_normal_min, &c.align_fine, &c.align_good, &c.align_fair, &c.damp_fine, &c.damp_good, &c.damp_fair, &c.rest_speed, &c.restitution_min_speed, &c.settle_speed, &c.settle_damping, &c.sleep_linear, &c.sleep_angular, &c.sleep_alignment, &c.drowsy_damping, &c.wake_speed, &c.wake_penetration, &c.wake_support_distance, &c.gravity.x, &c.gravity.y, &c.gravity.z}) q(*x);
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
Scene ieee_model_of(const Scene& scene) {
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

// record() with double (the baseline) and mp on ieee_model_of(scene), the
// other engines on the scene itself.
Recording record_models(const Scene& scene, const std::vector<std::string>& names) {
  const Scene ieee = ieee_model_of(scene);
  std::vector<std::unique_ptr<EngineRun>> runs;
  int baseline = -1;
  for (const std::string& n : names) {
    const bool is_ieee = n == "double" || n == "mp";
    if (n == "double") baseline = static_cast<int>(runs.size());
    runs.push_back(make_engine(n, is_ieee ? ieee : scene));
  }
  return record(scene, std::move(runs), baseline);
}

// The findings of `engine` against `reference` (two tracks of the same scene,
// however each was started) that fail the per-body checks: rest position,
// face up, supports and sleep frame. Trajectory findings are left out: the
// tracks' frame statistics were recorded against different baselines.
std::vector<Finding> per_body_failures(const Scene& scene, const EngineTrack& reference, const EngineTrack& engine,
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
// given, the mp truth, and double from the scene with every body's state
// nudged. The nudges span the differences the engines under test start to
// differ by: one Q16.16 ulp (2^-16, the fixed engine's resolution) up to
// 2^-10 (64 ulps: 1 mm, 1 mrad, 1 mm/s), the largest divergence measured
// between fixed and double before a case's trajectories part (about 2^-12 in
// position and 40 ulps of velocity after 35 frames of flight: the fixed
// engine's per-frame rounding of g dt, the damping factors and the
// quaternion accumulate; docs/COMPARE.md "Random scenes"). A knife edge that
// such a difference crosses (a landing whose alignment is within 2e-5 of
// align_fine, eq 72, is damped by 0.4 or by 0.7) is decided by the rounding,
// and each side of it is a right answer.
struct Ensemble {
  std::vector<EngineTrack> members;  // members[0]: double; members[1]: mp; then the nudged runs
  std::vector<std::string> labels;
};

Scene nudged(const Scene& scene, double scale, int member) {
  Scene s = scene;
  // A fixed sign pattern per member, body and component (no randomness: a
  // case reproduces from its scene alone).
  auto sign = [&](std::size_t body, int component) {
    const unsigned h = (static_cast<unsigned>(member) * 2654435761u) ^ (static_cast<unsigned>(body) * 40503u) ^
                       (static_cast<unsigned>(component) * 2246822519u);
    return ((h >> 7) ^ (h >> 13)) & 1u ? scale : -scale;
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

Ensemble ensemble_of(const Scene& scene) {
  Ensemble e;
  const Recording truth = record_models(scene, {"double", "mp"});
  e.members = truth.engines;
  e.labels = {"double", "mp"};
  constexpr int kMembersPerScale = 8;
  for (const double scale : {0x1p-16, 0x1p-13, 0x1p-10}) {
    for (int k = 0; k < kMembersPerScale; ++k) {
      e.members.push_back(record_models(nudged(scene, scale, k), {"double"}).engines[0]);
      e.labels.push_back("double nudged by " + std::to_string(static_cast<int>(std::lround(scale * 65536))) +
                         " ulp (pattern " + std::to_string(k) + ")");
    }
  }
  return e;
}

// Chaotic: some member of the ensemble parts from double itself (a rest
// position, face, support or sleep frame beyond the property's tolerances).
bool chaotic(const Scene& scene, const Ensemble& e, const CompareTolerances& t) {
  for (std::size_t m = 1; m < e.members.size(); ++m)
    if (!per_body_failures(scene, e.members[0], e.members[m], t).empty()) return true;
  return false;
}

// A chaotic scene, judged by the statistics of its ensemble: every body of
// the engine must end as some member of the ensemble ends that body (rest
// position, face up, supports and sleep frame within the property's
// tolerances): the engine reached an outcome that double reaches from a
// start within the engines' differences. It fails when the engine ends a
// body where no member does (e.g. it gains energy, sinks, or sleeps late).
// Bodies are judged one by one: the free boxes of a scene never meet, and in
// a stack each body's outcome is compared with every member's.
std::vector<std::string> outside_ensemble(const Scene& scene, const Ensemble& e, const EngineTrack& engine,
                                          const CompareTolerances& t) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < engine.final_bodies.size(); ++i) {
    const Finding* nearest = nullptr;
    std::vector<std::vector<Finding>> fails;
    for (const EngineTrack& m : e.members) fails.push_back(per_body_failures(scene, m, engine, t));
    bool reached = false;
    for (const std::vector<Finding>& f : fails) {
      bool body_ok = true;
      for (const Finding& x : f)
        if (x.body == static_cast<int>(i)) {
          body_ok = false;
          if (!nearest) nearest = &x;
        }
      if (body_ok) {
        reached = true;
        break;
      }
    }
    if (!reached)
      out.push_back(engine.name + ": body " + std::to_string(i) + " ends where no member of the ensemble (" +
                    std::to_string(e.members.size()) + " runs) does; against double: " +
                    (nearest ? nearest->message("double") : std::string("?")));
  }
  return out;
}

// Runs the scene and returns the failed rest, sleep and run checks, as lines.
std::vector<std::string> disagreements(const Scene& scene, const CompareTolerances& t) {
  const Recording r = record_models(scene, engines_under_test(scene));
  std::vector<std::string> out;
  for (const EngineTrack& track : r.engines)
    if (track.failed) out.push_back(track.name + ": stopped: " + track.failure.message);
  if (!out.empty()) return out;
  const Ensemble e = ensemble_of(scene);
  if (chaotic(scene, e, t)) {
    RC_TAG("chaotic (double parts from mp or from itself nudged by 1 to 64 ulps): judged by the ensemble");
    for (const EngineTrack& track : r.engines) {
      if (track.name == "double") continue;
      for (std::string& line : outside_ensemble(scene, e, track, t)) out.push_back(std::move(line));
    }
    return out;
  }
  RC_TAG("judged body by body");
  const Verdict v = judge(r, t);
  for (const Finding& f : v.failures())
    if (f.check != "trajectory") out.push_back(f.message(v.baseline));
  return out;
}

// The property body: on disagreement, writes the scene to `path` (each
// failing case overwrites it, so after shrinking it holds the minimal one)
// and fails naming the path and the disagreements.
void check_agreement(const Scene& scene, const CompareTolerances& t, const std::string& path) {
  validate_scene(scene);  // a generator bug, not an engine disagreement
  const std::vector<std::string> bad = disagreements(scene, t);
  if (bad.empty()) return;
  const std::string tol_path = path.substr(0, path.size() - 5) + ".tolerances.json";
  write_file(path, scene_to_json(scene));
  write_file(tol_path, tolerances_to_json(t));
  std::ostringstream m;
  m << bad.size() << " disagreement(s) on a " << scene.bodies.size() << "-body scene, written to " << path
    << " (reproduce: lockstep compare " << path << " --engines double,fixed --tolerances " << tol_path << "):";
  for (std::size_t i = 0; i < bad.size() && i < 5; ++i) m << "\n  " << bad[i];
  RC_FAIL(m.str());
}

// Runs a property with a fixed number of cases; returns RapidCheck's result.
template <class Testable>
rc::detail::TestResult run_property(Testable&& testable, int cases, const std::string& id) {
  rc::detail::TestParams params = rc::detail::configuration().testParams;
  params.maxSuccess = std::max(params.maxSuccess, cases);
  rc::detail::TestMetadata metadata;
  metadata.id = id;
  metadata.description = id;
  return rc::detail::checkTestable(std::forward<Testable>(testable), metadata, params);
}

TEST(AgreementProp, FixedDoubleAndGpuAgreeOnRestAndSleep) {
  const std::string path = (std::filesystem::path(failure_dir()) / "agreement_failure.json").string();
  const auto result = run_property(
      [&] { check_agreement(as_fixed_sees_it(*lockstep_test::gen_simple_scene()), prop_tolerances(), path); },
      LOCKSTEP_PROP_CASES, "AgreementProp/FixedDoubleAndGpuAgreeOnRestAndSleep");
  if (!result.template is<rc::detail::SuccessResult>()) {
    std::ostringstream ss;
    rc::detail::printResultMessage(result, ss);
    FAIL() << ss.str();
  }
}

// The failure path itself: with an impossible tolerance (rest positions equal
// to the bit) every case fails; RapidCheck must shrink it to the plain
// one-cube scene and the file must reproduce the disagreement.
TEST(AgreementMeta, AFailingCaseShrinksAndIsWrittenAsASceneThatReproduces) {
  CompareTolerances impossible = prop_tolerances();
  impossible.rest_position = 0.0;
  const std::string path =
      (std::filesystem::temp_directory_path() / "lockstep_agreement_meta_failure.json").string();
  std::filesystem::remove(path);
  const auto result = run_property(
      [&] { check_agreement(*lockstep_test::gen_simple_scene(), impossible, path); }, 20, "AgreementMeta");
  ASSERT_TRUE(result.template is<rc::detail::FailureResult>());
  std::ostringstream msg;
  rc::detail::printResultMessage(result, msg);
  EXPECT_NE(msg.str().find(path), std::string::npos) << msg.str();
  ASSERT_TRUE(std::filesystem::exists(path));
  const Scene shrunk = load_scene_file(path);
  EXPECT_EQ(shrunk.bodies.size(), 1u);
  EXPECT_EQ(shrunk.bodies[0].mass, 1.0);
  EXPECT_EQ(shrunk.bodies[0].half_extents.x, 0.5);
  EXPECT_EQ(shrunk.bodies[0].velocity.x, 0.0);
  EXPECT_FALSE(disagreements(shrunk, impossible).empty());
  // The sidecar beside it holds the tolerances that failed.
  const std::string tol_path = path.substr(0, path.size() - 5) + ".tolerances.json";
  EXPECT_EQ(load_tolerances_file(tol_path, CompareTolerances{}).rest_position, 0.0);
  std::filesystem::remove(path);
  std::filesystem::remove(tol_path);
}

}  // namespace
