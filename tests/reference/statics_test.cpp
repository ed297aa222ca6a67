// Statics and Newton's second law decide where a body may rest
// (docs/SPEC.md Part 4, eqs 116, 117 and 124), on every engine: fixed,
// float, double, mp and the GPU engine's host build (the CUDA kernels'
// pipeline).
// - Ramps (eq 116): a cube on a static slab tilted 10, 20 or 30 degrees with
//   friction below tan(a) slides with acceleration g (sin a - mu cos a),
//   within 2 % over two seconds; pushed down a ramp whose friction exceeds
//   tan(a) it stops where friction stops it, v^2 / (2 g (mu cos a - sin a)),
//   and sleeps. Before eq 116, eq 77 acted as a viscous drag: 0.226 m/s
//   terminal on 20 degrees with mu 0.2, where Newton says 3.0 m/s after 2 s.
// - A sleeper under a load (eq 124): a cube asleep on a ledge's edge wakes
//   and tips when a load set down on its overhanging end puts the centre of
//   both beyond the edge, and sleeps on under a load over its support.
// - Overhangs (eq 117): towers of 3-8 cubes (0.5-1 m, 0.5-2 kg) stacked
//   face on face, each shifted against the one below, so that the centre of
//   mass of some upper part lies 3-12 cm beyond the edge of the cube under
//   it: statics says they fall (some cube ends half its size or more below
//   where it started). Before eq 117 the upper cubes settled and slept
//   leaning: 8 of 10 stood (now none of 10,000 in the long run). Towers
//   whose every upper part's centre lies 3-12 cm inside the edge stand
//   (99.4 % of 10,000 in fixed; at most 1 % wrong allowed, the issue's 99 %).
//   At every frame no cube sleeps with the load it carries beyond its
//   support by more than 1 cm (docs/STATICS.md). kTowerCases per engine in
//   CI (drawn from a fixed seed: the same towers every run),
//   LOCKSTEP_TOWER_CASES (10,000) under the label long (fresh ones).
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <sstream>
#include <vector>

#include "../fixed/prop.hpp"
#include "engine_types.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "lockstep/scene_json.hpp"

#ifndef LOCKSTEP_TOWER_CASES
#define LOCKSTEP_TOWER_CASES 0
#endif

