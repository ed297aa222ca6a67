// Tests of the JSON scene loader/writer (reference/src/scene_json.cpp):
// the bad-scene corpus (tests/data/bad_scenes, expectations in EXPECTED.txt),
// the example scenes (tests/data/scenes), unit tests of the format's rules,
// and rapidcheck properties: random valid scenes round-trip bit for bit, and
// a random numeric field replaced by an out-of-range or ill-typed value is
// always rejected with a SceneError naming exactly that field.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "lockstep/scene.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep {
namespace {

using json = nlohmann::json;

// If one of these fails, a field was added to (or removed from) scene.hpp:
// teach reference/src/scene_json.cpp (reader, writer, Comparer, the constants
// table), docs/SCENES.md and spec_for() below about it, then update the count.
#if defined(__x86_64__) || defined(__aarch64__) || defined(_M_X64) || defined(_M_ARM64)
static_assert(sizeof(Material) == 2 * sizeof(double), "Material changed: update scene_json");
static_assert(sizeof(Constants) == (33 + 3) * 8, "Constants changed: update scene_json (33 doubles, 3 ints)");
static_assert(sizeof(Effects) == 9, "Effects changed: update scene_json");
static_assert(sizeof(BodyDesc) == 19 * 8 + 8, "BodyDesc changed: update scene_json");
static_assert(sizeof(GroundDesc) == 4 * 8, "GroundDesc changed: update scene_json");
#endif

// tests/data: the LOCKSTEP_TEST_DATA_DIR definition, else the environment
// variable of that name, else the working directory if it is tests/data,
// else tests/data below it.
std::filesystem::path data_dir() {
#ifdef LOCKSTEP_TEST_DATA_DIR
  return LOCKSTEP_TEST_DATA_DIR;
#else
  if (const char* e = std::getenv("LOCKSTEP_TEST_DATA_DIR")) return e;
  if (std::filesystem::is_directory("bad_scenes")) return ".";
  return "tests/data";
#endif
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

constexpr const char* kHeader = R"("format": "lockstep-scene", "version": 1)";

// parse_scene of a document; the error if it throws.
std::string error_of(const std::string& text, std::string* field = nullptr) {
  try {
    parse_scene(text, "test.json");
  } catch (const SceneError& e) {
    if (field) *field = e.field;
    return e.what();
  }
  return "";
}

// ---------------------------------------------------------------------------
// The bad-scene corpus
// ---------------------------------------------------------------------------

struct Expected {
  std::string file, field, substring;
};

std::vector<Expected> read_expected() {
  std::vector<Expected> out;
  std::ifstream in(data_dir() / "bad_scenes" / "EXPECTED.txt");
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const auto a = line.find(" | ");
    const auto b = a == std::string::npos ? a : line.find(" | ", a + 3);
    if (b == std::string::npos) {
      ADD_FAILURE() << "malformed EXPECTED.txt line: " << line;
      continue;
    }
    out.push_back({line.substr(0, a), line.substr(a + 3, b - a - 3), line.substr(b + 3)});
  }
  return out;
}

TEST(BadScenes, CorpusIsCompleteAndLargeEnough) {
  const auto expected = read_expected();
  EXPECT_GE(expected.size(), 30u);
  std::set<std::string> listed;
  for (const auto& e : expected) EXPECT_TRUE(listed.insert(e.file).second) << "listed twice: " << e.file;
  std::set<std::string> present;
  for (const auto& f : std::filesystem::directory_iterator(data_dir() / "bad_scenes")) {
    if (f.path().extension() == ".json") present.insert(f.path().filename().string());
  }
  EXPECT_EQ(listed, present) << "every bad_scenes/*.json must have one EXPECTED.txt line";
}

TEST(BadScenes, EachFailsWithItsExpectedFieldAndMessage) {
  const auto expected = read_expected();
  ASSERT_FALSE(expected.empty());
  for (const auto& e : expected) {
    const std::string path = (data_dir() / "bad_scenes" / e.file).string();
    SCOPED_TRACE(e.file);
    try {
      load_scene_file(path);
      ADD_FAILURE() << e.file << " was accepted";
    } catch (const SceneError& err) {
      const std::string what = err.what();
      EXPECT_EQ(err.field, e.field) << what;
      EXPECT_NE(what.find(e.substring), std::string::npos) << "message: " << what << "\nexpected: " << e.substring;
      EXPECT_EQ(what.rfind(path, 0), 0u) << "the message must start with the file name: " << what;
      // Every field error names its field in the message too.
      if (!e.field.empty() && e.substring.find("nested") == std::string::npos) {
        EXPECT_NE(what.find(e.field.substr(0, e.field.find('.'))), std::string::npos) << what;
      }
    }
  }
}

TEST(BadScenes, TooManyBodies) {
  std::string text = std::string("{") + kHeader + R"(, "bodies": [)";
  const std::size_t n = kMaxSceneBodies + 1;
  text.reserve(text.size() + 5 * n + 4);
  for (std::size_t i = 0; i < n; ++i) text += i ? ",null" : "null";
  text += "]}";
  std::string field;
  const std::string msg = error_of(text, &field);
  EXPECT_EQ(field, "bodies");
  EXPECT_NE(msg.find("1000001 bodies given: at most 1000000"), std::string::npos) << msg;
}

TEST(BadScenes, UnreadableFile) {
  try {
    load_scene_file((data_dir() / "no_such_scene.json").string());
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open the scene file"), std::string::npos) << e.what();
    EXPECT_EQ(e.field, "");
  }
  try {
    load_scene_file((data_dir() / "scenes").string());
    FAIL() << "a directory was read";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("it is a directory"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------
// Example scenes
// ---------------------------------------------------------------------------

TEST(ExampleScenes, AllLoadAndRoundTrip) {
  int n = 0;
  for (const auto& f : std::filesystem::directory_iterator(data_dir() / "scenes")) {
    if (f.path().extension() != ".json") continue;
    ++n;
    SCOPED_TRACE(f.path().string());
    const Scene s = load_scene_file(f.path().string());
    const Scene back = parse_scene(scene_to_json(s), "round trip");
    EXPECT_TRUE(scenes_equal(s, back)) << scene_difference(s, back);
    EXPECT_NO_THROW(validate_scene(s));
  }
  EXPECT_GE(n, 4);
}

TEST(ExampleScenes, MinimalTakesEveryDefault) {
  const Scene s = load_scene_file((data_dir() / "scenes" / "minimal.json").string());
  Scene want;
  want.bodies.resize(1);
  want.bodies[0].position = {0.0, 3.0, 0.0};
  EXPECT_TRUE(scenes_equal(s, want)) << scene_difference(s, want);
}

TEST(ExampleScenes, RawValuesAreExact) {
  const Scene s = load_scene_file((data_dir() / "scenes" / "raw_values.json").string());
  EXPECT_TRUE(same_bits(s.constants.dt, 1092.0 / 65536.0));
  EXPECT_TRUE(same_bits(s.constants.gravity.y, -642908.0 / 65536.0));
  EXPECT_TRUE(same_bits(s.ground.height, -0.5));
  ASSERT_EQ(s.bodies.size(), 1u);
  const BodyDesc& b = s.bodies[0];
  EXPECT_TRUE(same_bits(b.half_extents.x, 0.5));
  EXPECT_TRUE(same_bits(b.half_extents.y, 0.25));
  EXPECT_TRUE(same_bits(b.mass, 2.0));
  EXPECT_TRUE(same_bits(b.position.x, -1.0));
  EXPECT_TRUE(same_bits(b.position.y, 1.5));
  EXPECT_TRUE(same_bits(b.position.z, 1.0 / 65536.0));
  EXPECT_TRUE(same_bits(b.velocity.z, -1000.0));
  EXPECT_TRUE(same_bits(b.material.restitution, 0.0));
  EXPECT_TRUE(same_bits(b.material.friction, 1.0));
}

TEST(ExampleScenes, RampOverridesOnlyWhatItGives) {
  const Scene s = load_scene_file((data_dir() / "scenes" / "ramp.json").string());
  const Constants d;
  EXPECT_EQ(s.constants.solver_iterations, 8);
  EXPECT_EQ(s.constants.drowsy_frames, 20);
  EXPECT_EQ(s.constants.sleep_frames, 60);
  EXPECT_EQ(s.constants.linear_damping, 0.0);
  EXPECT_EQ(s.constants.angular_damping, d.angular_damping);
  EXPECT_EQ(s.constants.kp, d.kp);
  EXPECT_FALSE(s.effects.sleep);
  EXPECT_FALSE(s.effects.sdf);
  EXPECT_TRUE(s.effects.gravity);
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_TRUE(s.bodies[0].is_static);
  EXPECT_EQ(s.bodies[0].mass, 1.0);  // omitted: the default
  EXPECT_EQ(s.bodies[1].mass, 2.5);
}

TEST(ExampleScenes, SdfVolumes) {
  const Scene s = load_scene_file((data_dir() / "scenes" / "sdf_volumes.json").string());
  ASSERT_EQ(s.sdfs.size(), 3u);
  EXPECT_EQ(s.sdfs[0].name, "small_bowl");
  EXPECT_EQ(s.sdfs[0].values.size(), 17u * 11u * 17u);
  EXPECT_EQ(s.sdfs[0].material.friction, 0.8);
  EXPECT_EQ(s.sdfs[1].values.size(), 17u * 9u * 17u);
  const SdfDesc& slab = s.sdfs[2];
  ASSERT_EQ(slab.values.size(), 12u);
  EXPECT_EQ(slab.values[0], -1.0);
  EXPECT_EQ(slab.values[2], 0.0);
  EXPECT_EQ(slab.values[10], 1.0);
  // The generated bowl: centre (0,4,0) radius 3 over [-4,4]x[0,5]x[-4,4], 0.5 m
  // samples. Sample (8, 2, 8) is (0, 1, 0), on the bowl's bottom surface.
  const SdfDesc& bowl = s.sdfs[0];
  auto at = [&](int i, int j, int k) { return bowl.values[static_cast<std::size_t>(i + bowl.nx * (j + bowl.ny * k))]; };
  EXPECT_EQ(at(8, 2, 8), 0.0);
  EXPECT_EQ(at(8, 4, 8), 1.0);   // (0, 2, 0): 1 m inside the hollow
  EXPECT_EQ(at(8, 0, 8), -1.0);  // (0, 0, 0): 1 m into the solid
  EXPECT_EQ(at(0, 10, 0), 1.0);  // (-4, 5, -4): above the rim plane y = 4
}

// The complete example of docs/SCENES.md loads.
TEST(ExampleScenes, DocumentationExampleLoads) {
  const auto doc = data_dir() / ".." / ".." / "docs" / "SCENES.md";
  std::ifstream in(doc);
  if (!in) GTEST_SKIP() << "no " << doc;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string md = ss.str();
  const auto start = md.find("```json\n");
  ASSERT_NE(start, std::string::npos);
  const auto end = md.find("```", start + 8);
  ASSERT_NE(end, std::string::npos);
  const Scene s = parse_scene(md.substr(start + 8, end - start - 8), "docs/SCENES.md example");
  EXPECT_EQ(s.name, "ramp_and_bowl");
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[2].position.y, 9.0);
  ASSERT_EQ(s.sdfs.size(), 2u);
  EXPECT_EQ(s.sdfs[0].values.size(), 33u * 21u * 33u);
  EXPECT_EQ(s.constants.solver_iterations, 8);
}

// ---------------------------------------------------------------------------
// Unit tests of the format's rules
// ---------------------------------------------------------------------------

TEST(SceneJson, PairContactModelIsReadWrittenAndChecked) {
  Scene s = parse_scene(R"({"format": "lockstep-scene", "version": 1, "pair_contacts": "aabb"})", "scene.json");
  EXPECT_EQ(s.pair_contacts, PairModel::kAabb);
  EXPECT_EQ(parse_scene(scene_to_json(s), "round.json").pair_contacts, PairModel::kAabb);
  EXPECT_EQ(parse_scene(R"({"format": "lockstep-scene", "version": 1})", "scene.json").pair_contacts,
            PairModel::kOrientedBox);
  try {
    parse_scene(R"({"format": "lockstep-scene", "version": 1, "pair_contacts": "obb"})", "scene.json");
    FAIL() << "an unknown pair model was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("pair_contacts: \"obb\" is not a pair contact model: must be \"oriented_box\""),
              std::string::npos) << e.what();
  }
}

TEST(SceneJson, WriterPinsEveryField) {
  Scene s;
  const json j = json::parse(scene_to_json(s));
  EXPECT_EQ(j.at("format"), "lockstep-scene");
  EXPECT_EQ(j.at("version"), 1);
  EXPECT_EQ(j.at("effects").size(), 9u);
  EXPECT_EQ(j.at("constants").size(), 34u);
  EXPECT_EQ(j.at("constants").at("solver_iterations"), 8);
  EXPECT_EQ(j.at("pair_contacts"), "oriented_box");
  EXPECT_TRUE(j.at("constants").at("solver_iterations").is_number_integer());
  EXPECT_TRUE(j.at("constants").at("kp").is_number_float());  // written 30.0
}

TEST(SceneJson, SignedZeroAndExtremeDoublesRoundTrip) {
  Scene s;
  BodyDesc b;
  b.position = {-0.0, 4.9406564584124654e-324, -29999.999999999996};
  b.velocity = {0.1, 1.0 / 3.0, -999.9999999999999};
  b.half_extents = {1.0 / 256.0, 1024.0, 0.30000000000000004};
  b.orientation = {-0.0, 0.5, -0.0, 0.0};
  s.bodies.push_back(b);
  s.ground.height = -0.0;
  const std::string text = scene_to_json(s);
  const Scene back = parse_scene(text, "t");
  EXPECT_TRUE(scenes_equal(s, back)) << scene_difference(s, back);
  EXPECT_TRUE(std::signbit(back.bodies[0].position.x));
  EXPECT_TRUE(std::signbit(back.ground.height));
  EXPECT_EQ(scene_to_json(back), text);
}

TEST(SceneJson, ComparisonIsBitwiseAndNamesTheField) {
  Scene a;
  a.bodies.resize(3);
  Scene b = a;
  EXPECT_TRUE(scenes_equal(a, b));
  EXPECT_EQ(scene_difference(a, b), "");
  b.bodies[2].position.y = -0.0;
  EXPECT_FALSE(scenes_equal(a, b));
  EXPECT_EQ(scene_difference(a, b), "bodies[2].position[1]: 0 vs -0");
  b = a;
  b.constants.sleep_frames = 31;
  EXPECT_EQ(scene_difference(a, b), "constants.sleep_frames: 30 vs 31");
  b = a;
  b.sdfs.resize(1);
  EXPECT_EQ(scene_difference(a, b), "sdfs (count): 0 vs 1");
}

TEST(SceneJson, WriterRejectsNonFiniteValuesNamingTheField) {
  Scene s;
  s.bodies.resize(2);
  s.bodies[1].velocity.z = std::numeric_limits<double>::quiet_NaN();
  try {
    scene_to_json(s);
    FAIL() << "NaN written";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "bodies[1].velocity[2]");
  }
  s.bodies[1].velocity.z = 0.0;
  s.sdfs.resize(1);
  s.sdfs[0].values.assign(8, 0.0);
  s.sdfs[0].max = {1, 1, 1};
  s.sdfs[0].values[5] = -std::numeric_limits<double>::infinity();
  try {
    validate_scene(s);
    FAIL() << "-inf accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "sdfs[0].values[5]");
  }
}

