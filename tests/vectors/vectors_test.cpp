// Tests of the hand-off test vectors: the checked-in vectors/data agree with
// the fixed engine bit for bit at all three levels, they are exactly what the
// generator writes, and a perturbed file is rejected naming the first
// differing test, or frame, body and field.
//
// If a *CheckedIn* test fails after an intentional physics change, the
// engine's bits moved: regenerate the vectors on purpose (the command is in
// the failure message) and review the diff before committing it.
#include "lockstep/vectors/vectors.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/vectors/arithmetic.hpp"
#include "lockstep/vectors/formulas.hpp"
#include "lockstep/vectors/json_text.hpp"
#include "lockstep/vectors/params_json.hpp"
#include "lockstep/vectors/scenes.hpp"

namespace lockstep::vectors {
namespace {

namespace fs = std::filesystem;

const std::string kDir = LOCKSTEP_VECTORS_DIR;

std::string regenerate_hint() {
  return std::string("\nIf this fails after an intentional physics change, regenerate the vectors with:\n  ") +
         LOCKSTEP_REGENERATE_COMMAND + "\nthen review and commit the diff of vectors/data.";
}

Json load(const std::string& rel) { return read_json_file(kDir + "/" + rel); }

// Pile1000 is checked to this frame in the default run (its full 600 frames are label long).
constexpr int kPileQuickFrames = 120;

// ---------------------------------------------------------------------------
// The checked-in vectors
// ---------------------------------------------------------------------------

TEST(VectorsCheckedIn, ArithmeticAgreesWithTheFixedEngine) {
  const Verdict v = verify_arithmetic(load("arithmetic.json"), "arithmetic.json");
  EXPECT_TRUE(v.ok) << v.message << regenerate_hint();
  EXPECT_GT(v.checked, 2000u);
}

TEST(VectorsCheckedIn, FormulasAgreeWithTheFixedEngine) {
  const Verdict v = verify_formulas(load("formulas.json"), "formulas.json");
  EXPECT_TRUE(v.ok) << v.message << regenerate_hint();
  EXPECT_GT(v.checked, 500u);
}

class VectorsCheckedInScene : public ::testing::TestWithParam<std::string> {};

TEST_P(VectorsCheckedInScene, AgreesWithTheFixedEngineEveryFrame) {
  const std::string rel = "scenes/" + GetParam() + ".json";
  const Json doc = load(rel);
  SceneVerifyOptions o;
  if (GetParam() == "pile1000") o.max_frames = kPileQuickFrames;
  const Verdict v = verify_scene_vectors(doc, rel, o);
  EXPECT_TRUE(v.ok) << v.message << regenerate_hint();
  EXPECT_EQ(v.checked, static_cast<std::size_t>(o.max_frames >= 0 ? o.max_frames + 1 : doc["frames"].get<int>() + 1));
}

INSTANTIATE_TEST_SUITE_P(Builtin, VectorsCheckedInScene, ::testing::ValuesIn(builtin_scene_names()),
                         [](const ::testing::TestParamInfo<std::string>& scene) { return scene.param; });

// The full pile1000 run (label long, with the other long tests).
TEST(VectorsCheckedInLong, Pile1000AllFrames) {
  const Verdict v = verify_scene_vectors(load("scenes/pile1000.json"), "scenes/pile1000.json");
  EXPECT_TRUE(v.ok) << v.message << regenerate_hint();
  EXPECT_EQ(v.checked, 601u);
}

TEST(VectorsCheckedIn, IndexListsEveryLevelAndEveryBuiltinScene) {
  const Json index = load("index.json");
  EXPECT_EQ(index["schemaVersion"], kSchemaVersion);
  std::vector<std::string> paths;
  for (const Json& f : index["files"]) {
    paths.push_back(f["path"].get<std::string>());
    EXPECT_EQ(load(paths.back())["numberOfTests"], f["numberOfTests"]) << paths.back();
  }
  EXPECT_NE(std::find(paths.begin(), paths.end(), "arithmetic.json"), paths.end());
  EXPECT_NE(std::find(paths.begin(), paths.end(), "formulas.json"), paths.end());
  for (const std::string& n : builtin_scene_names())
    EXPECT_NE(std::find(paths.begin(), paths.end(), "scenes/" + n + ".json"), paths.end()) << n << regenerate_hint();
}

// Verification recomputes the outputs from the inputs in the files; these make
// sure the inputs themselves are the generator's (a changed case list or format
// is regenerated too), byte for byte.
TEST(VectorsCheckedIn, ArithmeticFileIsTheGeneratorsOutput) {
  EXPECT_EQ(to_text(load("arithmetic.json")), to_text(generate_arithmetic())) << regenerate_hint();
}

TEST(VectorsCheckedIn, FormulasFileIsTheGeneratorsOutput) {
  EXPECT_EQ(to_text(load("formulas.json")), to_text(generate_formulas())) << regenerate_hint();
}

TEST(VectorsCheckedIn, SmallSceneFilesAreTheGeneratorsOutput) {
  for (const char* name : {"drop", "stack5"})
    EXPECT_EQ(to_text(load(std::string("scenes/") + name + ".json")),
              to_text(generate_scene_vectors(*builtin_scene(name))))
        << name << regenerate_hint();
}

TEST(VectorsCheckedIn, EveryFileHasTheWycheproofStyleHeader) {
  for (const std::string rel : {"arithmetic.json", "formulas.json", "scenes/drop.json"}) {
    const Json d = load(rel);
    for (const char* key : {"algorithm", "schema", "schemaVersion", "generatorVersion", "numberOfTests", "header"})
      EXPECT_TRUE(d.contains(key)) << rel << " lacks " << key;
    EXPECT_EQ(d["generatorVersion"], generator_version()) << rel << regenerate_hint();
  }
}

// ---------------------------------------------------------------------------
// Perturbed vectors are rejected, naming the place
// ---------------------------------------------------------------------------

// Finds the test with the given tcId.
Json& test_with_id(Json& doc, long id) {
  for (Json& g : doc["testGroups"])
    for (Json& t : g["tests"])
      if (t["tcId"] == id) return t;
  throw std::runtime_error("no tcId " + std::to_string(id));
}

TEST(VectorsPerturbed, ArithmeticOutputNamesTheTestAndField) {
  Json doc = generate_arithmetic();
  Json& t = test_with_id(doc, 700);
  const std::int64_t r = t["out"]["r"].is_array() ? 0 : t["out"]["r"].get<std::int64_t>();
  ASSERT_FALSE(t["out"]["r"].is_array());
  t["out"]["r"] = r + 1;
  const Verdict v = verify_arithmetic(doc, "arithmetic.json");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.tc_id, 700);
  EXPECT_EQ(v.field, "out.r");
  EXPECT_NE(v.message.find("tcId 700"), std::string::npos) << v.message;
  EXPECT_NE(v.message.find("expected " + std::to_string(r + 1) + ", got " + std::to_string(r)), std::string::npos)
      << v.message;
}

TEST(VectorsPerturbed, ArithmeticStatusNamesTheFlag) {
  Json doc = generate_arithmetic();
  // The first division by zero: drop its flag.
  for (Json& g : doc["testGroups"]) {
    if (g["operation"] != "div") continue;
    for (Json& t : g["tests"]) {
      if (t["status"] == Json::array({"div_by_zero"})) {
        t["status"] = Json::array();
        const long id = t["tcId"].get<long>();
        const Verdict v = verify_arithmetic(doc, "arithmetic.json");
        ASSERT_FALSE(v.ok);
        EXPECT_EQ(v.tc_id, id);
        EXPECT_EQ(v.field, "status");
        EXPECT_NE(v.message.find("div_by_zero"), std::string::npos) << v.message;
        return;
      }
    }
  }
  FAIL() << "no division by zero case";
}

TEST(VectorsPerturbed, FormulaOutputNamesTheTestAndField) {
  Json doc = generate_formulas();
  for (Json& g : doc["testGroups"]) {
    if (g["function"] != "two_body_impulse") continue;
    Json& t = g["tests"][3];
    t["out"]["a"]["w"][2] = t["out"]["a"]["w"][2].get<std::int64_t>() - 1;
    const Verdict v = verify_formulas(doc, "formulas.json");
    ASSERT_FALSE(v.ok);
    EXPECT_EQ(v.tc_id, t["tcId"].get<long>());
    EXPECT_EQ(v.field, "out.a.w[2]");
    EXPECT_NE(v.message.find("two_body_impulse"), std::string::npos) << v.message;
    return;
  }
  FAIL() << "no two_body_impulse group";
}

TEST(VectorsPerturbed, ManifoldImpulseNamesTheTestAndPoint) {
  Json doc = generate_formulas();
  for (Json& g : doc["testGroups"]) {
    if (g["function"] != "manifold_visit") continue;
    for (Json& t : g["tests"]) {
      if (t["out"]["points"].size() < 3) continue;
      t["out"]["points"][2]["j_n"] = t["out"]["points"][2]["j_n"].get<std::int64_t>() + 1;
      const Verdict v = verify_formulas(doc, "formulas.json");
      ASSERT_FALSE(v.ok);
      EXPECT_EQ(v.tc_id, t["tcId"].get<long>());
      EXPECT_EQ(v.field, "out.points[2].j_n");
      return;
    }
  }
  FAIL() << "no manifold_visit case with 3 points";
}

TEST(VectorsPerturbed, SceneStateNamesFrameBodyAndField) {
  Json doc = generate_scene_vectors(*builtin_scene("stack5"));
  // Frame 50, body 3, p.y (field 1) one ulp off, as a port that diverged there would have it.
  Json& state = doc["states"][50];
  ASSERT_EQ(state["frame"], 50);
  const std::int64_t y = state["bodies"][3][1].get<std::int64_t>();
  state["bodies"][3][1] = y + 1;
  const Verdict v = verify_scene_vectors(doc, "scenes/stack5.json");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.frame, 50);
  EXPECT_EQ(v.body, 3);
  EXPECT_EQ(v.field, "p.y");
  EXPECT_NE(
      v.message.find("frame 50, body 3, field p.y: expected " + std::to_string(y + 1) + ", got " + std::to_string(y)),
      std::string::npos)
      << v.message;
}

