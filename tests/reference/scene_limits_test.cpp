// Tests of validate_scene_for (reference/src/scene_limits.cpp): each derived
// quantity of a body (1/m, h^2 and h_b^2 + h_c^2, 3/(h_b^2 + h_c^2), the
// inverse inertia, the AABB) at both edges of its range for the fixed engine
// (just inside: accepted and World<Q16> builds; just outside: refused with the
// field, the value, the limit and a fix, and World<Q16> would have stopped at
// frame 0), the float and double limits, and every shipped scene accepted.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/scene.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/scene_limits.hpp"
#include "lockstep/world.hpp"

namespace lockstep {
namespace {

struct Refusal {
  bool refused = false;
  std::string field, message;
};

Refusal check(std::string_view type, const Scene& s) {
  try {
    validate_scene_for(type, s);
    return {};
  } catch (const SceneError& e) {
    return {true, e.field, e.what()};
  }
}

// One body above the ground, loaded through the JSON loader (so the format
// accepts it: the refusal is the engine's).
std::string exact(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
Scene one_body(double mass, Vec3d half, bool is_static = false) {
  const std::string json = std::string("{\"format\": \"lockstep-scene\", \"version\": 1, \"name\": \"limits\", \"bodies\": [{") +
                           "\"half_extents\": [" + exact(half.x) + ", " + exact(half.y) + ", " + exact(half.z) + "], " +
                           (is_static ? "\"static\": true" : "\"mass\": " + exact(mass)) + ", \"position\": [0, 200, 0]}]}";
  return parse_scene(json, "limits.json");
}
Scene cube(double mass, double h) { return one_body(mass, {h, h, h}); }

// Whether World<Q16> builds the scene (false: RunError at frame 0).
bool fixed_builds(const Scene& s) {
  try {
    World<Q16> w(s);
    return true;
  } catch (const RunError&) {
    return false;
  }
}

// Just inside: accepted by the check and built by World<Q16>. Just outside:
// refused naming `field` and each of `parts`, and World<Q16> stops at frame 0.
void expect_edge(const Scene& inside, const Scene& outside, const std::string& field,
                 const std::vector<std::string>& parts) {
  const Refusal in = check("fixed", inside);
  EXPECT_FALSE(in.refused) << in.message;
  EXPECT_TRUE(fixed_builds(inside));
  const Refusal out = check("fixed", outside);
  ASSERT_TRUE(out.refused) << "accepted just outside the range";
  EXPECT_EQ(out.field, field);
  for (const std::string& p : parts) EXPECT_NE(out.message.find(p), std::string::npos) << "no '" << p << "' in: " << out.message;
  EXPECT_NE(out.message.find("or run on float or double"), std::string::npos) << out.message;
  EXPECT_FALSE(fixed_builds(outside)) << "refused, but World<Q16> builds it: " << out.message;
  // The other engines run it.
  EXPECT_FALSE(check("double", outside).refused);
  EXPECT_FALSE(check("float", outside).refused);
}

// 1/m < 32768: the Q16.16 mass must round to at least 3 raw (m > 2.5 * 2^-16
// = 3.8147e-05 kg). A cube of half extent 8 m keeps its inverse inertia in
// range there, so 1/m is what fails.
TEST(SceneLimitsFixed, InverseMass) {
  expect_edge(cube(3.815e-05, 8), cube(3.814e-05, 8), "bodies[0].mass",
              {"bodies[0].mass = 3.814e-05 kg: the fixed engine's inverse mass 1/m = 26219.2 1/kg",
               "outside Q16.16's range |x| < 32768", "use a mass of at least 3.82e-05 kg"});
  // A mass that rounds to 0 in Q16.16 (below 2^-17 kg): 1/m divides by 0.
  const Refusal zero = check("fixed", cube(5e-06, 8));
  ASSERT_TRUE(zero.refused);
  EXPECT_NE(zero.message.find("inverse mass 1/m = 200000 1/kg"), std::string::npos) << zero.message;
  // The suggested mass is accepted.
  EXPECT_FALSE(check("fixed", cube(3.82e-05, 8)).refused);
}

// The issue's scenes: a 1e-5 kg and a 1e-4 kg unit cube, a 1 kg cube of half
// extent 1/256 = 0.0039 m (the format's smallest size), each with the field and a fix.
TEST(SceneLimitsFixed, TheIssuesScenes) {
  const Refusal a = check("fixed", cube(1e-05, 0.5));
  ASSERT_TRUE(a.refused);
  EXPECT_EQ(a.message,
            "<scene limits>: bodies[0].mass = 1e-05 kg: the fixed engine's inverse mass 1/m = 100000 1/kg is outside "
            "Q16.16's range |x| < 32768; use a mass of at least 0.000176 kg, or run on float or double");
  const Refusal b = check("fixed", cube(1e-04, 0.5));
  ASSERT_TRUE(b.refused);
  EXPECT_EQ(b.field, "bodies[0].mass");
  EXPECT_NE(b.message.find("inverse inertia I_x^-1 = 3/(m (h_y^2 + h_z^2)) = 60000 1/(kg m^2)"), std::string::npos) << b.message;
  const Refusal c = check("fixed", cube(1, 0.00390625));
  ASSERT_TRUE(c.refused);
  EXPECT_EQ(c.field, "bodies[0].half_extents");
  EXPECT_NE(c.message.find("at least 0.00731 m"), std::string::npos) << c.message;
  EXPECT_FALSE(fixed_builds(cube(1e-05, 0.5)));
  EXPECT_FALSE(fixed_builds(cube(1e-04, 0.5)));
  EXPECT_FALSE(fixed_builds(cube(1, 0.00390625)));
}

// The inverse inertia 3/(m (h_y^2 + h_z^2)) < 32768: a unit cube's
// 3/(h_y^2 + h_z^2) is 6, so 1/m must stay below 5461.33: the Q16.16 mass at
// least 12 raw (m > 11.5 * 2^-16 = 1.7548e-04 kg).
TEST(SceneLimitsFixed, InverseInertiaOverflow) {
  expect_edge(cube(1.76e-04, 0.5), cube(1.75e-04, 0.5), "bodies[0].mass",
              {"bodies[0].mass = 0.000175 kg", "inverse inertia I_x^-1 = 3/(m (h_y^2 + h_z^2)) = 34285.7 1/(kg m^2)",
               "outside Q16.16's range |x| < 32768", "use a mass of at least 0.000176 kg for these half extents"});
  // A flat box: the inertia about y (h_x^2 + h_z^2 small) is the one at fault.
  const Refusal flat = check("fixed", one_body(0.01, {0.01, 1, 0.01}));
  ASSERT_TRUE(flat.refused);
  EXPECT_NE(flat.message.find("inverse inertia I_y^-1 = 3/(m (h_z^2 + h_x^2))"), std::string::npos) << flat.message;
}

// An inverse inertia below half of Q16.16's step rounds to 0 and is accepted
// (documented): the engine allows for it, and such a body turns less than
// Q16.16 resolves. A cube of half extent 8 m: 3/(m 128) rounds to 0 above
// 3048 kg. The other edge of the inverse inertia is the overflow above.
TEST(SceneLimitsFixed, InverseInertiaRoundingToZeroIsAccepted) {
  for (const double m : {3048.0, 3049.0, 10000.0}) {
    const Scene s = cube(m, 8);
    EXPECT_FALSE(check("fixed", s).refused) << m;
    World<Q16> w(s);
    EXPECT_EQ(w.body(0).inv_inertia.x.raw() == 0, m > 3048.5) << m;
  }
  EXPECT_FALSE(check("fixed", *builtin_scene("drop")).refused);
}

// 3/(h_y^2 + h_z^2) < 32768, whatever the mass (World<Q16> forms it before
// multiplying by 1/m): the Q16.16 sum of squares at least 7 raw; a cube needs
// h^2 to round to 4 raw, h >= sqrt(3.5) / 256 = 0.0073079 m.
TEST(SceneLimitsFixed, SmallestSize) {
  expect_edge(cube(1, 0.00731), cube(1, 0.0073), "bodies[0].half_extents",
              {"bodies[0].half_extents = [0.0073, 0.0073, 0.0073] m: the fixed engine's 3/(h_y^2 + h_z^2) = 28147.9 1/m^2",
               "outside Q16.16's range |x| < 32768",
               "make every half extent at least 0.00731 m"});
  // Heavy does not help: the factor overflows before the mass enters.
  EXPECT_TRUE(check("fixed", cube(10000, 0.0073)).refused);
  // A thin plate is fine while its two other axes are large enough.
  EXPECT_FALSE(check("fixed", one_body(1, {0.5, 0.00390625, 0.5})).refused);
  // A static body has no inertia: the smallest size of the format is accepted.
  EXPECT_FALSE(check("fixed", one_body(0, {0.00390625, 0.00390625, 0.00390625}, true)).refused);
  EXPECT_TRUE(fixed_builds(one_body(0, {0.00390625, 0.00390625, 0.00390625}, true)));
}

// h_b^2 + h_c^2 < 32768 (a cube: h < 128 m) and each h^2 < 32768 (h < 181.02 m).
TEST(SceneLimitsFixed, LargestSize) {
  expect_edge(cube(1, 127.99), cube(1, 128), "bodies[0].half_extents",
              {"bodies[0].half_extents = [128, 128, 128] m: the fixed engine's h_y^2 + h_z^2 = 32768 m^2",
               "outside Q16.16's range |x| < 32768", "keep every half extent at most 127 m",
               "or make the body static"});
  expect_edge(one_body(1, {181, 1, 1}), one_body(1, {181.1, 1, 1}), "bodies[0].half_extents",
              {"h_x^2 = 32797.2 m^2", "outside Q16.16's range |x| < 32768", "keep every half extent at most 181 m"});
  // The format's largest static box is accepted.
  EXPECT_FALSE(check("fixed", one_body(0, {1024, 1024, 1024}, true)).refused);
  EXPECT_TRUE(fixed_builds(one_body(0, {1024, 1024, 1024}, true)));
}

// The AABB (eq 31): |p| + the rotated half extent < 32768. Within the format
// (|p| <= 30000 m, h <= 1024 m) it always holds; a scene built in code can
// break it. A static 1024 m cube turned 45 degrees about y reaches 1448.15 m.
TEST(SceneLimitsFixed, Aabb) {
  auto at = [](double x) {
    Scene s = one_body(0, {1024, 1024, 1024}, true);
    s.bodies[0].position = {x, 0, 0};
    s.bodies[0].orientation = {0.9238795325112867, 0, 0.3826834323650898, 0};  // 45 degrees about y
    return s;
  };
  EXPECT_FALSE(check("fixed", at(30000)).refused);  // the format's extreme
  EXPECT_FALSE(check("fixed", at(31310)).refused);
  const Refusal out = check("fixed", at(31330));
  ASSERT_TRUE(out.refused);
  EXPECT_EQ(out.field, "bodies[0].position");
  EXPECT_NE(out.message.find("AABB (eq 31) reaches |x| = 32778"), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("outside Q16.16's range |x| < 32768"), std::string::npos) << out.message;
  EXPECT_NE(out.message.find("towards the origin"), std::string::npos) << out.message;
}

// The first body at fault is named; the caller's Q16 status flags survive.
TEST(SceneLimitsFixed, FirstBodyAndFlags) {
  Scene s = cube(1, 0.5);
  s.bodies.push_back(s.bodies[0]);
  s.bodies.push_back(s.bodies[0]);
  s.bodies[2].mass = 1e-05;
  s.bodies[1].half_extents = {0.005, 0.005, 0.005};
  q16_clear_status();
  q16detail::raise(kQ16SqrtNegative);
  const Refusal r = check("fixed", s);
  EXPECT_EQ(r.field, "bodies[1].half_extents");
  EXPECT_EQ(q16_take_status(), static_cast<std::uint32_t>(kQ16SqrtNegative));
  EXPECT_FALSE(check("fixed", cube(1, 0.5)).refused);
  EXPECT_EQ(q16_take_status(), 0u);
}

// float: 1/m and the inverse inertia must be finite. A unit cube's
// 6/m < 3.40282e38 needs m > 1.7632e-38 kg; double runs it, and refuses
// only masses whose 1/m overflows a double.
TEST(SceneLimitsFloat, InverseInertiaAndMass) {
  EXPECT_FALSE(check("float", cube(1.77e-38, 0.5)).refused);
  const Refusal f = check("float", cube(1.76e-38, 0.5));
  ASSERT_TRUE(f.refused);
  EXPECT_EQ(f.field, "bodies[0].mass");
  EXPECT_NE(f.message.find("the float engine's inverse inertia I_x^-1"), std::string::npos) << f.message;
  EXPECT_NE(f.message.find("outside float's range"), std::string::npos) << f.message;
  EXPECT_NE(f.message.find("or run on double"), std::string::npos) << f.message;
  EXPECT_FALSE(check("double", cube(1.76e-38, 0.5)).refused);
  EXPECT_FALSE(check("double", cube(1e-300, 0.5)).refused);
  const Refusal d = check("double", cube(1e-310, 0.5));
  ASSERT_TRUE(d.refused);
  EXPECT_NE(d.message.find("the double engine's inverse mass 1/m"), std::string::npos) << d.message;
  EXPECT_FALSE(check("mp", cube(1e-310, 0.5)).refused);
  EXPECT_EQ(number_type_of_engine("gpu"), "float");
  EXPECT_EQ(number_type_of_engine("gpu-jacobi"), "float");
  EXPECT_EQ(number_type_of_engine("gpu-fixed"), "fixed");  // the GPU engine on Q16.16 (docs/GPU.md "gpu-fixed")
  EXPECT_EQ(number_type_of_engine("fixed"), "fixed");
}

// The check is World<Q16>'s construction: for random bodies over the
// format's whole range (masses and sizes log-uniform, any orientation, static
// or not, positions up to the format's 30000 m), validate_scene_for("fixed")
// refuses exactly the scenes whose World<Q16> stops at frame 0.
RC_GTEST_PROP(SceneLimitsFixed, RefusedExactlyWhenWorldQ16StopsAtFrameZero, ()) {
  auto log_uniform = [](double lo, double hi) {
    const int k = *rc::gen::inRange(0, 1 << 20);
    return lo * std::pow(hi / lo, k / double(1 << 20));
  };
  Scene s = cube(1, 0.5);
  BodyDesc& b = s.bodies[0];
  b.is_static = *rc::gen::inRange(0, 8) == 0;
  b.mass = b.is_static ? 0.0 : log_uniform(1e-6, 1e4);
  b.half_extents = {log_uniform(1.0 / 256, 1024), log_uniform(1.0 / 256, 1024), log_uniform(1.0 / 256, 1024)};
  // Norm in [0.5, 1.33]: any rotation (q and -q are the same one).
  b.orientation = {*rc::gen::inRange(50, 101) / 100.0, *rc::gen::inRange(-50, 51) / 100.0,
                   *rc::gen::inRange(-50, 51) / 100.0, *rc::gen::inRange(-50, 51) / 100.0};
  b.position = {*rc::gen::inRange(-30000, 30001) * 1.0, 2000.0, *rc::gen::inRange(-30000, 30001) * 1.0};
  validate_scene(s);  // the format accepts it
  const Refusal r = check("fixed", s);
  RC_ASSERT(r.refused == !fixed_builds(s));
  RC_ASSERT(!check("double", s).refused);
}

// Every shipped scene runs on every engine: the built-in scenes and the
// example and hard-case scene files.
TEST(SceneLimits, ShippedScenesAreAccepted) {
  std::vector<Scene> scenes;
  for (const std::string& n : builtin_scene_names()) scenes.push_back(*builtin_scene(n));
  for (const char* dir : {"scenes", "hard"})
    for (const auto& e : std::filesystem::directory_iterator(std::string(LOCKSTEP_TEST_DATA_DIR) + "/" + dir))
      if (e.path().extension() == ".json") scenes.push_back(load_scene_file(e.path().string()));
  ASSERT_GT(scenes.size(), 20u);
  for (const Scene& s : scenes)
    for (const char* type : {"fixed", "float", "double"}) {
      const Refusal r = check(type, s);
      EXPECT_FALSE(r.refused) << s.name << " on " << type << ": " << r.message;
    }
}

}  // namespace
}  // namespace lockstep