TEST(SceneJson, ValidateSceneUsesTheLoaderRules) {
  Scene s;
  s.name = "mine";
  s.bodies.resize(1);
  EXPECT_NO_THROW(validate_scene(s));
  s.bodies[0].mass = 0.0;
  try {
    validate_scene(s);
    FAIL() << "mass 0 accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "bodies[0].mass");
    EXPECT_NE(std::string(e.what()).find("<scene mine>: bodies[0].mass: 0.0 is out of range"), std::string::npos)
        << e.what();
  }
  s.bodies[0].mass = 1.0;
  s.sdfs.resize(1);  // 2x2x2 but no values
  s.sdfs[0].max = {1, 1, 1};
  try {
    validate_scene(s);
    FAIL() << "empty SDF accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field, "sdfs[0].values");
  }
}

TEST(SceneJson, IntegersMayBeWrittenAsIntegralFloats) {
  const Scene s = parse_scene(std::string("{") + kHeader + R"(, "frames": 1e3, "constants": {"solver_iterations": 8.0}})", "t");
  EXPECT_EQ(s.frames, 1000);
  EXPECT_EQ(s.constants.solver_iterations, 8);
  std::string field;
  EXPECT_NE(error_of(std::string("{") + kHeader + R"(, "frames": {"raw": 65536}})", &field).find("must be an integer"),
            std::string::npos);
  EXPECT_EQ(field, "frames");
  EXPECT_NE(error_of(std::string("{") + kHeader + R"(, "frames": 18446744073709551615})", &field).find("out of range"),
            std::string::npos);
  EXPECT_EQ(field, "frames");
  EXPECT_NE(error_of(std::string("{") + kHeader + R"(, "frames": -9223372036854775808})", &field).find("out of range"),
            std::string::npos);
}