namespace lockstep::test {
namespace {

inline constexpr int kTowerCases = LOCKSTEP_TOWER_CASES > 0 ? LOCKSTEP_TOWER_CASES : 200;
constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

struct Snap {
  double p[3], v[3];
  bool asleep;
  double qw;  // |w| of its orientation: 1 as built (each cube starts unrotated)
};
template <class T>
Snap snap(const World<T>& w, int i) {
  const Body<T>& b = w.body(i);
  return {{d(b.p.x), d(b.p.y), d(b.p.z)}, {d(b.v.x), d(b.v.y), d(b.v.z)}, b.asleep, std::fabs(d(b.q.w))};
}
Snap snap(const gpu::GpuWorld& w, int i) {
  const BodySnapshot b = w.body(i);
  return {{b.p[0], b.p[1], b.p[2]}, {b.v[0], b.v[1], b.v[2]}, b.asleep, std::fabs(b.q[0])};
}

// One engine of each kind behind one interface: build, step, look.
template <class T>
struct Engine {
  World<T> w;
  explicit Engine(const Scene& s) : w(s) {}
  void step() { w.step(); }
  void wake(int i) { w.wake(i); }
  Snap body(int i) const { return snap(w, i); }
  int count() const { return static_cast<int>(w.bodies().size()); }
  static const char* name() { return Num<T>::kName; }
};
struct GpuEngine {
  gpu::GpuWorld w;
  static gpu::GpuOptions host() {
    gpu::GpuOptions o;
    o.backend = gpu::Backend::kHost;
    return o;
  }
  explicit GpuEngine(const Scene& s) : w(s, host()) {}
  void step() { w.step(); }
  Snap body(int i) const { return snap(w, i); }
  int count() const { return w.body_count(); }
  static const char* name() { return "gpu"; }
};

template <class E>
class StaticsTest : public ::testing::Test {};
using StaticsEngines = ::testing::Types<Engine<Q16>, Engine<float>, Engine<double>, Engine<Mp>, GpuEngine>;
TYPED_TEST_SUITE(StaticsTest, StaticsEngines);

// A static slab (20 x 1 x 4 m) turned by `deg` about z, so that its top face
// falls towards +x with normal n = (sin a, cos a, 0), and a unit cube (1 kg)
// resting on that face 3 m up the slope, turned with it, moving down the
// slope at v0 (m/s). Friction mu on both (eq 58: mu), no bounce. Returns the
// unit vector down the slope through `down`.
Scene ramp(double deg, double mu, double v0, double down[3]) {
  const double a = deg * kPi / 180.0;
  Scene s;
  s.name = "ramp";
  s.frames = 120;
  s.ground.present = false;
  const double n[3] = {std::sin(a), std::cos(a), 0.0};
  down[0] = std::cos(a);
  down[1] = -std::sin(a);
  down[2] = 0.0;
  BodyDesc slab;
  slab.half_extents = {10.0, 0.5, 2.0};
  slab.is_static = true;
  slab.position = {0.0, 5.0, 0.0};
  slab.orientation = {std::cos(a / 2), 0.0, 0.0, -std::sin(a / 2)};
  slab.material = {0.0, mu};
  BodyDesc cube;
  cube.position = {n[0] - 3 * down[0], 5.0 + n[1] - 3 * down[1], 0.0};
  cube.orientation = slab.orientation;
  cube.velocity = {v0 * down[0], v0 * down[1], 0.0};
  cube.material = {0.0, mu};
  s.bodies = {slab, cube};
  return s;
}

double along(const Snap& b, const double dir[3], bool velocity) {
  const double* x = velocity ? b.v : b.p;
  return x[0] * dir[0] + x[1] * dir[1] + x[2] * dir[2];
}

// Eq 116: friction below tan(a): the cube slides at g (sin a - mu cos a).
TYPED_TEST(StaticsTest, RampSlidesAtNewtonsAcceleration) {
  using E = TypeParam;
  for (const double deg : {10.0, 20.0, 30.0}) {
    const double a = deg * kPi / 180.0;
    for (const double share : {0.0, 0.5, 0.8}) {  // mu as a share of tan(a)
      const double mu = share * std::tan(a);
      double down[3];
      E e(ramp(deg, mu, 0.0, down));
      for (int f = 0; f < 120; ++f) e.step();  // 2 s
      const double want = kG * (std::sin(a) - mu * std::cos(a)) * 2.0;
      const Snap c = e.body(1);
      EXPECT_NEAR(along(c, down, true), want, 0.02 * want) << E::name() << ": " << deg << " degrees, mu " << mu;
      EXPECT_FALSE(c.asleep) << E::name() << ": " << deg << " degrees, mu " << mu;
    }
  }
}

// Eq 116: friction above tan(a): a cube pushed down the ramp at 1 m/s stops
// after v^2 / (2 g (mu cos a - sin a)) (as the integrator sums it) and
// sleeps; one released at rest holds.
// Eq 77 damps it only below what friction could stop in a frame (eq 116's
// spare): damped below 0.3 m/s, it stopped 4-8 % short.
TYPED_TEST(StaticsTest, RampHoldsAndStopsWhereFrictionStopsIt) {
  using E = TypeParam;
  for (const double deg : {10.0, 20.0, 30.0}) {
    const double a = deg * kPi / 180.0;
    const double mu = 1.5 * std::tan(a) + 0.05;
    for (const double v0 : {0.0, 1.0}) {
      double down[3];
      const Scene s = ramp(deg, mu, v0, down);
      E e(s);
      const double start = along(e.body(1), down, false);
      bool slept = false;
      for (int f = 0; f < 240 && !slept; ++f) {
        e.step();
        slept = e.body(1).asleep;
      }
      // v^2 / (2 a) as symplectic Euler integrates it (velocity first, then
      // position): dt * sum of v0 - n a dt over the frames it still moves,
      // v0 dt / 2 (8 mm at 1 m/s) below the continuous distance.
      const double decel = kG * (mu * std::cos(a) - std::sin(a)), dt = 1.0 / 60.0;
      double want = 0;
      for (int n = 1; v0 - n * decel * dt > 0; ++n) want += (v0 - n * decel * dt) * dt;
      const double got = along(e.body(1), down, false) - start;
      EXPECT_NEAR(got, want, std::max(0.02 * want, 0.002)) << E::name() << ": " << deg << " degrees, v0 " << v0;
      EXPECT_TRUE(slept) << E::name() << ": " << deg << " degrees, v0 " << v0 << " not asleep by frame 240";
    }
  }
}

// Eq 124: a cube S (1 kg, 1 m) on the edge of a static ledge, its centre
// 0.1 m inside the edge, falls asleep; a cube L (2 kg, 0.5 m) held asleep
// 1 mm above S's top, its centre 0.3 m beyond the ledge's edge (over S), is
// woken at frame 60 and settles onto S at 0.06 m/s, too slowly for eq 81.
// Together their centre lies (2 x 0.3 - 0.1) / 3 = 0.167 m beyond the edge:
// statics says S tips off the ledge with L. Without eq 124 S slept on under
// L, which rested on it (the sleeper was never asked about its load).
Scene ledge_with_late_load() {
  Scene s;
  s.name = "ledge";
  s.frames = 240;
  BodyDesc ledge;
  ledge.is_static = true;
  ledge.half_extents = {1.0, 0.5, 1.0};
  ledge.position = {-1.0, 0.5, 0.0};
  BodyDesc cube;
  cube.position = {-0.1, 1.5, 0.0};
  BodyDesc load;
  load.half_extents = {0.25, 0.25, 0.25};
  load.mass = 2.0;
  load.position = {0.3, 2.251, 0.0};
  load.asleep = true;
  s.bodies = {ledge, cube, load};
  return s;
}

template <class E>
class SleeperLoadTest : public ::testing::Test {};
using WorldEngines = ::testing::Types<Engine<Q16>, Engine<float>, Engine<double>, Engine<Mp>>;
TYPED_TEST_SUITE(SleeperLoadTest, WorldEngines);

TYPED_TEST(SleeperLoadTest, SleeperTipsWhenItsLoadLeavesItsSupport) {
  using E = TypeParam;
  E e(ledge_with_late_load());
  for (int f = 0; f < 59; ++f) e.step();
  ASSERT_TRUE(e.body(1).asleep) << E::name() << ": the cube on the ledge should be asleep by frame 59";
  e.wake(2);
  bool woke = false;
  for (int f = 59; f < 240; ++f) {
    e.step();
    woke = woke || !e.body(1).asleep;
  }
  EXPECT_TRUE(woke) << E::name() << ": the sleeper under the load never woke";
  EXPECT_LT(e.body(1).p[1], 1.0) << E::name() << ": the cube should have tipped off the ledge with its load";
}

// The same ledge with the load's centre 0.2 m inside the ledge's edge:
// together (2 x -0.2 - 0.1) / 3 = -0.167 m, inside. S sleeps on, L settles
// on it and sleeps, nothing moves.
TYPED_TEST(SleeperLoadTest, SleeperUnderALoadOverItsSupportSleepsOn) {
  using E = TypeParam;
  Scene s = ledge_with_late_load();
  s.bodies[2].position.x = -0.2;
  E e(s);
  for (int f = 0; f < 59; ++f) e.step();
  ASSERT_TRUE(e.body(1).asleep) << E::name();
  e.wake(2);
  bool woke = false;
  for (int f = 59; f < 240; ++f) {
    e.step();
    woke = woke || !e.body(1).asleep;
  }
  EXPECT_FALSE(woke) << E::name() << ": a load over the support woke the sleeper";
  EXPECT_TRUE(e.body(2).asleep) << E::name() << ": the load should rest asleep";
  EXPECT_NEAR(e.body(1).p[1], 1.5, 0.01) << E::name();
}

// A tower of the statics probe's kind (../shared/tools/statics_probe.py):
// n cubes of one size, the first on the ground, each shifted horizontally
// against the one below by up to 0.45 size in one of 6 directions; `margin`
// (m) is its worst upper part's centre of mass against the edge of the cube
// under it (negative: beyond the edge).
struct Tower {
  double size = 1.0, margin = 0.0;
  Scene scene;
};

double worst_margin(const std::vector<double>& xs, const std::vector<double>& zs, double size) {
  const std::size_t n = xs.size();
  double worst = 1e9;
  for (std::size_t k = 1; k < n; ++k) {
    double cx = 0, cz = 0;
    for (std::size_t j = k; j < n; ++j) cx += xs[j], cz += zs[j];
    cx /= static_cast<double>(n - k);
    cz /= static_cast<double>(n - k);
    worst = std::min(worst, size / 2 - std::max(std::fabs(cx - xs[k - 1]), std::fabs(cz - zs[k - 1])));
  }
  return worst;
}

// Towers whose worst margin lies in [-0.12, -0.03] m (must fall), or in
// [0.03, 0.12] m (must stand). Sized at rapidcheck's nominal 100: every draw
// spans its whole range from the first case (at size 0 inRange gives its
// minimum, which no tower of the window is made of).
rc::Gen<Tower> tower_gen(bool falls) {
  return rc::gen::resize(100, rc::gen::exec([falls] {
    auto unit = [] { return *rc::gen::inRange(0, 1000001) / 1e6; };
    const int dirs[6] = {0, 90, 180, 270, 45, 135};
    for (;;) {
      Tower t;
      t.size = 0.5 + 0.5 * unit();
      const int n = *rc::gen::inRange(3, 9);
      std::vector<double> xs{0.0}, zs{0.0};
      for (int k = 1; k < n; ++k) {
        const double r = 0.45 * t.size * unit();
        const double ang = dirs[*rc::gen::inRange(0, 6)] * kPi / 180.0;
        xs.push_back(xs.back() + r * std::cos(ang));
        zs.push_back(zs.back() + r * std::sin(ang));
      }
      t.margin = worst_margin(xs, zs, t.size);
      if (falls ? !(t.margin >= -0.12 && t.margin <= -0.03) : !(t.margin >= 0.03 && t.margin <= 0.12)) continue;
      const double mass = 0.5 + 1.5 * unit();
      for (int k = 0; k < n; ++k) {
        BodyDesc b;
        b.half_extents = {t.size / 2, t.size / 2, t.size / 2};
        b.mass = mass;
        b.position = {xs[static_cast<std::size_t>(k)], t.size / 2 + k * t.size, zs[static_cast<std::size_t>(k)]};
        b.material = {0.1, 0.5};
        t.scene.bodies.push_back(b);
      }
      t.scene.name = "overhang";
      t.scene.ground.material = {0.1, 0.5};
      return t;
    }
  }));
}

// Every frame, statics' oracle on the part of the tower still stacked as
// built: cube j rests face on face on cube j - 1 while both are turned by
// less than 6 degrees from how they were built (each cube starts unrotated;
// a column may lean a few degrees as a whole), j's centre is one size above
// j - 1's (within 6 % of the size: a 6 degree tilt on an edge lifts it by
// 5 %) and their faces overlap. A sleeping cube k resting so carries the cubes stacked on it
// above; the centre of mass of that load (equal masses) must lie over the
// overlap of its face and the face of cube k - 1 (an axis-aligned
// rectangle), or beyond it by at most 1 cm. (Cubes that have fallen rest on
// whatever they hit, which this oracle does not model. Until 2026-11-28 a
// cube counted only while within 2 cm of where it started, so a cube still
// resting on the one below, dragged 2 cm by the cubes toppling off it,
// dropped out of its supporter's load: the long run's falling tower 1,421.)
// Returns "" or what is wrong.
template <class E>
std::string sleeping_load_beyond_support(const E& e, double size) {
  const int n = e.count();
  const double level = std::cos(3.0 * kPi / 180.0);  // |q.w| of a 6 degree turn
  auto stacked = [&](int lo, int hi) {
    const Snap a = e.body(lo), b = e.body(hi);
    return a.qw > level && b.qw > level && std::fabs(b.p[1] - a.p[1] - size) < 0.06 * size &&
           std::fabs(b.p[0] - a.p[0]) < size && std::fabs(b.p[2] - a.p[2]) < size;
  };
  for (int k = 1; k < n; ++k) {
    const Snap body = e.body(k);
    if (!body.asleep || !stacked(k - 1, k)) continue;
    double cx = 0, cz = 0;
    int m = 0;
    for (int j = k; j < n && (j == k || stacked(j - 1, j)); ++j, ++m) cx += e.body(j).p[0], cz += e.body(j).p[2];
    cx /= m;
    cz /= m;
    const Snap below = e.body(k - 1);
    const double lox = std::max(body.p[0], below.p[0]) - size / 2, hix = std::min(body.p[0], below.p[0]) + size / 2;
    const double loz = std::max(body.p[2], below.p[2]) - size / 2, hiz = std::min(body.p[2], below.p[2]) + size / 2;
    const double beyond = std::max({lox - cx, cx - hix, loz - cz, cz - hiz});
    if (beyond > 0.01) {
      std::ostringstream ss;
      ss << "cube " << k << " sleeps with the load of " << m << " cubes " << beyond * 100
         << " cm beyond its support";
      return ss.str();
    }
  }
  return "";
}

// A failing tower's scene, for `lockstep run`: under the build tree
// (LOCKSTEP_TEST_OUTPUT_DIR, wherever the test is run from), overwritten by
// the next failure.
void write_failing_tower(const Scene& scene) {
  std::ofstream(std::string(LOCKSTEP_TEST_OUTPUT_DIR) + "/statics_failing_tower.json") << scene_to_json(scene);
}

template <class E>
void check_falls(const Tower& t) {
  E e(t.scene);
  std::vector<Snap> start;
  for (int i = 0; i < e.count(); ++i) start.push_back(e.body(i));
  double drop = 0;
  for (int f = 0; f < 600; ++f) {
    e.step();
    for (int i = 0; i < e.count(); ++i) drop = std::max(drop, start[static_cast<std::size_t>(i)].p[1] - e.body(i).p[1]);
    const std::string wrong = sleeping_load_beyond_support(e, t.size);
    if (!wrong.empty()) {
      write_failing_tower(t.scene);
      RC_FAIL(std::string(E::name()) + ", frame " + std::to_string(f + 1) + ": " + wrong);
    }
  }
  if (!(drop >= t.size / 2))
    RC_FAIL(std::string(E::name()) + ": a tower of " + std::to_string(e.count()) +
                                       " cubes of " + std::to_string(t.size) + " m, margin " +
                                       std::to_string(t.margin * 100) + " cm, stood: largest drop " +
                                       std::to_string(drop) + " m");
}

// Steps a scene 600 frames; "" when statics' oracle holds at every frame (no
// cube sleeps with its load beyond its support, sleeping_load_beyond_support)
// and body `falls` (-1: any body) ends at least size / 2 below where it
// started; else what is wrong.
template <class E>
std::string falls_as_statics_says(const Scene& s, double size, int falls) {
  E e(s);
  std::vector<Snap> start;
  for (int i = 0; i < e.count(); ++i) start.push_back(e.body(i));
  double drop = 0;
  for (int f = 0; f < 600; ++f) {
    e.step();
    for (int i = 0; i < e.count(); ++i)
      if (falls < 0 || i == falls) drop = std::max(drop, start[static_cast<std::size_t>(i)].p[1] - e.body(i).p[1]);
    const std::string wrong = sleeping_load_beyond_support(e, size);
    if (!wrong.empty()) return std::string(E::name()) + ", frame " + std::to_string(f + 1) + ": " + wrong;
  }
  if (drop >= size / 2) return "";
  return std::string(E::name()) + ": it stood, largest drop " + std::to_string(drop) + " m";
}

template <class E>
class HeldAcrossTest : public ::testing::Test {};
using HeldAcrossEngines = ::testing::Types<Engine<Q16>, Engine<float>, Engine<double>, GpuEngine>;
TYPED_TEST_SUITE(HeldAcrossTest, HeldAcrossEngines);

// Eq 117, the direction of a hold (2026-11-28): a column of three unit cubes
// (1 kg), cube 1 at z = -0.45 on cube 0, cube 2 at z = -0.61 on cube 1: the
// load of cubes 1 and 2 has its centre at z = -0.53, 3 cm beyond the edge of
// cube 0 (z = -0.5), while cube 1's own centre is 5 cm inside it. A static
// wall touches cube 1's +x face (shifted 0.2 m in x, so that only cube 1
// touches it), along the edge the load tips over: it cannot hold the load
// (its normal is square to the turn), and statics says cubes 1 and 2 fall.
// Before, the wall counted as holding cube 1 (holds_off_support): eq 117
// left its load alone and settling (eqs 72-74) damped the tip, and the
// column slept leaning 1 degree with the load 5.7 cm beyond the edge on
// every engine.
TYPED_TEST(HeldAcrossTest, WallAlongTheEdgeDoesNotHoldTheLoad) {
  using E = TypeParam;
  Scene s;
  s.name = "held_across";
  for (const auto& [x, y, z] : {std::array<double, 3>{0.0, 0.5, 0.0}, {0.2, 1.5, -0.45}, {0.1, 2.5, -0.61}}) {
    BodyDesc b;
    b.position = {x, y, z};
    b.material = {0.1, 0.5};
    s.bodies.push_back(b);
  }
  BodyDesc wall;
  wall.is_static = true;
  wall.half_extents = {0.5, 2.0, 2.0};
  wall.position = {1.2, 2.0, 0.0};
  wall.material = {0.1, 0.5};
  s.bodies.push_back(wall);
  s.ground.material = {0.1, 0.5};
  EXPECT_EQ(falls_as_statics_says<E>(s, 1.0, 2), "");
}

// The long run's float tower 3,122 (statics_long_test, 2026-11-28; the GPU
// engine, World<float>'s bits, failed on its tower 5,404 alike): 8 cubes of
// 0.687 m whose upper part, cubes 3-7, has its centre 3.3 cm beyond the edge
// of cube 2. That part toppled off, dragging cubes 1 and 2 until the centre
// of the two lay 2.3 cm beyond the edge of cube 0, and a fallen cube leaning
// on cube 1's side (pushing along -x while the two tipped towards -z) counted
// as holding it: cube 1 slept at frame 191 with its load beyond its support.
// Now the fallen cube does not hold its load (eq 117's holds_block_tip) and
// both fall, on every engine.
TYPED_TEST(HeldAcrossTest, FallenCubeBesideDoesNotHoldTheTower3122) {
  using E = TypeParam;
  const Scene s = parse_scene(R"({"format": "lockstep-scene", "version": 1, "name": "overhang",
  "ground": {"present": true, "height": 0.0, "material": {"restitution": 0.1, "friction": 0.5}},
  "bodies": [
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [0.0, 0.3436335, 0.0], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [-5.563980279349467e-17, 1.0309005, -0.30288897899504996], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [-6.019430760154812e-17, 1.7181674999999998, -0.32768254838024996], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [0.21106140388629221, 2.4054345, -0.11662114449395772], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [0.46203846039339214, 3.0927015, -0.11662114449395772], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [0.47480540863754755, 3.7799685, -0.10385419624980227], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [0.47480540863754755, 4.4672355, -0.19909548529305227], "material": {"restitution": 0.1, "friction": 0.5}},
    {"half_extents": [0.3436335, 0.3436335, 0.3436335], "mass": 0.500003, "position": [0.2621320787482476, 5.1545024999999995, -0.19909548529305224], "material": {"restitution": 0.1, "friction": 0.5}}
  ]})", "tower 3122");
  EXPECT_EQ(falls_as_statics_says<E>(s, 0.687267, -1), "");
}

