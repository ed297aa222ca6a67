// World<T> on N threads (docs/SPEC.md 7.7 "Threads", eqs 125-127): every
// frame's state hash and counters are the same for N in {1, 2, 3, 8}, on
// random perturbed piles large enough that the solver's steps are cut into
// several parts (a step runs in parallel only from 16 visits up).
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "engine_types.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/world.hpp"
#include "random_scene_gen.hpp"

namespace lockstep {
namespace {

using test::grid;

// 4-9 columns of 3-9 boxes (sizes 0.3-0.6 m, masses 0.5-4 kg, tilted, off
// their column's axis, some spinning), dropped with gaps onto the ground or
// into the SDF bowl, either pair model, now and then an effect off: the
// columns fall into each other, so the frames have many edges and colours.
rc::Gen<Scene> random_pile() {
  return rc::gen::exec([] {
    Scene s;
    s.name = "threads_case";
    s.frames = 150;
    s.pair_contacts = *rc::gen::inRange(0, 4) == 0 ? PairModel::kAabb : PairModel::kOrientedBox;
    const bool bowl = *rc::gen::inRange(0, 5) == 0;
    if (bowl) s.sdfs = builtin_scene("bowl")->sdfs;
    s.effects.sdf = bowl;
    if (*rc::gen::inRange(0, 5) == 0) {
      s.effects.settling = *rc::gen::arbitrary<bool>();
      s.effects.friction = *rc::gen::arbitrary<bool>();
      s.effects.restitution = *rc::gen::arbitrary<bool>();
    }
    s.ground.material = {grid(0, 8, 1.0 / 16), grid(2, 16, 1.0 / 16)};
    const int columns = *rc::gen::inRange(4, 10);
    for (int c = 0; c < columns; ++c) {
      const double cx = (c % 3) * 1.25 - 1.25 + grid(-2, 2, 1.0 / 16), cz = (c / 3) * 1.25 - 1.25 + grid(-2, 2, 1.0 / 16);
      double y = bowl ? 1.0 : 0.0;
      const int height = *rc::gen::inRange(3, 10);
      for (int k = 0; k < height; ++k) {
        BodyDesc b;
        b.half_extents = {grid(20, 38, 1.0 / 64), grid(20, 38, 1.0 / 64), grid(20, 38, 1.0 / 64)};
        b.mass = grid(2, 16, 0.25);
        b.material = {grid(0, 8, 1.0 / 16), grid(2, 16, 1.0 / 16)};
        b.position = {cx + grid(-4, 4, 1.0 / 32), y + b.half_extents.y + grid(0, 6, 1.0 / 16), cz + grid(-4, 4, 1.0 / 32)};
        y = b.position.y + b.half_extents.y;
        b.orientation = {1.0, grid(-4, 4, 1.0 / 64), grid(-8, 8, 1.0 / 16), grid(-4, 4, 1.0 / 64)};
        if (*rc::gen::inRange(0, 4) == 0) b.angular_velocity = {grid(-4, 4, 1.0 / 4), grid(-4, 4, 1.0 / 4), grid(-4, 4, 1.0 / 4)};
        s.bodies.push_back(b);
      }
    }
    return s;
  });
}

struct Trace {
  std::vector<std::uint64_t> hashes;
  StageCounters counters;
};

template <class T>
Trace run(const Scene& s, int threads, int frames) {
  World<T> w(s);
  w.set_threads(threads);
  Trace t;
  for (int f = 0; f < frames; ++f) {
    w.step();
    t.hashes.push_back(w.state_hash());
  }
  t.counters = w.counters();
  return t;
}

template <class T>
void same_bits_for_every_thread_count(int frames) {
  const Scene s = *random_pile();
  const Trace one = run<T>(s, 1, frames);
  for (int threads : {2, 3, 8}) {
    const Trace many = run<T>(s, threads, frames);
    for (std::size_t f = 0; f < one.hashes.size(); ++f)
      if (many.hashes[f] != one.hashes[f])
        RC_FAIL("frame " + std::to_string(f + 1) + " differs on " + std::to_string(threads) + " threads");
    RC_ASSERT(many.counters.solver_contacts == one.counters.solver_contacts);
    RC_ASSERT(many.counters.normal_impulses == one.counters.normal_impulses);
    RC_ASSERT(many.counters.friction_steps == one.counters.friction_steps);
    RC_ASSERT(many.counters.corrections == one.counters.corrections);
  }
}

RC_GTEST_PROP(ThreadsProp, SameBitsForEveryThreadCountFixed, ()) { same_bits_for_every_thread_count<Q16>(150); }
RC_GTEST_PROP(ThreadsProp, SameBitsForEveryThreadCountFloat, ()) { same_bits_for_every_thread_count<float>(150); }
RC_GTEST_PROP(ThreadsProp, SameBitsForEveryThreadCountDouble, ()) { same_bits_for_every_thread_count<double>(150); }

// The truth engine too, on a shorter run (multiprecision is slow).
TEST(ThreadsTest, MpGivesTheSameBitsOnThreeThreads) {
  Scene s = *builtin_scene("pyramid");
  for (BodyDesc& b : s.bodies) b.position.y += 0.25;  // dropped: its contacts form and change
  const Trace one = run<Mp>(s, 1, 40), three = run<Mp>(s, 3, 40);
  EXPECT_EQ(one.hashes, three.hashes);
}

// The busy frames of pile1000 (the columns falling into each other, up to
// 6,000 contacts, 1,000 bodies): every stage runs in several parts (the
// broad phase's cells, the environment's contacts, the stances, the manifolds
// and the solver's passes, whose parts wait on each other's bodies; loads,
// settling and eqs 110-111 by groups of bodies; positions and sleep counters
// in chunks), and the bits and counters are the single thread's, frame for
// frame, on 2 and 3 threads (3: cuts that fall mid-column), fixed and float.
template <class T>
void check_pile1000_busy_frames() {
  const Scene s = *builtin_scene("pile1000");
  const Trace one = run<T>(s, 1, 90);
  for (int threads : {2, 3}) {
    const Trace many = run<T>(s, threads, 90);
    EXPECT_EQ(one.hashes, many.hashes) << threads << " threads";
    EXPECT_EQ(one.counters.solver_contacts, many.counters.solver_contacts) << threads << " threads";
    EXPECT_EQ(one.counters.normal_impulses, many.counters.normal_impulses) << threads << " threads";
    EXPECT_EQ(one.counters.pairs_tested, many.counters.pairs_tested) << threads << " threads";
    EXPECT_EQ(one.counters.ground_contacts, many.counters.ground_contacts) << threads << " threads";
    EXPECT_EQ(one.counters.body_contacts, many.counters.body_contacts) << threads << " threads";
    EXPECT_EQ(one.counters.corrections, many.counters.corrections) << threads << " threads";
    EXPECT_EQ(one.counters.settling_bodies, many.counters.settling_bodies) << threads << " threads";
    EXPECT_EQ(one.counters.sleep_updates, many.counters.sleep_updates) << threads << " threads";
    EXPECT_EQ(one.counters.integrate_position, many.counters.integrate_position) << threads << " threads";
  }
}
TEST(ThreadsTest, Pile1000BusyFramesSameBitsOnTwoAndThreeThreadsFixed) { check_pile1000_busy_frames<Q16>(); }
TEST(ThreadsTest, Pile1000BusyFramesSameBitsOnTwoAndThreeThreadsFloat) { check_pile1000_busy_frames<float>(); }

// A world's threads are not state: a copy steps on as many, and a bad count
// is refused with the value named.
TEST(ThreadsTest, CountIsCheckedAndCopied) {
  World<float> w(*builtin_scene("stack5"));
  EXPECT_THROW(w.set_threads(0), std::invalid_argument);
  EXPECT_THROW(w.set_threads(257), std::invalid_argument);
  try {
    w.set_threads(-3);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("threads = -3"), std::string::npos) << e.what();
  }
  w.set_threads(4);
  const World<float> copy(w);
  EXPECT_EQ(copy.threads(), 4);
  EXPECT_EQ(w.threads(), 4);
}

// Where a fixed run of `s` on `threads` threads stops within `frames`
// frames: "frame body quantity message", or "no stop".
std::string stop_message(const Scene& s, int threads, int frames) {
  World<Q16> w(s);
  w.set_threads(threads);
  for (int f = 0; f < frames; ++f) {
    try {
      w.step();
    } catch (const RunError& e) {
      return std::to_string(e.frame) + " " + std::to_string(e.body) + " " + e.quantity + " " + e.what();
    }
  }
  return std::string("no stop");
}

// A Q16.16 overflow inside a parallel step stops the run as on one thread:
// the same frame, body and quantity.
TEST(ThreadsTest, OverflowInAParallelStepNamesTheSameBody) {
  Scene s = *builtin_scene("pile1000");
  // a whole layer driven into the one below: 100 edges of one colour
  // overflow at once, in every part of the step
  for (std::size_t i = 500; i < 600; ++i) s.bodies[i].velocity = {0.0, -30000.0, 0.0};
  auto stop = [&](int threads) { return stop_message(s, threads, 200); };
  const std::string one = stop(1);
  EXPECT_NE(one.find("contact impulse"), std::string::npos) << one;  // in the solver's parallel steps
  EXPECT_EQ(stop(2), one);
  EXPECT_EQ(stop(8), one);
}

// Whole islands (7.7 "Threads"): 64 islands 20 m apart, in each a 1000 kg
// cube falling at 400 m/s onto a cube resting on the ground (the impulse
// leaves Q16.16). The last 32 islands also have a third cube beside the
// struck one, so they are heavier and the parts run them first; the first
// failing visit in the serial order is in the first island, which is light
// and runs late. The run must stop where a single thread stops, not at the
// first failure a part happens to meet.
TEST(ThreadsTest, OverflowInWholeIslandsNamesTheSameBody) {
  Scene s;
  for (int c = 0; c < 64; ++c) {
    const double x = 20.0 * (c % 8), z = 20.0 * (c / 8);
    BodyDesc b;
    b.half_extents = {0.5, 0.5, 0.5};
    b.mass = 1000.0;
    b.position = {x, 0.5, z};
    s.bodies.push_back(b);
    b.position = {x, 1.55, z};
    b.velocity = {0.0, -400.0, 0.0};
    s.bodies.push_back(b);
    if (c >= 32) {
      b.position = {x + 1.0, 0.5, z};
      b.velocity = {};
      s.bodies.push_back(b);
    }
  }
  auto stop = [&](int threads) { return stop_message(s, threads, 20); };
  const std::string one = stop(1);
  EXPECT_NE(one.find("frame 1, body 1, contact impulse"), std::string::npos) << one;
  EXPECT_EQ(stop(2), one);
  EXPECT_EQ(stop(3), one);
  EXPECT_EQ(stop(8), one);
}

}  // namespace
}  // namespace lockstep
