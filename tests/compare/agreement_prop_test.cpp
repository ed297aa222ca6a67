// Property-based agreement: on random simple scenes (scene_gen.hpp) the
// fixed, double and (when built) gpu engines agree on every body's resting
// state and sleep frame within prop_tolerances(); a case that is chaotic at
// the size the engines differ by is recognised and judged by an ensemble of
// nudged double runs and mp (ensemble.hpp). A failing case is shrunk by
// RapidCheck to a minimal scene and written as a scene file (scene_to_json)
// whose path the failure message prints, with the property's tolerances
// beside it: `lockstep compare FILE --tolerances FILE.tolerances.json`
// reproduces it.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/scene_json.hpp"
#include <cmath>

#include "lockstep/fixed/q16.hpp"
#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/physics/params.hpp"
#include "ensemble.hpp"
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

// double, fixed and, where it is built, gpu (both pair models;
// engine_names_for leaves out an engine with a limitation, none today).
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



// record() with double (the baseline) and mp on ieee_model_of(scene), the
// other engines on the scene itself.
Recording record_models(const Scene& scene, const std::vector<std::string>& names) {
  const Scene ieee = lockstep_test::ieee_model_of(scene);
  std::vector<std::unique_ptr<EngineRun>> runs;
  int baseline = -1;
  for (const std::string& n : names) {
    const bool is_ieee = n == "double" || n == "mp";
    if (n == "double") baseline = static_cast<int>(runs.size());
    runs.push_back(make_engine(n, is_ieee ? ieee : scene));
  }
  return record(scene, std::move(runs), baseline);
}

// How the cases were judged (printed after the property).
struct CaseCounts {
  int chaotic = 0, bodies = 0;
} g_cases;