TEST(SceneJson, RawBoundaries) {
  auto mass = [](const std::string& raw) {
    return std::string("{") + kHeader + R"(, "bodies": [{"position": [0, 0, 0], "mass": {"raw": )" + raw + "}}]}";
  };
  EXPECT_EQ(parse_scene(mass("655360000"), "t").bodies[0].mass, 10000.0);
  EXPECT_EQ(parse_scene(mass("1"), "t").bodies[0].mass, 1.0 / 65536.0);
  std::string field;
  EXPECT_NE(error_of(mass("0"), &field).find("is out of range: must be in (0, 10000] kg"), std::string::npos);
  EXPECT_NE(error_of(mass("-2147483649"), &field).find("the raw value is out of range"), std::string::npos);
  EXPECT_EQ(field, "bodies[0].mass");
  const std::string pos = std::string("{") + kHeader +
                          R"(, "bodies": [{"position": [{"raw": -2147483648}, {"raw": 2147483647}, 0]}]})";
  EXPECT_NE(error_of(pos, &field).find("outside the Q16.16 range"), std::string::npos);
  EXPECT_EQ(field, "bodies[0].position[0]");
}

TEST(SceneJson, StaticBodiesMayHaveZeroMass) {
  const Scene s = parse_scene(
      std::string("{") + kHeader + R"(, "bodies": [{"position": [0, 0, 0], "static": true, "mass": 0}])" + "}", "t");
  EXPECT_TRUE(s.bodies[0].is_static);
  EXPECT_EQ(s.bodies[0].mass, 0.0);
}