TEST(VectorsPerturbed, SceneHashWithAgreeingStateBlamesTheHash) {
  Json doc = generate_scene_vectors(*builtin_scene("drop"));
  doc["hashes"][20] = "0123456789abcdef";
  const Verdict v = verify_scene_vectors(doc, "scenes/drop.json");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.frame, 20);
  EXPECT_EQ(v.field, "hash");
  EXPECT_NE(v.message.find("frame 20: state hash expected 0123456789abcdef"), std::string::npos) << v.message;
}

TEST(VectorsPerturbed, SparseStatesLocateTheBodyAtTheNextStoredFrame) {
  // As pile1000 is stored: hashes every frame, full states only at some frames.
  SceneVectorOptions o;
  o.full_state_max_bodies = 0;
  o.sparse_frames = {0, 100};
  Json doc = generate_scene_vectors(*builtin_scene("pyramid"), o);
  ASSERT_EQ(doc["stateFrames"], Json::array({0, 100, 600}));
  // A port that went wrong at frame 40 in body 7's v.x (field 7).
  for (int f = 40; f <= 600; ++f) doc["hashes"][static_cast<std::size_t>(f)] = "ffffffffffffffff";
  Json& at100 = doc["states"][1];
  ASSERT_EQ(at100["frame"], 100);
  at100["bodies"][7][7] = at100["bodies"][7][7].get<std::int64_t>() + 5;
  const Verdict v = verify_scene_vectors(doc, "scenes/pyramid.json");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.frame, 40);
  EXPECT_EQ(v.body, 7);
  EXPECT_EQ(v.field, "v.x");
  EXPECT_NE(v.message.find("frame 40: state hash expected ffffffffffffffff"), std::string::npos) << v.message;
  EXPECT_NE(v.message.find("frame 100, body 7, field v.x"), std::string::npos) << v.message;
}