// check_prop with rapidcheck's seed fixed (CI: the same towers every run)
// unless LOCKSTEP_TOWER_CASES asks for the long run or RC_PARAMS names one.
template <class Testable>
void check_prop_seeded(Testable&& testable, int cases) {
  const bool fixed = kTowerCases <= 200 && std::getenv("RC_PARAMS") == nullptr;
  ::lockstep_test::check_prop(std::forward<Testable>(testable), cases,
                              fixed ? std::optional<std::uint64_t>(20261128) : std::nullopt);
}

TEST(StaticsProp, OverhangBeyondTheEdgeFallsFixed) {
  check_prop_seeded([] { check_falls<Engine<Q16>>(*tower_gen(true)); }, kTowerCases);
}
TEST(StaticsProp, OverhangBeyondTheEdgeFallsFloat) {
  check_prop_seeded([] { check_falls<Engine<float>>(*tower_gen(true)); }, kTowerCases);
}
TEST(StaticsProp, OverhangBeyondTheEdgeFallsDouble) {
  check_prop_seeded([] { check_falls<Engine<double>>(*tower_gen(true)); }, kTowerCases);
}
TEST(StaticsProp, OverhangBeyondTheEdgeFallsGpu) {
  check_prop_seeded([] { check_falls<GpuEngine>(*tower_gen(true)); }, kTowerCases);
}