TEST(SceneJson, SyntaxErrorsGiveLineAndColumn) {
  const std::string text = std::string("{\n") + kHeader + ",\n  \"frames\": 60,,\n}";
  std::string field;
  const std::string msg = error_of(text, &field);
  EXPECT_NE(msg.find("test.json:3:16: JSON syntax error"), std::string::npos) << msg;
}

TEST(SceneJson, UnicodeNamesRoundTrip) {
  Scene s;
  s.name = "caf\xC3\xA9 \"quoted\" back\\slash \xE4\xB8\x96 tab\t";
  const Scene back = parse_scene(scene_to_json(s), "t");
  EXPECT_EQ(back.name, s.name);
}

TEST(SceneJson, ValuesOfTheBriefExamples) {
  std::string f;
  EXPECT_NE(error_of(std::string("{") + kHeader + R"(, "sdfs": [{"min": [0,0,0], "max": [3,3,3], "resolution": [4,4,4], "values": [)" +
                         [] {
                           std::string v;
                           for (int i = 0; i < 100; ++i) v += i ? ",0" : "0";
                           return v;
                         }() + "]}]}",
                     &f)
                .find("sdfs[0].values: 100 values given, resolution 4x4x4 needs 64"),
            std::string::npos);
}

// ---------------------------------------------------------------------------
// rapidcheck: random valid scenes and their mutations
// ---------------------------------------------------------------------------