TEST(VectorsPerturbed, SceneSleepFrameIsChecked) {
  Json doc = generate_scene_vectors(*builtin_scene("drop"));
  ASSERT_GT(doc["sleepFrames"][0].get<int>(), 0) << "drop is expected to fall asleep";
  doc["sleepFrames"][0] = doc["sleepFrames"][0].get<int>() + 1;
  const Verdict v = verify_scene_vectors(doc, "scenes/drop.json");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.field, "sleepFrames[0]");
}

TEST(VectorsPerturbed, ChangedBuiltinSceneIsNamed) {
  Json doc = generate_scene_vectors(*builtin_scene("drop"));
  doc["sceneDocument"]["bodies"][0]["position"][1] = 2.5;
  const Verdict v = verify_scene_vectors(doc, "scenes/drop.json");
  ASSERT_FALSE(v.ok);
  EXPECT_EQ(v.field, "scene");
  EXPECT_NE(v.message.find("bodies[0].position"), std::string::npos) << v.message;
}

TEST(VectorsPerturbed, MalformedFileNamesTheMissingField) {
  Json doc = generate_formulas();
  doc["testGroups"][1]["tests"][0]["in"].erase("v");
  const Verdict v = verify_formulas(doc, "formulas.json");
  ASSERT_FALSE(v.ok);
  EXPECT_NE(v.message.find("malformed"), std::string::npos) << v.message;
  EXPECT_NE(v.message.find("testGroups[1].tests[0].in"), std::string::npos) << v.message;
}

