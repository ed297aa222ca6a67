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
#include "scene_gen.hpp"

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

std::string failure_dir() {
  const char* d = std::getenv("LOCKSTEP_FAILURE_DIR");
  return d && *d ? d : std::filesystem::current_path().string();
}

// Is the scene chaotic: do double and the mp truth part (a trajectory beyond
// the default 0.05 m / 0.1 rad)? Then no engine can be asked to follow
// double body by body, and the scene is judged by statistics (resting
// heights, faces up, sleep), as the piles are (docs/COMPARE.md).
bool chaotic(const Scene& scene) {
  const Recording r = record(scene, {"double", "mp"}, "double");
  CompareTolerances t;
  t.judge = Judge::bodies;
  for (const Finding& f : judge(r, t).failures())
    if (f.check == "trajectory") return true;
  return false;
}

// Runs the scene and returns the failed rest, sleep and run checks, as lines.
std::vector<std::string> disagreements(const Scene& scene, const CompareTolerances& tolerances) {
  CompareTolerances t = tolerances;
  if (t.judge == Judge::bodies && chaotic(scene)) {
    t.judge = Judge::statistics;
    RC_TAG("chaotic (double and mp part): judged by statistics");
  } else {
    RC_TAG("judged body by body");
  }
  const Recording r = record(scene, engines_under_test(scene), "double");
  const Verdict v = judge(r, t);
  std::vector<std::string> out;
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
      [&] { check_agreement(*lockstep_test::gen_simple_scene(), prop_tolerances(), path); },
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