// The documented range of each numeric field (docs/SCENES.md), by path.
struct Spec {
  double lo, hi;
  bool lo_open = false, hi_open = false;
  bool integer = false;
};

const std::map<std::string, Spec>& constant_ranges() {
  static const std::map<std::string, Spec> m = {
      {"dt", {1.0 / 65536.0, 0.1}},
      {"gravity", {-1000, 1000}},
      {"linear_damping", {0, 1000}},
      {"angular_damping", {0, 1000}},
      {"cell_size", {0.25, 1024}},
      {"slop", {0, 1}},
      {"baumgarte", {0, 1}},
      {"solver_iterations", {1, 64, false, false, true}},
      {"contact_tolerance", {0, 1}},
      {"converged_speed", {0, 100}},
      {"kp", {0, 1000}},
      {"kd", {0, 1000}},
      {"speed_factor_min", {0, 100}},
      {"speed_factor_max", {0, 100}},
      {"support_normal_min", {0, 1}},
      {"align_fine", {0, 1, true}},
      {"align_good", {0, 1, true}},
      {"align_fair", {0, 1, true}},
      {"damp_fine", {0, 1}},
      {"damp_good", {0, 1}},
      {"damp_fair", {0, 1}},
      {"rest_speed", {0, 100}},
      {"restitution_min_speed", {0, 100}},
      {"settle_speed", {0, 100}},
      {"settle_damping", {0, 1}},
      {"sleep_linear", {0, 100}},
      {"sleep_angular", {0, 100}},
      {"sleep_alignment", {0, 1, true}},
      {"drowsy_frames", {1, 100000, false, false, true}},
      {"drowsy_damping", {0, 1}},
      {"sleep_frames", {1, 100000, false, false, true}},
      {"wake_speed", {0, 100}},
      {"wake_penetration", {0, 10}},
      {"wake_support_distance", {0, 10}},
  };
  return m;
}