// Runs the scene and returns the failed rest, sleep and run checks, as lines.
std::vector<std::string> disagreements(const Scene& scene, const CompareTolerances& t) {
  const Recording r = record_models(scene, engines_under_test(scene));
  std::vector<std::string> out;
  for (const EngineTrack& track : r.engines)
    if (track.failed) out.push_back(track.name + ": stopped: " + track.failure.message);
  if (!out.empty()) return out;
  const lockstep_test::Ensemble e = lockstep_test::ensemble_of(scene, record_models, false);
  if (lockstep_test::chaotic(scene, e, t)) {
    RC_TAG("chaotic (double parts from mp or from itself nudged by 2^-22 to 2^-10): judged by the ensemble");
    ++g_cases.chaotic;
    for (const EngineTrack& track : r.engines) {
      if (track.name == "double") continue;
      for (std::string& line : lockstep_test::outside_ensemble(scene, e, track, t)) out.push_back(std::move(line));
    }
    return out;
  }
  RC_TAG("judged body by body");
  ++g_cases.bodies;
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
rc::detail::TestResult run_property(Testable&& testable, int cases, const std::string& id, std::uint64_t seed = 0) {
  rc::detail::TestParams params = rc::detail::configuration().testParams;
  params.maxSuccess = std::max(params.maxSuccess, cases);
  if (seed != 0) params.seed = seed;
  rc::detail::TestMetadata metadata;
  metadata.id = id;
  metadata.description = id;
  return rc::detail::checkTestable(std::forward<Testable>(testable), metadata, params);
}

TEST(AgreementProp, FixedDoubleAndGpuAgreeOnRestAndSleep) {
  const std::string path = (std::filesystem::path(failure_dir()) / "agreement_failure.json").string();
  const auto result = run_property(
      [&] { check_agreement(lockstep_test::as_fixed_sees_it(*lockstep_test::gen_simple_scene()), prop_tolerances(), path); },
      LOCKSTEP_PROP_CASES, "AgreementProp/FixedDoubleAndGpuAgreeOnRestAndSleep");
  std::cout << "cases judged body by body: " << g_cases.bodies << ", chaotic (judged by the ensemble): "
            << g_cases.chaotic << "\n";
  if (!result.template is<rc::detail::SuccessResult>()) {
    std::ostringstream ss;
    rc::detail::printResultMessage(result, ss);
    FAIL() << ss.str();
  }
}

// AgreementProp seed 7106, as RapidCheck shrank it: a box of 0.72 x 1.22 x
// 1.28 m (2.75 kg) thrown onto the ground rocks about an edge and falls flat
// at frame 74, turning at 1.34 rad/s. At that frame's start its landing
// corners were 2.56 mm up in fixed and 3.00 mm in double, and only fixed's
// were within support_fade (2.7 mm): eq 112 counted them as support points,
// so fixed settled the box (eq 72: w x 0.4) and it stopped dead at sleep
// frame 109, where double rocked it on (Housner's ratio for this block,
// 0.61) and slept at 125 (tolerance 15). A speculative corner closing faster
// than rest_speed is an impact, not a support point (support_impact), in
// every engine: both rock the box on.
TEST(AgreementCases, RockingBoxFallingFlatSeed7106) {
  const Scene scene = parse_scene(R"json({
  "format": "lockstep-scene",
  "version": 1,
  "name": "agreement_case",
  "frames": 480,
  "pair_contacts": "oriented_box",
  "effects": {"gravity": true, "damping": true, "ground": true, "contacts": true, "friction": true, "restitution": true, "settling": true, "sleep": true, "sdf": false},
  "constants": {
    "dt": 0.01666259765625,
    "gravity": [0.0, -9.80999755859375, 0.0],
    "linear_damping": 0.0050048828125,
    "angular_damping": 0.0200042724609375,
    "cell_size": 4.0,
    "slop": 0.001007080078125,
    "baumgarte": 1.0,
    "solver_iterations": 8,
    "contact_tolerance": 0.0099945068359375,
    "converged_speed": 0.0,
    "kp": 30.0,
    "kd": 10.0,
    "speed_factor_min": 0.5,
    "speed_factor_max": 2.0,
    "support_normal_min": 0.6999969482421875,
    "align_fine": 0.9980010986328125,
    "align_good": 0.9900054931640625,
    "align_fair": 0.9499969482421875,
    "damp_fine": 0.399993896484375,
    "damp_good": 0.6999969482421875,
    "damp_fair": 0.850006103515625,
    "rest_speed": 0.1999969482421875,
    "restitution_min_speed": 0.5,
    "settle_speed": 0.3000030517578125,
    "settle_damping": 0.100006103515625,
    "sleep_linear": 0.0500030517578125,
    "sleep_angular": 0.0500030517578125,
    "sleep_alignment": 0.9900054931640625,
    "drowsy_frames": 10,
    "drowsy_damping": 0.5,
    "sleep_frames": 30,
    "wake_speed": 0.25,
    "wake_penetration": 0.0200042724609375,
    "wake_support_distance": 0.0050048828125
  },
  "ground": {"present": true, "height": 0.0, "material": {"restitution": 0.0, "friction": 0.4375}},
  "bodies": [
    {"half_extents": [0.5, 0.5, 0.5], "mass": 1.0, "position": [0.0, 0.875, 0.0], "orientation": [1.0, 0.0, 0.0, 0.0], "velocity": [0.0, 0.0, 0.0], "angular_velocity": [0.0, 0.0, 0.0], "material": {"restitution": 0.0, "friction": 0.5}, "static": false, "asleep": false},
    {"half_extents": [0.359375, 0.609375, 0.640625], "mass": 2.75, "position": [4.0, 1.40625, 0.0], "orientation": [0.8314696123025452, -0.02598342538445454, 0.5555702330196022, 0.017361569781862568], "velocity": [-0.5, 0.375, 0.375], "angular_velocity": [-0.1875, -0.3125, -0.25], "material": {"restitution": 0.0, "friction": 0.59375}, "static": false, "asleep": false}
  ],
  "sdfs": []
})json", "AgreementProp seed 7106");
  const std::vector<std::string> bad = disagreements(scene, prop_tolerances());
  std::ostringstream m;
  for (const std::string& line : bad) m << "\n  " << line;
  EXPECT_TRUE(bad.empty()) << m.str();
}

