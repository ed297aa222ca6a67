// The fixed engine repeats bit for bit: two runs, and a run saved and restored
// mid-way, give the same per-frame hashes (eq 92).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <vector>

#include "engine_types.hpp"
#include "lockstep/builtin_scenes.hpp"

namespace lockstep::test {
namespace {

Scene small_pile(int n, unsigned seed) {
  Scene s;
  unsigned x = seed;
  auto next = [&x]() { x = x * 1664525u + 1013904223u; return static_cast<double>(x >> 8) / 16777216.0; };
  for (int i = 0; i < n; ++i) {
    BodyDesc b = unit_cube((next() - 0.5) * 2, 1.0 + 1.2 * i, (next() - 0.5) * 2);
    b.orientation = {1, next() * 0.4 - 0.2, next() * 0.4 - 0.2, next() * 0.4 - 0.2};
    s.bodies.push_back(b);
  }
  return s;
}

std::vector<std::uint64_t> hashes(World<Q16>& w, int frames) {
  std::vector<std::uint64_t> out;
  for (int i = 0; i < frames; ++i) {
    w.step();
    out.push_back(w.state_hash());
  }
  return out;
}

RC_GTEST_PROP(DeterminismTest, TwoRunsGiveTheSameHashes, ()) {
  const int n = *rc::gen::inRange(1, 8);
  const auto seed = *rc::gen::arbitrary<unsigned>();
  const Scene s = small_pile(n, seed);
  World<Q16> a(s), b(s);
  RC_ASSERT(hashes(a, 120) == hashes(b, 120));
}

RC_GTEST_PROP(DeterminismTest, SaveAndRestoreMidRunGivesTheSameHashes, ()) {
  const Scene s = small_pile(*rc::gen::inRange(1, 8), *rc::gen::arbitrary<unsigned>());
  const int split = *rc::gen::inRange(1, 100);
  World<Q16> full(s);
  const std::vector<std::uint64_t> expected = hashes(full, 150);
  World<Q16> first(s);
  hashes(first, split);
  World<Q16> saved = first;            // save
  World<Q16> restored(Scene{});        // an unrelated world...
  restored = saved;                    // ...restored from the save
  first = World<Q16>(small_pile(3, 1));  // the original is gone
  std::vector<std::uint64_t> rest = hashes(restored, 150 - split);
  RC_ASSERT(std::equal(rest.begin(), rest.end(), expected.begin() + split));
}

// Box2D-style pinned determinism: the hash of the single-drop scene at the
// frame where it falls asleep. A change of any bit of the fixed engine moves
// it; update it only for an intended physics change (and regenerate vectors/).
// 2026-11-25 moved it from frame 94 (0x2460f2f6b01b819c) to 90: eqs 75, 98
// (support gap and weights: the cube no longer hops off its landing edge
// every third frame but slides on it; alone, frame 99), the ground
// tolerance growing with the reach (eqs 97, 107; alone, frame 84) and eq
// 99's friction cone first.
// 2026-11-26 moved it from 90 (0xa072a4d308155ca9) to 77: eq 112 (a body
// whose centre of mass is not over its support contacts does not settle:
// landing on an edge, the cube tips flat under gravity instead of being
// held back by the righting torque and the damping regimes); eq 98's
// support_fade alone left it at 90, same hash. Eq 113's skip, off by
// default, leaves both (with converged_speed 2^-5: frame 78).
// 2026-11-26 (afternoon) kept frame 77 and moved the hash from
// 0x9911e0172e48e1ea: eq 114 (the normal step through each point's row,
// the same velocities rounded differently). The pyramid's hashes moved with
// it (oriented 0x6ade4901b3a01dd0, AABB 0x91445dda8f6ec7df; both at frame 30
// still); eq 96's warm-start rule and eq 112's chain left all three.
// 2026-11-28 moved the pyramid's oriented hash from 0xb22ab51a87368732
// (frame 30 still): eqs 72-74 relative to a movable support's spin.
// 2026-11-28 (issue 29) moved both pyramid hashes (oriented from
// 0x72642753b4a5caf4, AABB from 0x072d9b29dcbecd35; frame 30 still): the
// solver's order of eqs 125-127 (the bodies' own visits, then the edges by
// colour, instead of the contact list).
// 2026-11-28 (issue 29, later) kept frame 77 and moved the drop's hash from
// 0xdf77937a2dd044a0 and both pyramid hashes (oriented from
// 0x54eb9eef991f701a, AABB from 0x91f1b6d2426d6cf3; frame 30 still): eqs
// 94-95 through the rows of eqs 114, 128-129 (m_n = 1/k_n and the friction
// step's k_t formed once per frame; the same values in exact arithmetic,
// rounded differently).
constexpr int kPinnedSleepFrame = 77;
constexpr int kPinnedOrientedStackFrame = 30;
constexpr std::uint64_t kPinnedOrientedStackHash = 0x771f9c1a93f04d1aull;
constexpr int kPinnedAabbStackFrame = 30;
constexpr std::uint64_t kPinnedAabbStackHash = 0x10291ad5a5b326aaull;
constexpr std::uint64_t kPinnedHash = 0xb62ac53796fbde47ull;
TEST(DeterminismTest, PinnedDropHashAndSleepFrame) {
  Scene s;
  BodyDesc b = unit_cube(0, 2, 0);
  b.orientation = {1, 0.05, 0, 0.03};
  s.bodies.push_back(b);
  World<Q16> w(s);
  while (!w.all_asleep() && w.frame() < 600) w.step();
  EXPECT_EQ(w.frame(), kPinnedSleepFrame);
  EXPECT_EQ(w.state_hash(), kPinnedHash);
}

// Each pair model has its own pinned hash (Box2D style: the state hash of
// the frame the scene falls asleep, and that frame): pyramid, on the fixed
// engine, with the oriented-box model (the default, docs/SPEC.md 2.4) and
// with the source's AABB model.
std::pair<int, std::uint64_t> pyramid_asleep(PairModel model) {
  Scene s = *builtin_scene("pyramid");
  s.pair_contacts = model;
  World<Q16> w(s);
  while (!w.all_asleep() && w.frame() < s.frames) w.step();
  return {w.frame(), w.state_hash()};
}

TEST(DeterminismTest, PinnedStackHashPerPairModel) {
  const auto oriented = pyramid_asleep(PairModel::kOrientedBox);
  EXPECT_EQ(oriented.first, kPinnedOrientedStackFrame);
  EXPECT_EQ(oriented.second, kPinnedOrientedStackHash) << std::hex << oriented.second;
  const auto aabb = pyramid_asleep(PairModel::kAabb);
  EXPECT_EQ(aabb.first, kPinnedAabbStackFrame);
  EXPECT_EQ(aabb.second, kPinnedAabbStackHash) << std::hex << aabb.second;
}

// Fix 11: the Q16 rounding (to nearest, ties to even) is sign-symmetric, so
// a one-body scene and its mirror image (x -> -x, or z -> -z) give mirrored
// bits every frame: p and v mirrored, the quaternion's other two components
// and the angular velocity's other two components negated (a reflection turns
// rotations the other way). Floor broke this: -x floored away from zero.
RC_GTEST_PROP(DeterminismProp, MirrorImageGivesMirroredBitsEveryFrame, ()) {
  auto raw = [](int lo, int hi) { return Q16::from_raw(*rc::gen::inRange(lo, hi + 1)).to_double(); };
  Scene s;
  BodyDesc b;
  b.half_extents = {raw(8192, 65536), raw(8192, 65536), raw(8192, 65536)};
  b.position = {raw(-65536, 65536), raw(65536, 4 * 65536), raw(-65536, 65536)};
  b.orientation = {raw(32768, 65536), raw(-20000, 20000), raw(-20000, 20000), raw(-20000, 20000)};
  b.velocity = {raw(-131072, 131072), raw(-65536, 65536), raw(-131072, 131072)};
  b.angular_velocity = {raw(-131072, 131072), raw(-131072, 131072), raw(-131072, 131072)};
  s.bodies.push_back(b);
  const int axis = *rc::gen::element(0, 2);  // mirror x or z (gravity and the ground are along y)
  Scene m = s;
  BodyDesc& mb = m.bodies[0];
  double* p[3] = {&mb.position.x, &mb.position.y, &mb.position.z};
  double* v[3] = {&mb.velocity.x, &mb.velocity.y, &mb.velocity.z};
  double* w[3] = {&mb.angular_velocity.x, &mb.angular_velocity.y, &mb.angular_velocity.z};
  double* q[3] = {&mb.orientation.x, &mb.orientation.y, &mb.orientation.z};
  *p[axis] = -*p[axis];
  *v[axis] = -*v[axis];
  for (int a = 0; a < 3; ++a)
    if (a != axis) { *w[a] = -*w[a]; *q[a] = -*q[a]; }
  World<Q16> a(s), c(m);
  for (int f = 0; f < 240; ++f) {
    a.step();
    c.step();
    const Body<Q16>& x = a.body(0);
    const Body<Q16>& y = c.body(0);
    for (int k = 0; k < 3; ++k) {
      const bool flip = k == axis;
      RC_ASSERT(y.p[k].raw() == (flip ? -x.p[k].raw() : x.p[k].raw()));
      RC_ASSERT(y.v[k].raw() == (flip ? -x.v[k].raw() : x.v[k].raw()));
      RC_ASSERT(y.w[k].raw() == (flip ? x.w[k].raw() : -x.w[k].raw()));
    }
    RC_ASSERT(y.q.w.raw() == x.q.w.raw());
    const Q16 qx[3] = {x.q.x, x.q.y, x.q.z}, qy[3] = {y.q.x, y.q.y, y.q.z};
    for (int k = 0; k < 3; ++k) RC_ASSERT(qy[k].raw() == (k == axis ? qx[k].raw() : -qx[k].raw()));
    RC_ASSERT(y.asleep == x.asleep);
  }
}

// Fix 11: a slow spin of +w and of -w about y (no gravity, no ground) turns
// by the same angle in the fixed engine after 100,000 frames: with floor,
// +0.0001 rad/s never turned and -0.0001 rad/s turned 4.48 rad (the true
// angle is 0.167 rad).
TEST(DeterminismTest, SlowSpinTurnsTheSameBothWays) {
  auto angle_after = [](double w) {
    Scene s;
    s.effects = Effects{false, false, false, false, false, false, false, false, false};
    s.ground.present = false;
    BodyDesc b;
    b.angular_velocity = {0, w, 0};
    s.bodies.push_back(b);
    World<Q16> world(s);
    for (int f = 0; f < 100000; ++f) world.step();
    const Quat<Q16>& q = world.body(0).q;
    return 2 * std::atan2(q.y.to_double(), q.w.to_double());
  };
  for (const double w : {0.0001, 0.01, 0.5}) {
    const double plus = angle_after(w), minus = angle_after(-w);
    EXPECT_EQ(plus, -minus) << "w = " << w;
  }
}

}  // namespace
}  // namespace lockstep::test