// "bodies[12].position[1]" -> "position"; "constants.gravity[1]" -> "gravity".
std::string last_name(const std::string& path) {
  std::string p = path;
  if (!p.empty() && p.back() == ']') p = p.substr(0, p.rfind('['));
  const auto dot = p.rfind('.');
  return dot == std::string::npos ? p : p.substr(dot + 1);
}

Spec spec_for(const std::string& path, bool is_static_body) {
  const std::string name = last_name(path);
  if (path == "version") return {1, 1, false, false, true};
  if (path == "frames") return {1, 10000000, false, false, true};
  if (path.rfind("constants.", 0) == 0) return constant_ranges().at(name);
  if (name == "restitution") return {0, 1};
  if (name == "friction") return {0, 4};
  if (path == "ground.height") return {-30000, 30000};
  if (name == "half_extents") return {1.0 / 256.0, 1024};
  if (name == "mass") return is_static_body ? Spec{0, 10000} : Spec{0, 10000, true};
  if (name == "position") return {-30000, 30000};
  if (name == "orientation") return {-2, 2};
  if (name == "velocity" || name == "angular_velocity") return {-1000, 1000};
  if (name == "min" || name == "max" || name == "values") return {-30000, 30000};
  if (name == "resolution") return {2, 256, false, false, true};
  ADD_FAILURE() << "no range for " << path;
  return {0, 0};
}

bool inside(double v, const Spec& s) {
  return (s.lo_open ? v > s.lo : v >= s.lo) && (s.hi_open ? v < s.hi : v <= s.hi);
}

// A random value inside the spec: a bound, a Q16.16 multiple, a short
// decimal, signed zero or an arbitrary double.
double gen_in(const Spec& s) {
  double v = 0.0;
  switch (*rc::gen::inRange(0, 7)) {
    case 0: v = s.lo; break;
    case 1: v = s.hi; break;
    case 2: {
      const auto lo = static_cast<std::int64_t>(std::ceil(s.lo * 65536.0));
      const auto hi = static_cast<std::int64_t>(std::floor(s.hi * 65536.0));
      v = static_cast<double>(*rc::gen::inRange<std::int64_t>(lo, hi + 1)) / 65536.0;
      break;
    }
    case 3: {
      const auto lo = static_cast<std::int64_t>(std::ceil(s.lo * 1000.0));
      const auto hi = static_cast<std::int64_t>(std::floor(s.hi * 1000.0));
      v = static_cast<double>(*rc::gen::inRange<std::int64_t>(lo, hi + 1)) / 1000.0;
      break;
    }
    case 4: v = -0.0; break;
    default: {
      const auto k = *rc::gen::inRange<std::uint64_t>(0, std::uint64_t{1} << 53);
      v = s.lo + (s.hi - s.lo) * (static_cast<double>(k) / 9007199254740992.0);
      break;
    }
  }
  if (!inside(v, s)) v = s.lo + (s.hi - s.lo) * 0.5;
  return v;
}
int gen_int(const Spec& s) {
  return *rc::gen::inRange(static_cast<int>(s.lo), static_cast<int>(s.hi) + 1);
}
double gen_path(const std::string& path) { return gen_in(spec_for(path, false)); }
Vec3d gen_vec(const std::string& path) {
  return {gen_path(path + "[0]"), gen_path(path + "[1]"), gen_path(path + "[2]")};
}
Material gen_material() { return {gen_path("x.restitution"), gen_path("x.friction")}; }

