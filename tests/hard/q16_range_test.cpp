// Bodies near the edge of the Q16.16 range (|x| < 32768 m; the loader allows
// |p| <= 30000 m): a body that stays in range runs like any other; a body
// whose motion carries it past 32768 m stops the fixed engine with a RunError
// naming the body, the frame and the quantity, in exactly the frame the
// Q16.16 rules of docs/SPEC.md 0.3 and (23)-(24) predict; never a silent wrap.
// The IEEE engines have no such range and run on.
#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <string>

#include "hard_case.hpp"

namespace lockstep::hard {
namespace {

constexpr std::int64_t kDtRaw = 1092;  // eq 91

// floor(a * b / 2^16) in exact integer arithmetic (eq 21 before clamping).
std::int64_t mul_raw(std::int64_t a, std::int64_t b) {
  const std::int64_t p = a * b;
  return p >= 0 ? p / 65536 : -((-p + 65535) / 65536);
}

// Unit roundoff of the engine's number type (mp is read through double).
double roundoff(const std::string& engine) {
  return engine == "float" || engine == "gpu" ? 0x1p-24 : 0x1p-53;
}

// tests/data/hard/q16_overflow.json: x = 30000 m, v = 1000 m/s along +x, no
// gravity, ground or damping. Raw: P0 = 30000 * 2^16, each frame adds
// floor(V * 1092 / 2^16) (eq 24) with V = 1000 * 2^16.
TEST(Q16Range, PastTheEdgeStopsWithRunErrorNamingBodyFrameQuantity) {
  const Scene scene = load_hard_scene("q16_overflow");
  ASSERT_EQ(scene.bodies.size(), 1u);
  const std::int64_t p0 = std::llround(scene.bodies[0].position.x * 65536.0);
  const std::int64_t step = mul_raw(std::llround(scene.bodies[0].velocity.x * 65536.0), kDtRaw);
  int expected_frame = 0;
  for (std::int64_t p = p0; p <= INT32_MAX; p += step) ++expected_frame;  // first frame whose x leaves int32
  ASSERT_EQ(expected_frame, 167);  // 1966080000 + 167 * 1092000 = 2148444000 > 2147483647

  auto run = make_engine("fixed", scene);
  int frame = 0;
  try {
    for (; frame < scene.frames; ++frame) {
      run->step();
      const std::vector<std::int32_t> raw = run->raw_state(0);
      ASSERT_EQ(raw[0], p0 + (frame + 1) * step) << "x at frame " << frame + 1 << " is not the exact eq 24 value";
    }
    FAIL() << "ran " << scene.frames << " frames past x = 32768 m without a RunError; x raw = " << run->raw_state(0)[0];
  } catch (const RunError& e) {
    EXPECT_EQ(e.frame, expected_frame) << e.what();
    EXPECT_EQ(e.body, 0) << e.what();
    EXPECT_EQ(e.quantity, "position/orientation") << e.what();
    const std::string what = e.what();
    EXPECT_NE(what.find("frame " + std::to_string(expected_frame)), std::string::npos) << what;
    EXPECT_NE(what.find("body 0"), std::string::npos) << what;
    EXPECT_NE(what.find("overflow"), std::string::npos) << what;
    EXPECT_EQ(frame + 1, expected_frame);
  }
}

// The same scene on the IEEE engines: no range to leave; x follows
// x0 + n v dt to within the rounding of n additions (2 n u (|x| + |v dt|)).
TEST(Q16Range, IeeeEnginesRunPastTheEdge) {
  const Scene scene = load_hard_scene("q16_overflow");
  const double x0 = scene.bodies[0].position.x, v = scene.bodies[0].velocity.x, dt = scene.constants.dt;
  for (const std::string& engine : engines_for(true)) {
    if (engine == "fixed") continue;
    SCOPED_TRACE(engine);
    MonitoredRun r(scene, engine);
    r.run_to(scene.frames);
    expect_every_case_criteria(r, scene.frames);
    const double n = scene.frames, x = r.monitor->state()[0].p[0], exact = x0 + n * v * dt;
    EXPECT_NEAR(x, exact, 2.0 * n * roundoff(engine) * (std::fabs(exact) + std::fabs(v * dt))) << r.summary();
    EXPECT_GT(x, 32768.0) << r.summary();
  }
}

// Falling from y = 0 under g = -1000 m/s^2 (the loader's largest), nothing
// else: V(n) = n A, A = floor(G * 1092 / 2^16) (eq 23), P(n) = P(n-1) +
// floor(V(n) * 1092 / 2^16) (eq 24); the fixed run stops in the first frame
// whose P leaves int32, naming body 0 and its position.
TEST(Q16Range, FallingPastTheEdgeStopsInThePredictedFrame) {
  Scene scene;
  scene.name = "q16_fall";
  scene.frames = 2000;
  scene.effects = {.gravity = true, .damping = false, .ground = false, .contacts = false, .friction = false,
                   .restitution = false, .settling = false, .sleep = false, .sdf = false};
  scene.ground.present = false;
  scene.constants.gravity = {0.0, -1000.0, 0.0};
  scene.bodies.push_back(BodyDesc{});
  scene.bodies[0].position = {0.0, 0.0, 0.0};
  validate_scene(scene);
  const std::int64_t a = mul_raw(-1000 * 65536, kDtRaw);
  std::int64_t vel = 0, pos = 0;
  int expected_frame = 0;
  while (pos >= INT32_MIN) {
    ++expected_frame;
    vel += a;
    pos += mul_raw(vel, kDtRaw);
  }
  auto run = make_engine("fixed", scene);
  try {
    for (int f = 0; f < scene.frames; ++f) run->step();
    FAIL() << "fell " << scene.frames << " frames without a RunError";
  } catch (const RunError& e) {
    EXPECT_EQ(e.frame, expected_frame) << e.what();
    EXPECT_EQ(e.body, 0) << e.what();
    EXPECT_EQ(e.quantity, "position/orientation") << e.what();
  }
}

// A body placed at the loader's limit (|x| = |z| = 29999.5 m) that stays in
// range: it lands, settles and sleeps on every engine, exactly as at the
// origin (the catalogue's q16_edge adds a body-body contact there).
TEST(Q16Range, BodyAtTheEdgeRunsAndRests) {
  Scene scene;
  scene.name = "q16_edge_single";
  scene.frames = 240;
  scene.effects.sdf = false;
  scene.bodies.push_back(BodyDesc{});
  scene.bodies[0].position = {29999.5, 0.6, -29999.5};
  validate_scene(scene);
  for (const std::string& engine : engines_for(true)) {
    SCOPED_TRACE(engine);
    MonitoredRun r(scene, engine);
    r.run_to(scene.frames);
    expect_every_case_criteria(r, scene.frames);
    expect_all_asleep(r);
    expect_rests_at(r, 0, 29999.5, 0.5, -29999.5, 0.01, resting_depth_bound(scene, 0));
  }
}

}  // namespace
}  // namespace lockstep::hard
