// CompareTolerances: defaults, the built-in table, and the sidecar JSON.
#include <gtest/gtest.h>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/tolerances.hpp"

namespace {

using namespace lockstep;
using namespace lockstep::compare;

TEST(TolerancesTest, DefaultJudgeFollowsTheDynamicBodyCount) {
  Scene s;
  s.bodies.resize(kBodiesJudgeMax);
  EXPECT_EQ(default_tolerances(s).judge, Judge::bodies);
  s.bodies.resize(kBodiesJudgeMax + 5);
  for (int i = 0; i < 5; ++i) s.bodies[static_cast<std::size_t>(i)].is_static = true;
  EXPECT_EQ(default_tolerances(s).judge, Judge::bodies);  // static bodies do not count
  s.bodies.emplace_back();
  EXPECT_EQ(default_tolerances(s).judge, Judge::statistics);
}

TEST(TolerancesTest, EveryBuiltinSceneHasAnEntry) {
  for (const std::string& name : builtin_scene_names()) {
    ASSERT_TRUE(builtin_tolerances(name).has_value()) << name;
    const Scene s = *builtin_scene(name);
    const bool chaotic = name == "pile1000" || name == "bowl" || name == "terrain";
    EXPECT_EQ(tolerances_for(s).judge, chaotic ? Judge::statistics : Judge::bodies) << name;
  }
  EXPECT_FALSE(builtin_tolerances("no_such_scene").has_value());
  // A file scene that merely shares a built-in name but not its bodies gets the defaults.
  Scene s = *builtin_scene("pile1000");
  s.bodies.resize(3);
  EXPECT_EQ(tolerances_for(s).judge, Judge::bodies);
}

TEST(TolerancesTest, SidecarOverridesOnlyTheFieldsItNames) {
  const CompareTolerances base;
  const CompareTolerances t = parse_tolerances(
      R"({"format": "lockstep-tolerances", "version": 1, "judge": "statistics", "rest_position": 0.125, "sleep_frames": 25})",
      "t.json", base);
  EXPECT_EQ(t.judge, Judge::statistics);
  EXPECT_EQ(t.rest_position, 0.125);
  EXPECT_EQ(t.sleep_frames, 25);
  EXPECT_EQ(t.position, base.position);
  EXPECT_EQ(t.height_distance, base.height_distance);
}

TEST(TolerancesTest, RoundTripsThroughJson) {
  CompareTolerances t;
  t.judge = Judge::statistics;
  t.position = 0.1 + 0.2;  // not a short decimal
  t.median_sleep_frames = 77;
  t.face_fraction = 0.3;
  const CompareTolerances back = parse_tolerances(tolerances_to_json(t), "round trip", CompareTolerances{});
  EXPECT_EQ(back.judge, t.judge);
  EXPECT_EQ(back.position, t.position);
  EXPECT_EQ(back.median_sleep_frames, 77);
  EXPECT_EQ(back.face_fraction, 0.3);
}

void expect_error(const std::string& json, const std::string& needle) {
  try {
    parse_tolerances(json, "side.json", CompareTolerances{});
    ADD_FAILURE() << "accepted: " << json;
  } catch (const ToleranceError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("side.json: ", 0), 0u) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
}

TEST(TolerancesTest, BadSidecarsAreRejectedNamingTheField) {
  const std::string head = R"({"format": "lockstep-tolerances", "version": 1, )";
  expect_error(head + R"("positon": 0.1})", "unknown field 'positon'");
  expect_error(head + R"("position": -0.1})", "position: -0.1 is out of range");
  expect_error(head + R"("position": "big"})", "position: \"big\" must be a number");
  expect_error(head + R"("sleep_frames": 2.5})", "sleep_frames: 2.5 must be a whole number");
  expect_error(head + R"("judge": "strict"})", "judge: \"strict\" must be");
  expect_error(head + R"("face_fraction": 1.5})", "face_fraction: 1.5 is out of range [0, 1]");
  expect_error(R"({"version": 1})", "format: must be \"lockstep-tolerances\"");
  expect_error(R"({"format": "lockstep-tolerances", "version": 2})", "version: must be 1");
  expect_error("[1, 2]", "must be a JSON object");
  expect_error("{", "not valid JSON");
  EXPECT_THROW(load_tolerances_file("/nonexistent/t.json", CompareTolerances{}), ToleranceError);
}

}  // namespace