Scene random_scene() {
  Scene s;
  static const std::vector<std::string> pieces = {"a", "Z", "0", "_", " ", "\"", "\\", "/", "\n", "\xC3\xA9", "\xE4\xB8\x96"};
  s.name.clear();
  const int name_len = *rc::gen::inRange(0, 8);
  for (int i = 0; i < name_len; ++i) s.name += *rc::gen::elementOf(pieces);
  s.frames = *rc::gen::inRange(1, 10000001);
  bool* effects[] = {&s.effects.gravity, &s.effects.damping, &s.effects.ground, &s.effects.contacts,
                     &s.effects.friction, &s.effects.restitution, &s.effects.settling, &s.effects.sleep, &s.effects.sdf};
  for (bool* e : effects) *e = *rc::gen::arbitrary<bool>();
  // Constants: each one either kept at its default or drawn in range.
  Constants& c = s.constants;
  auto maybe = [](auto& field, auto draw) {
    if (*rc::gen::arbitrary<bool>()) field = draw();
  };
  const auto& cr = constant_ranges();
  maybe(c.dt, [&] { return gen_in(cr.at("dt")); });
  maybe(c.gravity, [&] { return gen_vec("constants.gravity"); });
  struct D {
    const char* n;
    double* p;
  };
  for (D d : {D{"linear_damping", &c.linear_damping}, D{"angular_damping", &c.angular_damping},
              D{"cell_size", &c.cell_size}, D{"slop", &c.slop}, D{"baumgarte", &c.baumgarte},
              D{"contact_tolerance", &c.contact_tolerance}, D{"converged_speed", &c.converged_speed}, D{"kp", &c.kp}, D{"kd", &c.kd},
              D{"speed_factor_min", &c.speed_factor_min}, D{"speed_factor_max", &c.speed_factor_max},
              D{"support_normal_min", &c.support_normal_min}, D{"align_fine", &c.align_fine},
              D{"align_good", &c.align_good}, D{"align_fair", &c.align_fair}, D{"damp_fine", &c.damp_fine},
              D{"damp_good", &c.damp_good}, D{"damp_fair", &c.damp_fair}, D{"rest_speed", &c.rest_speed},
              D{"restitution_min_speed", &c.restitution_min_speed}, D{"settle_speed", &c.settle_speed},
              D{"settle_damping", &c.settle_damping}, D{"sleep_linear", &c.sleep_linear},
              D{"sleep_angular", &c.sleep_angular}, D{"sleep_alignment", &c.sleep_alignment},
              D{"drowsy_damping", &c.drowsy_damping}, D{"wake_speed", &c.wake_speed},
              D{"wake_penetration", &c.wake_penetration}, D{"wake_support_distance", &c.wake_support_distance}}) {
    maybe(*d.p, [&] { return gen_in(cr.at(d.n)); });
  }
  maybe(c.solver_iterations, [&] { return gen_int(cr.at("solver_iterations")); });
  maybe(c.drowsy_frames, [&] { return gen_int(cr.at("drowsy_frames")); });
  maybe(c.sleep_frames, [&] { return gen_int(cr.at("sleep_frames")); });
  // The rules between constants.
  if (!(c.linear_damping < 1.0 / c.dt)) c.linear_damping = 0.0;
  if (!(c.angular_damping < 1.0 / c.dt)) c.angular_damping = 0.0;
  if (c.speed_factor_min > c.speed_factor_max) std::swap(c.speed_factor_min, c.speed_factor_max);
  if (c.drowsy_frames > c.sleep_frames) std::swap(c.drowsy_frames, c.sleep_frames);

  s.ground.present = *rc::gen::arbitrary<bool>();
  s.ground.height = gen_path("ground.height");
  s.ground.material = gen_material();

  const int nb = *rc::gen::inRange(0, 6);
  for (int i = 0; i < nb; ++i) {
    BodyDesc b;
    b.is_static = *rc::gen::arbitrary<bool>();
    b.asleep = *rc::gen::arbitrary<bool>();
    b.half_extents = gen_vec("half_extents");
    b.mass = gen_in(spec_for("mass", b.is_static));
    b.position = gen_vec("position");
    const Spec unit{-1, 1};
    b.orientation = {gen_in(unit), gen_in(unit), gen_in(unit), gen_in(unit)};
    const Quatd& q = b.orientation;
    if (std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z) < 0.5) b.orientation.w = 1.0;
    b.velocity = gen_vec("velocity");
    b.angular_velocity = gen_vec("angular_velocity");
    b.material = gen_material();
    s.bodies.push_back(b);
  }
  const int ns = *rc::gen::inRange(0, 3);
  for (int i = 0; i < ns; ++i) {
    SdfDesc d;
    d.name = *rc::gen::elementOf(std::vector<std::string>{"", "bowl", "a b"});
    d.nx = *rc::gen::inRange(2, 5);
    d.ny = *rc::gen::inRange(2, 5);
    d.nz = *rc::gen::inRange(2, 5);
    const Spec lo{-30000, 29000};
    const Spec ext{1, 1000};
    d.min = {gen_in(lo), gen_in(lo), gen_in(lo)};
    d.max = {d.min.x + gen_in(ext), d.min.y + gen_in(ext), d.min.z + gen_in(ext)};
    d.values.resize(static_cast<std::size_t>(d.nx * d.ny * d.nz));
    for (double& v : d.values) v = gen_path("values");
    d.material = gen_material();
    s.sdfs.push_back(d);
  }
  return s;
}