// The failure path itself: with an impossible tolerance (rest positions equal
// to the bit) RapidCheck must find a failing case, shrink it to one body, and
// the file must reproduce the disagreement.
TEST(AgreementMeta, AFailingCaseShrinksAndIsWrittenAsASceneThatReproduces) {
  CompareTolerances impossible = prop_tolerances();
  impossible.rest_position = 0.0;
  const std::string path =
      (std::filesystem::temp_directory_path() / "lockstep_agreement_meta_failure.json").string();
  std::filesystem::remove(path);
  const auto result = run_property(
      [&] { check_agreement(*lockstep_test::gen_simple_scene(), impossible, path); }, 20, "AgreementMeta",
      0x6d657461ULL);  // a fixed seed: this tests the failure path, not the engines (how far RapidCheck's
                       // bounded shrink gets depends on the cases it drew: h stopped at 0.515625 once)
  ASSERT_TRUE(result.template is<rc::detail::FailureResult>());
  std::ostringstream msg;
  rc::detail::printResultMessage(result, msg);
  EXPECT_NE(msg.str().find(path), std::string::npos) << msg.str();
  ASSERT_TRUE(std::filesystem::exists(path));
  const Scene shrunk = load_scene_file(path);
  // Shrunk to one body (the plain upright cube itself may now agree to the
  // bit: double runs the fixed engine's per-frame products, so the shrink
  // stops at the nearest case that still differs).
  EXPECT_EQ(shrunk.bodies.size(), 1u);
  EXPECT_FALSE(disagreements(shrunk, impossible).empty());
  // The sidecar beside it holds the tolerances that failed.
  const std::string tol_path = path.substr(0, path.size() - 5) + ".tolerances.json";
  EXPECT_EQ(load_tolerances_file(tol_path, CompareTolerances{}).rest_position, 0.0);
  std::filesystem::remove(path);
  std::filesystem::remove(tol_path);
}

// The ensemble's judgement can fail: on the plain one-cube drop (not
// chaotic: every member ends as double does), a track equal to double's
// passes, and the same track moved 0.2 m along x, asleep 40 frames later, or
// awake at the end fails, naming the quantity.
TEST(EnsembleJudge, AnEngineOutsideTheSpreadFails) {
  // The generator's plain case: a unit cube of 1 kg dropped upright from
  // 0.875 m (its half diagonal rounded up to 1/64 m) onto the ground at 0.
  Scene scene;
  scene.name = "agreement_case";
  scene.frames = 480;
  scene.effects.sdf = false;
  scene.ground.material = {0.0, 0.5};
  BodyDesc cube;
  cube.material = {0.0, 0.5};
  cube.position = {0.0, 0.875, 0.0};
  scene.bodies.push_back(cube);
  scene = lockstep_test::as_fixed_sees_it(scene);
  const CompareTolerances t = prop_tolerances();
  const lockstep_test::Ensemble e = lockstep_test::ensemble_of(scene, record_models, false);
  EXPECT_FALSE(lockstep_test::chaotic(scene, e, t));
  EngineTrack same = e.members[0];
  same.name = "fixed";
  EXPECT_TRUE(lockstep_test::outside_ensemble(scene, e, same, t).empty());
  ASSERT_TRUE(same.final_bodies[0].asleep);
  EngineTrack moved = same;
  moved.final_bodies[0].p[0] += 0.2;
  const auto m = lockstep_test::outside_ensemble(scene, e, moved, t);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_NE(m[0].find("rests at x"), std::string::npos) << m[0];
  EngineTrack late = same;
  late.final_bodies[0].sleep_frame += 40;
  const auto l = lockstep_test::outside_ensemble(scene, e, late, t);
  ASSERT_EQ(l.size(), 1u);
  EXPECT_NE(l[0].find("falls asleep at frame"), std::string::npos) << l[0];
  EngineTrack awake = same;
  awake.final_bodies[0].asleep = false;
  awake.final_bodies[0].sleep_frame = -1;
  const auto a = lockstep_test::outside_ensemble(scene, e, awake, t);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_NE(a[0].find("is awake at the end"), std::string::npos) << a[0];
}

}  // namespace
