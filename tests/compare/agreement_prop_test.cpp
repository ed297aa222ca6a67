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
#include "scene_gen.hpp"

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

std::string failure_dir() {
  const char* d = std::getenv("LOCKSTEP_FAILURE_DIR");
  return d && *d ? d : std::filesystem::current_path().string();
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

// Is the scene chaotic at the resolution the engines differ by? Either double
// and the mp truth part, or double parts from itself when every body starts
// one Q16.16 ulp (2^-16) away (position along x or z, or orientation): then
// which way the scene goes is
// decided by a rounding, no engine can be asked to follow double body by body,
// and the scene is judged by statistics (resting heights, faces up, sleep),
// as the piles are (docs/COMPARE.md). "Part": a trajectory beyond the default
// 0.05 m / 0.1 rad, or a rest position or sleep frame beyond the property's
// tolerances.
bool parts(const Recording& r, const CompareTolerances& t) {
  for (const Finding& f : judge(r, t).failures())
    if (f.check != "run") return true;
  return false;
}
bool chaotic(const Scene& scene) {
  CompareTolerances bodies = prop_tolerances();
  bodies.judge = Judge::bodies;
  if (parts(record(scene, {"double", "mp"}, "double"), bodies)) return true;
  const Recording base = record(scene, {"double"}, "double");
  constexpr double kUlp = 1.0 / 65536.0;
  // Six nudges of every body: its position by +-1 ulp along x and z, its
  // orientation by +-1 ulp in the quaternion's x component.
  for (int k = 0; k < 6; ++k) {
    Scene nudged = scene;
    const double d = (k % 2 == 0) ? kUlp : -kUlp;
    for (BodyDesc& b : nudged.bodies) {
      if (k < 2) b.position.x += d;
      else if (k < 4) b.position.z += d;
      else b.orientation.x += d;
    }
    const Recording r = record(nudged, {"double"}, "double");
    for (std::size_t i = 0; i < base.engines[0].final_bodies.size(); ++i) {
      const BodySnapshot& x = base.engines[0].final_bodies[i];
      const BodySnapshot& y = r.engines[0].final_bodies[i];
      const double dx = y.p[0] - x.p[0], dy = y.p[1] - x.p[1], dz = y.p[2] - x.p[2];
      if (std::sqrt(dx * dx + dy * dy + dz * dz) > bodies.rest_position - 2 * kUlp) return true;
      if ((x.sleep_frame >= 0) != (y.sleep_frame >= 0)) return true;
      if (x.sleep_frame >= 0 && std::abs(x.sleep_frame - y.sleep_frame) > bodies.sleep_frames) return true;
    }
  }
  return false;
}

// Runs the scene and returns the failed rest, sleep and run checks, as lines.
std::vector<std::string> disagreements(const Scene& scene, const CompareTolerances& tolerances) {
  CompareTolerances t = tolerances;
  if (t.judge == Judge::bodies && chaotic(scene)) {
    t.judge = Judge::statistics;
    RC_TAG("chaotic (double parts from mp or from itself nudged by 1 ulp): judged by statistics");
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