RC_GTEST_PROP(SceneJsonProperty, RandomValidScenesRoundTripExactly, ()) {
  const Scene s = random_scene();
  const std::string text = scene_to_json(s);
  Scene back;
  try {
    back = parse_scene(text, "random");
  } catch (const SceneError& e) {
    RC_FAIL(std::string("valid scene rejected: ") + e.what());
  }
  RC_ASSERT(scene_difference(s, back) == "");
  RC_ASSERT(scene_to_json(back) == text);
}

struct Leaf {
  json::json_pointer ptr;
  std::string path;
};

void collect_numbers(const json& j, const std::string& ptr, const std::string& path, std::vector<Leaf>& out) {
  if (j.is_number()) {
    out.push_back({json::json_pointer(ptr), path});
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      collect_numbers(*it, ptr + "/" + it.key(), path.empty() ? it.key() : path + "." + it.key(), out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      collect_numbers(j[i], ptr + "/" + std::to_string(i), path + "[" + std::to_string(i) + "]", out);
    }
  }
}

RC_GTEST_PROP(SceneJsonProperty, OutOfRangeOrIllTypedFieldIsRejectedByName, ()) {
  const Scene s = random_scene();
  json doc = json::parse(scene_to_json(s));
  std::vector<Leaf> leaves;
  collect_numbers(doc, "", "", leaves);
  RC_PRE(!leaves.empty());
  const Leaf& leaf = *rc::gen::elementOf(leaves);
  bool is_static = false;
  if (leaf.path.rfind("bodies[", 0) == 0) {
    const std::size_t i = std::stoul(leaf.path.substr(7));
    is_static = s.bodies.at(i).is_static;
  }
  const Spec spec = spec_for(leaf.path, is_static);
  json bad;
  const int kind = *rc::gen::inRange(0, 8);
  switch (kind) {
    case 0:  // just below the range
      if (spec.integer) bad = static_cast<std::int64_t>(spec.lo) - 1;
      else bad = spec.lo_open ? spec.lo : std::nextafter(spec.lo, -std::numeric_limits<double>::infinity());
      break;
    case 1:  // just above
      if (spec.integer) bad = static_cast<std::int64_t>(spec.hi) + 1;
      else bad = spec.hi_open ? spec.hi : std::nextafter(spec.hi, std::numeric_limits<double>::infinity());
      break;
    case 2: {  // far outside (Q16.16 range, double range)
      std::vector<double> far;
      for (double v : {-1e300, 1e300, 1e20, -40000.0, 40000.0}) {
        if (!inside(v, spec)) far.push_back(v);
      }
      bad = *rc::gen::elementOf(far);
      break;
    }
    case 3: bad = "1"; break;
    case 4: bad = nullptr; break;
    case 5: bad = true; break;
    case 6: bad = json::array({1}); break;
    default: bad = json{{"raw", std::int64_t{1} << 31}}; break;
  }
  doc[leaf.ptr] = bad;
  RC_TAG(kind);
  try {
    parse_scene(doc.dump(), "mutant.json");
    RC_FAIL("accepted " + leaf.path + " = " + bad.dump());
  } catch (const SceneError& e) {
    RC_LOG() << e.what() << "\n";
    RC_ASSERT(e.field == leaf.path);
    RC_ASSERT(std::string(e.what()).find("mutant.json: " + leaf.path + ": ") == 0);
  }
}

}  // namespace
}  // namespace lockstep
