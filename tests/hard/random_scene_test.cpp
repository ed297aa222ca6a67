// RapidCheck: random valid scenes (within the loader's documented ranges,
// docs/SCENES.md) and the invariants of docs/HARD_CASES.md "Random scenes":
//  - the scene is valid (validate_scene) and survives the JSON round trip;
//  - on every engine: no run error, no NaN or infinity, no asleep body moves,
//    no resting body below the ground by more than its bound, energy within
//    its allowance;
//  - the fixed engine is deterministic (two runs, and a copy of the world,
//    give the same state hash every frame);
//  - a sleeping body touched by a falling one wakes in the frame of contact
//    and moves; a sleeping body given a velocity through the API wakes and moves.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "hard_case.hpp"
#include "lockstep/fixed/q16_num.hpp"

namespace lockstep::hard {
namespace {

constexpr int kFrames = 180;

// A decimal k / scale, k uniform in [lo, hi].
double decimal(int lo, int hi, int scale) { return *rc::gen::inRange(lo, hi + 1) / static_cast<double>(scale); }

// A quaternion with components in [-1, 1] and norm in [0.5, 2] (the loader's rule).
Quatd random_orientation() {
  for (;;) {
    const Quatd q{decimal(-100, 100, 100), decimal(-100, 100, 100), decimal(-100, 100, 100), decimal(-100, 100, 100)};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (n >= 0.5 && n <= 2.0) return q;
  }
}

Material random_material() { return {decimal(0, 100, 100), decimal(0, 400, 100)}; }

// A body anywhere in a 12 m x 9 m x 12 m box around the origin (possibly
// overlapping others or the ground), any orientation, up to 10 m/s and
// 10 rad/s; 1 in 8 static, 1 in 8 of the rest starting asleep (at rest).
BodyDesc random_body() {
  BodyDesc b;
  b.half_extents = {decimal(10, 150, 100), decimal(10, 150, 100), decimal(10, 150, 100)};
  b.is_static = *rc::gen::inRange(0, 8) == 0;
  b.mass = b.is_static ? 0.0 : decimal(1, 1000, 10);
  b.position = {decimal(-600, 600, 100), decimal(-50, 800, 100), decimal(-600, 600, 100)};
  b.orientation = random_orientation();
  b.asleep = !b.is_static && *rc::gen::inRange(0, 8) == 0;
  if (!b.asleep) {
    b.velocity = {decimal(-1000, 1000, 100), decimal(-1000, 1000, 100), decimal(-1000, 1000, 100)};
    b.angular_velocity = {decimal(-1000, 1000, 100), decimal(-1000, 1000, 100), decimal(-1000, 1000, 100)};
  }
  b.material = random_material();
  return b;
}

Scene random_scene() {
  Scene s;
  s.name = "random";
  s.frames = kFrames;
  s.effects.gravity = *rc::gen::inRange(0, 8) != 0;
  s.effects.damping = *rc::gen::arbitrary<bool>();
  s.effects.ground = *rc::gen::inRange(0, 8) != 0;
  s.effects.contacts = *rc::gen::inRange(0, 8) != 0;
  s.effects.friction = *rc::gen::arbitrary<bool>();
  s.effects.restitution = *rc::gen::arbitrary<bool>();
  s.effects.settling = *rc::gen::arbitrary<bool>();
  s.effects.sleep = *rc::gen::arbitrary<bool>();
  s.effects.sdf = false;
  s.constants.solver_iterations = *rc::gen::inRange(1, 9);
  s.ground.present = *rc::gen::inRange(0, 8) != 0;
  s.ground.height = decimal(-100, 100, 100);
  s.ground.material = random_material();
  const int n = *rc::gen::inRange(1, 11);
  for (int i = 0; i < n; ++i) s.bodies.push_back(random_body());
  return s;
}

// Validates the scene, checks the JSON round trip, and logs the scene (a
// failing case prints it: save it to a file and `lockstep run` it).
void assert_valid(const Scene& s) {
  RC_LOG() << scene_to_json(s) << "\n";
  try {
    validate_scene(s);
  } catch (const SceneError& e) {
    RC_FAIL(std::string("generator produced an invalid scene: ") + e.what());
  }
  const Scene again = parse_scene(scene_to_json(s), "<random>");
  RC_ASSERT(scene_difference(s, again) == "");
}

// fixed, float, double and, where it runs the scene's pair model
// (engine_limitation: the GPU engine runs the source's AABB model only), gpu.
// An engine is not given another model than the scene's: the AABB model lets
// a box turning over an edge gain energy on every engine (docs/HARD_CASES.md),
// so its energy would judge the model, not the engine; the GPU engine's AABB
// path is judged against double and float in compare_validation_test
// (ValidationAabbTest) and on the hard catalogue.
std::vector<std::string> engines_running(const Scene& scene) {
  std::vector<std::string> out;
  for (const std::string& e : engines_for(false))
    if (engine_limitation(e, scene).empty()) out.push_back(e);
  return out;
}

void assert_invariants(const MonitoredRun& r) {
  const MonitorStats& s = r.stats();
  RC_LOG() << r.summary() << "\n";
  RC_ASSERT(r.error == "");
  RC_ASSERT(s.nonfinite_frame == -1);
  RC_ASSERT(s.asleep_moved == 0);
  RC_ASSERT(s.resting_excess <= 0.0);
  RC_ASSERT(s.worst_excess <= 0.0);
}

RC_GTEST_PROP(RandomScenes, ValidAndStableOnEveryEngine, ()) {
  const Scene scene = random_scene();
  assert_valid(scene);
  for (const std::string& engine : engines_running(scene)) {
    RC_LOG() << "engine " << engine << "\n";
    MonitoredRun r(scene, engine);
    r.run_to(scene.frames);
    assert_invariants(r);
  }
}

RC_GTEST_PROP(RandomScenes, FixedEngineIsDeterministic, ()) {
  const Scene scene = random_scene();
  World<Q16> a(scene), b(scene);
  auto run = make_engine("fixed", scene);
  const int split = *rc::gen::inRange(1, kFrames);
  std::vector<std::uint64_t> hashes;
  for (int f = 0; f < split; ++f) {
    a.step();
    b.step();
    run->step();
    RC_ASSERT(a.state_hash() == b.state_hash());
    RC_ASSERT(a.state_hash() == run->state_hash());
  }
  World<Q16> copy(a);  // a saved state continues exactly like the original
  for (int f = split; f < kFrames; ++f) {
    a.step();
    copy.step();
    RC_ASSERT(a.state_hash() == copy.state_hash());
  }
}

// A box asleep flat on the ground (any size, mass, yaw) and a box falling on
// it from 5 cm to 2 m above, landing within half the sleeper's smaller
// half extent of its centre.
Scene sleeper_and_dropper() {
  Scene s;
  s.name = "wake";
  s.frames = 240;
  s.effects.sdf = false;
  s.ground.height = decimal(-100, 100, 100);
  BodyDesc sleeper;
  sleeper.half_extents = {decimal(25, 150, 100), decimal(25, 150, 100), decimal(25, 150, 100)};
  sleeper.mass = decimal(1, 1000, 10);
  sleeper.orientation = {1.0, 0.0, decimal(-100, 100, 100), 0.0};  // a turn about y: still flat
  sleeper.position = {decimal(-300, 300, 100), s.ground.height + sleeper.half_extents.y, decimal(-300, 300, 100)};
  sleeper.asleep = true;
  BodyDesc dropper;
  dropper.half_extents = {decimal(10, 100, 100), decimal(10, 100, 100), decimal(10, 100, 100)};
  dropper.mass = decimal(1, 1000, 10);
  const double reach = 0.5 * std::min(sleeper.half_extents.x, sleeper.half_extents.z);
  dropper.position = {sleeper.position.x + reach * decimal(-100, 100, 100),
                      sleeper.position.y + sleeper.half_extents.y + dropper.half_extents.y + decimal(5, 200, 100),
                      sleeper.position.z + reach * decimal(-100, 100, 100)};
  dropper.velocity = {0.0, -decimal(0, 500, 100), 0.0};
  s.bodies = {sleeper, dropper};
  return s;
}

// How far bodies 0 and 1 are from being a contact in the monitor's state:
// the smallest per-axis overlap of their world AABBs (eqs 38-39) plus
// contact_tolerance (the boxes grown by half of it each, eq 97) plus `reach`.
// > 0 with reach = 0: their AABBs overlap. <= 0 with reach = the dropper's
// largest speculative reach (eq 107): the next frame cannot make them a
// (speculative) contact, since the broadphase and the early-out grow the
// boxes by no more.
double contact_margin(const Monitor& m, double tol, double reach) {
  const auto& s = m.state();
  const auto& g = m.geometry();
  double margin = 1e300;
  for (int k = 0; k < 3; ++k)
    margin = std::min(margin, g[0].aabb_half[k] + g[1].aabb_half[k] - std::fabs(s[0].p[k] - s[1].p[k]) + tol + reach);
  return margin;
}

// Eq 107's reach of the dropper (body 1) in the next frame, from above: its
// speed after the frame's gravity at most |v|inf + |g| dt.
double reach_bound(const Monitor& m, const Scene& scene) {
  const auto& b = m.state()[1];
  const Vec3d& h = scene.bodies[1].half_extents;
  const double dt = scene.constants.dt, g = std::fabs(scene.constants.gravity.y);
  double v = 0, w = 0;
  for (int k = 0; k < 3; ++k) {
    v = std::max(v, std::fabs(b.v[k]));
    w = std::max(w, std::fabs(b.w[k]));
  }
  const double hmax = std::max(h.x, std::max(h.y, h.z));
  return (std::min(v + g * dt, 64.0) + std::min(3 * w * hmax, 64.0)) * dt;
}

// eq 81 with eqs 97 and 107: the falling box approaches at over 0.99 m/s
// (> wake_speed) when it reaches the sleeper, so the sleeper wakes in the
// frame whose narrow phase first sees their pair as a (speculative) contact:
// it is asleep after every frame that starts with the boxes clearly out of
// reach (margin with the dropper's reach < -0.1 mm; the band of +-0.1 mm
// covers the engines' rounding of the margin), and awake after the first
// frame that starts with their AABBs clearly overlapping (margin > 0.1 mm).
// In that frame it moves: its position or velocity changes.
RC_GTEST_PROP(RandomScenes, TouchedSleeperWakesAndMoves, ()) {
  const Scene scene = sleeper_and_dropper();
  assert_valid(scene);
  const double tol = scene.constants.contact_tolerance, band = 1e-4;
  for (const std::string& engine : engines_running(scene)) {
    RC_LOG() << "engine " << engine << "\n";
    MonitoredRun r(scene, engine);
    while (r.stats().frames < scene.frames && contact_margin(*r.monitor, tol, 0.0) <= band && r.error.empty()) {
      const bool out_of_reach = contact_margin(*r.monitor, tol, reach_bound(*r.monitor, scene)) < -band;
      r.run_to(r.stats().frames + 1);
      if (out_of_reach) RC_ASSERT(r.monitor->state()[0].asleep);  // nothing wakes it before the contact
      if (!r.monitor->state()[0].asleep) break;                     // woken by a speculative contact
    }
    RC_ASSERT(r.error == "");
    if (r.monitor->state()[0].asleep) {
      RC_ASSERT(contact_margin(*r.monitor, tol, 0.0) > band);  // the dropper reached the sleeper
      const BodySnapshot before = r.monitor->state()[0];
      r.run_to(r.stats().frames + 1);
      RC_ASSERT(r.error == "");
      const BodySnapshot& after = r.monitor->state()[0];
      RC_LOG() << "woke at frame " << r.stats().frames << "\n";
      RC_ASSERT(!after.asleep);
      RC_ASSERT(std::memcmp(before.p, after.p, sizeof after.p) != 0 || std::memcmp(before.v, after.v, sizeof after.v) != 0);
    }
    r.run_to(scene.frames);
    assert_invariants(r);
  }
}

// A box resting flat on the ground falls asleep; set_velocity (the API's
// touch, 5.1) wakes it and it moves in the next frame.
template <class T>
void api_wake(const Scene& scene, const Vec3d& v, const Vec3d& w) {
  World<T> world(scene);
  int frame = 0;
  while (frame < scene.frames && !world.body(0).asleep) {
    world.step();
    ++frame;
  }
  RC_LOG() << Num<T>::kName << ": asleep at frame " << frame << "\n";
  RC_ASSERT(world.body(0).asleep);
  const Vec3<T> p = world.body(0).p;
  auto n = [](double x) { return Num<T>::from_double(x); };
  world.set_velocity(0, Vec3<T>{n(v.x), n(v.y), n(v.z)}, Vec3<T>{n(w.x), n(w.y), n(w.z)});
  RC_ASSERT(!world.body(0).asleep);
  world.step();
  RC_ASSERT(!world.body(0).asleep);
  RC_ASSERT(!(world.body(0).p == p));
}

RC_GTEST_PROP(RandomScenes, ApiTouchWakesAndMoves, ()) {
  Scene scene;
  scene.name = "api_wake";
  scene.frames = 300;
  scene.effects.sdf = false;
  BodyDesc b;
  b.half_extents = {decimal(25, 150, 100), decimal(25, 150, 100), decimal(25, 150, 100)};
  b.mass = decimal(1, 1000, 10);
  b.orientation = {1.0, 0.0, decimal(-100, 100, 100), 0.0};
  b.position = {decimal(-300, 300, 100), b.half_extents.y, decimal(-300, 300, 100)};
  scene.bodies.push_back(b);
  assert_valid(scene);
  // Horizontal speed of at least 0.5 m/s, so the body moves by at least
  // 0.5 dt = 8 mm in the frame (well above any rounding).
  const double speed = decimal(50, 500, 100), angle = decimal(0, 628, 100);
  const Vec3d v{speed * std::cos(angle), decimal(0, 200, 100), speed * std::sin(angle)};
  const Vec3d w{decimal(-200, 200, 100), decimal(-200, 200, 100), decimal(-200, 200, 100)};
  api_wake<Q16>(scene, v, w);
  api_wake<float>(scene, v, w);
  api_wake<double>(scene, v, w);
}

}  // namespace
}  // namespace lockstep::hard
