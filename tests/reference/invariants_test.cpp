// rapidcheck invariants of the engine (issue 3): unit quaternions, nothing
// resting below the ground by more than slop, sleeping bodies stay put, and
// momentum conservation through body-body contacts without gravity or ground.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "engine_types.hpp"
#include "lockstep/physics/aabb.hpp"

namespace lockstep::test {
namespace {

double gen_unit(int lo, int hi, int scale) { return *rc::gen::inRange(lo, hi) / static_cast<double>(scale); }

BodyDesc random_cube() {
  BodyDesc b;
  const double h = gen_unit(20, 100, 100);
  b.half_extents = {h, h, h};
  b.mass = gen_unit(1, 50, 10);
  b.position = {gen_unit(-300, 300, 100), gen_unit(60, 500, 100), gen_unit(-300, 300, 100)};
  b.orientation = {1.0, gen_unit(-100, 100, 100), gen_unit(-100, 100, 100), gen_unit(-100, 100, 100)};
  b.velocity = {gen_unit(-300, 300, 100), gen_unit(-300, 300, 100), gen_unit(-300, 300, 100)};
  b.angular_velocity = {gen_unit(-300, 300, 100), gen_unit(-300, 300, 100), gen_unit(-300, 300, 100)};
  b.material = {gen_unit(0, 100, 100), gen_unit(0, 100, 100)};
  return b;
}

Scene random_scene(int max_bodies) {
  Scene s;
  const int n = *rc::gen::inRange(1, max_bodies + 1);
  for (int i = 0; i < n; ++i) s.bodies.push_back(random_cube());
  return s;
}

template <class T>
double quat_norm_error(const Body<T>& b) {
  const double w = d(b.q.w), x = d(b.q.x), y = d(b.q.y), z = d(b.q.z);
  return std::fabs(std::sqrt(w * w + x * x + y * y + z * z) - 1.0);
}

// |q| stays within 2^-13 of 1 in Q16 (normalise: two floors per component, 4
// components of 2 ulp each -> |q| - 1 in (-2^-14, 0], plus the step) and 1e-6 in float.
RC_GTEST_PROP(InvariantsTest, QuaternionsStayUnit, ()) {
  const Scene s = random_scene(4);
  World<Q16> wq(s);
  World<float> wf(s);
  for (int f = 0; f < 200; ++f) {
    wq.step();
    wf.step();
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      RC_ASSERT(quat_norm_error(wq.body(static_cast<int>(i))) < std::ldexp(1.0, -13));
      RC_ASSERT(quat_norm_error(wf.body(static_cast<int>(i))) < 1e-6);
    }
  }
}

// No body at rest lies below the ground by more than slop (plus one frame of
// gravity, which the next frame's correction removes).
RC_GTEST_PROP(InvariantsTest, NothingRestsBelowTheGround, ()) {
  const Scene s = random_scene(4);
  World<Q16> w(s);
  for (int f = 0; f < 600; ++f) w.step();
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const Body<Q16>& b = w.body(static_cast<int>(i));
    if (!b.asleep) continue;
    double lowest = 1e9;
    for (int k = 0; k < 8; ++k) lowest = std::min(lowest, d(box_corner(b.p, b.R, b.half, k).y));
    RC_ASSERT(lowest > -(0.001 + 9.81 / 3600 + 1e-4));
  }
}

// A sleeping body's state does not change while it sleeps.
RC_GTEST_PROP(InvariantsTest, SleepingBodiesDoNotMove, ()) {
  const Scene s = random_scene(3);
  World<Q16> w(s);
  std::vector<Body<Q16>> last(s.bodies.size());
  std::vector<bool> was_asleep(s.bodies.size(), false);
  for (int f = 0; f < 500; ++f) {
    w.step();
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      const Body<Q16>& b = w.body(static_cast<int>(i));
      if (was_asleep[i] && b.asleep) {
        RC_ASSERT(b.p == last[i].p);
        RC_ASSERT(b.q == last[i].q);
        RC_ASSERT(b.v == Vec3<Q16>{});
      }
      was_asleep[i] = b.asleep;
      last[i] = b;
    }
  }
}

// Without gravity, ground or settling, body-body impulses are equal and
// opposite: total linear momentum is conserved (to rounding in double).
RC_GTEST_PROP(InvariantsTest, MomentumConservedThroughContacts, ()) {
  Scene s = random_scene(5);
  s.effects.gravity = s.effects.ground = s.effects.settling = s.effects.damping = s.effects.sleep = false;
  s.ground.present = false;
  // All bodies head for the origin, so bodies collide whenever there are two.
  for (auto& b : s.bodies) b.velocity = {-2 * b.position.x, -2 * b.position.y, -2 * b.position.z};
  World<double> w(s);
  auto momentum = [&]() {
    double p[3] = {0, 0, 0};
    for (const auto& b : w.bodies())
      for (int a = 0; a < 3; ++a) p[a] += b.v[a] / b.inv_mass;
    return std::vector<double>(p, p + 3);
  };
  const std::vector<double> p0 = momentum();
  for (int f = 0; f < 120; ++f) w.step();
  const std::vector<double> p1 = momentum();
  if (s.bodies.size() >= 2) RC_ASSERT(w.counters().normal_impulses > 0u);
  for (int a = 0; a < 3; ++a) RC_ASSERT(std::fabs(p1[static_cast<std::size_t>(a)] - p0[static_cast<std::size_t>(a)]) < 1e-9);
}

}  // namespace
}  // namespace lockstep::test