// A tower whose every upper part's centre lies 3-12 cm inside the edge under
// it stands: every cube ends within 2 cm of where it started, all asleep by
// frame 600 (the statics probe's rule), and no cube sleeps with its load
// beyond its support at any frame. Issue 30 asks 99 % of towers right on
// every engine, and so does this test: at most 1 % wrong. The towers are
// drawn from a fixed seed in CI (the same 200 every run: 1 wrong on each
// engine, 2026-11-28); the long run draws 10,000 fresh ones.
template <class E>
std::string stands(const Tower& t) {
  E e(t.scene);
  std::vector<Snap> start;
  for (int i = 0; i < e.count(); ++i) start.push_back(e.body(i));
  for (int f = 0; f < 600; ++f) {
    e.step();
    const std::string wrong = sleeping_load_beyond_support(e, t.size);
    if (!wrong.empty()) return "frame " + std::to_string(f + 1) + ": " + wrong;
  }
  double moved = 0;
  bool asleep = true;
  for (int i = 0; i < e.count(); ++i) {
    const Snap b = e.body(i);
    for (int a = 0; a < 3; ++a) moved = std::max(moved, std::fabs(b.p[a] - start[static_cast<std::size_t>(i)].p[a]));
    asleep = asleep && b.asleep;
  }
  if (moved < 0.02 && asleep) return "";
  std::ostringstream ss;
  ss << "a tower of " << e.count() << " cubes of " << t.size << " m, margin " << t.margin * 100
     << " cm: largest move " << moved << " m, all asleep " << asleep;
  return ss.str();
}

template <class E>
void check_stand_rate() {
  int total = 0, wrong = 0;
  std::string first;
  check_prop_seeded(
      [&] {
        const Tower t = *tower_gen(false);
        const std::string why = stands<E>(t);
        ++total;
        if (why.empty()) return;
        ++wrong;
        if (first.empty()) {
          first = why;
          write_failing_tower(t.scene);
        }
      },
      kTowerCases);
  std::printf("%s: %d of %d towers that statics says stand did not\n", E::name(), wrong, total);
  EXPECT_LE(100 * wrong, total) << E::name() << ": " << wrong << " of " << total << " towers did not stand; first: "
                                << first;
}

TEST(StaticsProp, OverhangInsideTheEdgeStandsFixed) { check_stand_rate<Engine<Q16>>(); }
TEST(StaticsProp, OverhangInsideTheEdgeStandsFloat) { check_stand_rate<Engine<float>>(); }
TEST(StaticsProp, OverhangInsideTheEdgeStandsDouble) { check_stand_rate<Engine<double>>(); }
TEST(StaticsProp, OverhangInsideTheEdgeStandsGpu) { check_stand_rate<GpuEngine>(); }

}  // namespace
}  // namespace lockstep::test
