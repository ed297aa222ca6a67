// Only the effects a scene calls for run: per-stage counters prove it.
#include <gtest/gtest.h>

#include "engine_types.hpp"

namespace lockstep::test {
namespace {

Scene two_cubes_falling() {
  Scene s;
  s.bodies.push_back(unit_cube(0, 0.5, 0));
  BodyDesc b = unit_cube(0.3, 1.6, 0);
  b.velocity = {1.0, 0, 0};
  s.bodies.push_back(b);
  return s;
}

StageCounters run(const Scene& s, int frames) {
  World<Q16> w(s);
  for (int i = 0; i < frames; ++i) w.step();
  return w.counters();
}

TEST(EffectsTest, EverythingOnRunsEveryStage) {
  const StageCounters c = run(two_cubes_falling(), 60);
  EXPECT_GT(c.integrate_velocity, 0u);
  EXPECT_GT(c.damping, 0u);
  EXPECT_GT(c.broadphase_bodies, 0u);
  EXPECT_GT(c.pairs_tested, 0u);
  EXPECT_GT(c.ground_contacts, 0u);
  EXPECT_GT(c.body_contacts, 0u);
  EXPECT_GT(c.normal_impulses, 0u);
  EXPECT_GT(c.friction_steps, 0u);
  EXPECT_GT(c.settling_bodies, 0u);
  EXPECT_GT(c.sleep_updates, 0u);
}

struct Case {
  const char* name;
  bool Effects::*flag;
  std::uint64_t StageCounters::*counter;
};

class EffectOff : public ::testing::TestWithParam<Case> {};

TEST_P(EffectOff, StageDoesNotRun) {
  Scene s = two_cubes_falling();
  s.effects.*(GetParam().flag) = false;
  const StageCounters c = run(s, 60);
  EXPECT_EQ(c.*(GetParam().counter), 0u) << GetParam().name;
  // And the rest still ran.
  EXPECT_GT(c.integrate_position, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Stages, EffectOff,
    ::testing::Values(Case{"gravity", &Effects::gravity, &StageCounters::integrate_velocity},
                      Case{"damping", &Effects::damping, &StageCounters::damping},
                      Case{"ground", &Effects::ground, &StageCounters::ground_contacts},
                      Case{"contacts", &Effects::contacts, &StageCounters::pairs_tested},
                      Case{"contacts-broadphase", &Effects::contacts, &StageCounters::broadphase_bodies},
                      Case{"friction", &Effects::friction, &StageCounters::friction_steps},
                      Case{"settling", &Effects::settling, &StageCounters::settling_bodies},
                      Case{"sleep", &Effects::sleep, &StageCounters::sleep_updates}),
    [](const ::testing::TestParamInfo<Case>& i) {
      std::string n = i.param.name;
      for (char& ch : n) if (ch == '-') ch = '_';
      return n;
    });

TEST(EffectsTest, RestitutionOffNeverBounces) {
  Scene s = two_cubes_falling();
  s.bodies[1].position.y = 3.0;
  s.bodies[1].material.restitution = 0.9;
  s.effects.restitution = false;
  EXPECT_EQ(run(s, 90).restitution_bounces, 0u);
  s.effects.restitution = true;
  EXPECT_GT(run(s, 90).restitution_bounces, 0u);
}

TEST(EffectsTest, SdfOffOrAbsentRunsNoSdfStage) {
  Scene s = two_cubes_falling();
  EXPECT_EQ(run(s, 30).sdf_contacts, 0u);
}

TEST(EffectsTest, SleepingBodiesCostNoIntegration) {
  Scene s;
  for (int i = 0; i < 10; ++i) {
    BodyDesc b = unit_cube(2.0 * i, 0.5, 0);
    b.asleep = true;
    s.bodies.push_back(b);
  }
  World<Q16> w(s);
  for (int i = 0; i < 30; ++i) w.step();
  EXPECT_EQ(w.counters().integrate_velocity, 0u);
  EXPECT_EQ(w.counters().integrate_position, 0u);
  EXPECT_EQ(w.counters().pairs_tested, 0u);  // 7.3: sleeping pairs are never tested
  EXPECT_EQ(w.counters().ground_contacts, 0u);
}

}  // namespace
}  // namespace lockstep::test