TEST(VectorsPerturbed, UnsupportedSchemaVersionIsRejected) {
  Json doc = generate_arithmetic();
  doc["schemaVersion"] = kSchemaVersion + 1;
  const Verdict v = verify_arithmetic(doc, "arithmetic.json");
  ASSERT_FALSE(v.ok);
  EXPECT_NE(v.message.find("schemaVersion"), std::string::npos) << v.message;
}

// ---------------------------------------------------------------------------
// The directory round trip and the generator's own properties
// ---------------------------------------------------------------------------

TEST(VectorsDirectory, GenerateThenVerifyRoundTripsAndAMissingSceneIsNamed) {
  const fs::path dir = fs::temp_directory_path() /
                       ("lockstep_vectors_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::remove_all(dir);
  GenerateOptions g;
  g.scenes = {"drop", "slide"};
  const auto written = generate_directory(dir.string(), g, nullptr);
  EXPECT_EQ(written.size(), 5u);
  VerifyOptions o;
  o.only_scenes = {"drop", "slide"};
  for (const Verdict& v : verify_directory(dir.string(), o, nullptr)) EXPECT_TRUE(v.ok) << v.message;
  // Verifying all scenes: the eight without files are reported missing.
  int missing = 0;
  for (const Verdict& v : verify_directory(dir.string(), VerifyOptions{}, nullptr))
    if (!v.ok) {
      ++missing;
      EXPECT_NE(v.message.find("missing"), std::string::npos) << v.message;
    }
  EXPECT_EQ(missing, static_cast<int>(builtin_scene_names().size()) - 2);
  fs::remove_all(dir);
}

TEST(VectorsGenerator, IsDeterministic) {
  EXPECT_EQ(to_text(generate_formulas()), to_text(generate_formulas()));
  EXPECT_EQ(to_text(generate_scene_vectors(*builtin_scene("tip_edge"))),
            to_text(generate_scene_vectors(*builtin_scene("tip_edge"))));
}

TEST(VectorsGenerator, TextFormRoundTrips) {
  const Json doc = generate_scene_vectors(*builtin_scene("bounce"));
  const std::string text = to_text(doc);
  EXPECT_EQ(Json::parse(text), doc);
  EXPECT_EQ(to_text(Json::parse(text)), text);
}

TEST(VectorsGenerator, ParamsTableCoversEveryParamsField) {
  EXPECT_TRUE(param_fields_complete())
      << "Params<Q16> has a member that vectors/src/params_json.cpp param_fields() does not list: add it there.";
}

TEST(VectorsGenerator, EveryArithmeticOperationAndFormulaHasCases) {
  const Json a = generate_arithmetic();
  ASSERT_EQ(a["testGroups"].size(), arithmetic_operations().size());
  for (const Json& g : a["testGroups"]) EXPECT_GE(g["tests"].size(), 20u) << g["operation"];
  const Json f = generate_formulas();
  ASSERT_EQ(f["testGroups"].size(), formula_functions().size());
  for (const Json& g : f["testGroups"])
    EXPECT_GE(g["tests"].size(), g["function"] == "params" ? 2u : 20u) << g["function"];
}

// The formula group's test of the given comment.
const Json& formula_case(const Json& doc, const std::string& function, const std::string& comment) {
  for (const Json& g : doc["testGroups"])
    if (g["function"] == function)
      for (const Json& t : g["tests"])
        if (t["comment"] == comment) return t;
  throw std::runtime_error("no " + function + " case '" + comment + "'");
}

// eq 97, independently of the engine's code: touching contacts target the
// bounce -e v (v = min(v_n0, 0), floored product); a contact with a gap never
// targets more than that bounce (a bounce from a gap adds no energy) and,
// when it does not bounce, targets penetration / dt.
TEST(VectorsGenerator, TargetVelocityCasesFollowEq97) {
  const Json f = generate_formulas();
  int touching = 0, bounced = 0, open = 0;
  for (const Json& g : f["testGroups"]) {
    if (g["function"] != "contact_target_velocity") continue;
    const std::int64_t inv_dt = g["shared"]["inv_dt"];
    for (const Json& t : g["tests"]) {
      const std::int64_t pen = t["in"]["penetration"], e = t["in"]["e"], v_n0 = t["in"]["v_n0"];
      const std::int64_t v = std::min<std::int64_t>(v_n0, 0);
      // round(n / 2^16) to nearest, ties to even (the Q16 product, Fix 11).
      auto r16 = [](std::int64_t n) {
        const std::int64_t q = n >> 16, r = n & 0xFFFF;
        return q + ((r > 0x8000 || (r == 0x8000 && (q & 1) != 0)) ? 1 : 0);
      };
      const std::int64_t bounce = -r16(e * v);  // -(e * v) in Q16: rounded, then negated
      const std::int64_t target = t["out"]["target"];
      if (pen >= 0) {
        EXPECT_EQ(target, bounce) << t["tcId"];
        ++touching;
      } else if (target == r16(pen * inv_dt)) {
        ++open;
      } else {
        EXPECT_GE(target, 0) << t["tcId"];
        EXPECT_LE(target, bounce) << t["tcId"];
        ++bounced;
      }
    }
  }
  EXPECT_GT(touching, 3);
  EXPECT_GT(bounced, 3);
  EXPECT_GT(open, 3);
}

// eq 99, independently of the engine's code: a body landing level with its
// bottom corners gets, in total, the impulse that stops its fall (m dv) from
// one visit, however many corners touch; without the split factor the 4
// corners of the tall box would push 3.8 times too hard, the 8 sunk corners
// of the cube 2 times.
TEST(VectorsGenerator, ManifoldSplitSharesOneImpulse) {
  const Json f = generate_formulas();
  const Json& flat = formula_case(f, "manifold_visit", "unit cube flat: o = 1 exactly, split 1");
  const std::int64_t fall = -flat["in"]["a"]["v"][1].get<std::int64_t>();  // m = 1 kg: m dv = -v_y
  for (const char* comment : {"unit cube flat: o = 1 exactly, split 1", "unit cube, all 8 corners sunk: o = 2",
                              "tall thin box (0.2 x 2 x 0.2 m) standing: o about 3.8"}) {
    const Json& t = formula_case(f, "manifold_visit", comment);
    std::int64_t total = 0;
    for (const Json& pt : t["out"]["points"]) total += pt["j_n"].get<std::int64_t>();
    EXPECT_NEAR(static_cast<double>(total), static_cast<double>(fall), 8.0) << comment;
    EXPECT_NEAR(static_cast<double>(t["out"]["a"]["v"][1].get<std::int64_t>()), 0.0, 8.0) << comment;
  }
}

TEST(VectorsGenerator, EdgeCasesRaiseTheirFlags) {
  const Json a = generate_arithmetic();
  std::map<std::string, int> seen;
  for (const Json& g : a["testGroups"])
    for (const Json& t : g["tests"])
      for (const Json& s : t["status"]) ++seen[s.get<std::string>()];
  for (const char* flag : {"overflow", "div_by_zero", "sqrt_negative", "normalize_zero", "invalid"})
    EXPECT_GT(seen[flag], 0) << flag;
}

}  // namespace
}  // namespace lockstep::vectors
