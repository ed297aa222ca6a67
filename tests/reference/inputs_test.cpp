// Run-time inputs (issue 32, docs/SPEC.md "Run-time inputs", eqs 118-123):
// each input against its analytic effect, its wakes and its errors; ids
// across creations and removals; inputs before the first step against a
// scene built with their result; and the property: random perturbed scenes,
// random inputs at random frames and a random save frame, where the run
// resumed from save_state (load_state, and restore_state into another world)
// gives the uninterrupted run's hash after every frame and its final bytes.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "../../reference/src/snapshot_bytes.hpp"
#include "engine_types.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/input.hpp"
#include "random_inputs_gen.hpp"
#include "random_scene_gen.hpp"

namespace lockstep::test {
namespace {

template <class T>
class InputTest : public ::testing::Test {};
using InputTypes = ::testing::Types<Q16, float, double, Mp>;
TYPED_TEST_SUITE(InputTest, InputTypes);

// How close a computed change must be to the analytic one (m/s, rad/s).
template <class T> constexpr double kChangeTol = 1e-12;
template <> constexpr double kChangeTol<float> = 1e-5;
template <> constexpr double kChangeTol<Q16> = 4e-4;  // a few ulps (2^-16) through a rotation

// One box, not a cube (so that I^-1 is not isotropic), tilted, in empty space.
Scene one_box() {
  Scene s = bare_scene();
  BodyDesc b;
  b.half_extents = {0.5, 0.25, 1.0};
  b.mass = 2.0;
  b.position = {1.0, 2.0, 3.0};
  b.orientation = {0.9, 0.1, 0.3, -0.2};
  s.bodies.push_back(b);
  return s;
}

struct Dv { double v[3], w[3]; };
template <class T>
Dv velocity(const World<T>& w, int i) {
  const Body<T>& b = w.body(i);
  return {{d(b.v.x), d(b.v.y), d(b.v.z)}, {d(b.w.x), d(b.w.y), d(b.w.z)}};
}

// I^-1_world x = R diag(I^-1) R^T x (eqs 14-18, 90), in double from the body's R.
template <class T>
void inverse_inertia(const World<T>& w, int i, const double x[3], double out[3]) {
  const Body<T>& b = w.body(i);
  const double m = 1.0 / d(b.inv_mass);
  const double h[3] = {d(b.half.x), d(b.half.y), d(b.half.z)};
  const double inv_i[3] = {3.0 / (m * (h[1] * h[1] + h[2] * h[2])), 3.0 / (m * (h[0] * h[0] + h[2] * h[2])),
                           3.0 / (m * (h[0] * h[0] + h[1] * h[1]))};
  double body[3];
  for (int a = 0; a < 3; ++a) {
    body[a] = 0;
    for (int k = 0; k < 3; ++k) body[a] += d(b.R.row[k][a]) * x[k];
    body[a] *= inv_i[a];
  }
  for (int a = 0; a < 3; ++a) {
    out[a] = 0;
    for (int k = 0; k < 3; ++k) out[a] += d(b.R.row[a][k]) * body[k];
  }
}

// eq 120: an impulse J at an off-centre point r from the centre: dv = J/m,
// domega = I^-1 (r x J).
TYPED_TEST(InputTest, ImpulseAtAPointGivesTheAnalyticChange) {
  using T = TypeParam;
  World<T> w(one_box());
  const BodyId id = w.id_of(0);
  const double J[3] = {1.5, -0.5, 2.0}, r[3] = {0.25, 0.125, -0.5};
  const Body<T>& b = w.body(0);
  const Vec3d point{d(b.p.x) + r[0], d(b.p.y) + r[1], d(b.p.z) + r[2]};
  w.apply_impulse(id, {J[0], J[1], J[2]}, point);
  const double rxj[3] = {r[1] * J[2] - r[2] * J[1], r[2] * J[0] - r[0] * J[2], r[0] * J[1] - r[1] * J[0]};
  double dw[3];
  inverse_inertia(w, 0, rxj, dw);
  const Dv got = velocity(w, 0);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(got.v[a], J[a] / 2.0, kChangeTol<T>) << "v[" << a << "]";
    EXPECT_NEAR(got.w[a], dw[a], kChangeTol<T>) << "omega[" << a << "]";
  }
  EXPECT_GT(std::fabs(dw[0]) + std::fabs(dw[1]) + std::fabs(dw[2]), 1.0) << "the point must be off-centre";
}

// eq 121: a force and a torque for one step: dv = F dt / m, domega = I^-1 tau dt,
// then nothing (gravity and damping off): the force acts for one step only.
TYPED_TEST(InputTest, AForceActsForOneStep) {
  using T = TypeParam;
  World<T> w(one_box());
  const BodyId id = w.id_of(0);
  const double F[3] = {30.0, -12.0, 6.0}, tau[3] = {1.0, 2.0, -0.5}, dt = 1.0 / 60.0;
  w.add_force(id, {F[0] / 2, F[1] / 2, F[2] / 2}, {tau[0] / 2, tau[1] / 2, tau[2] / 2});
  w.add_force(id, {F[0] / 2, F[1] / 2, F[2] / 2}, {tau[0] / 2, tau[1] / 2, tau[2] / 2});  // summed
  EXPECT_EQ(d(w.pending_force(0).first.x), F[0]);
  const Dv before = velocity(w, 0);
  EXPECT_EQ(before.v[0], 0.0) << "a force acts in the next step, not at once";
  double dw[3];
  const double tdt[3] = {tau[0] * dt, tau[1] * dt, tau[2] * dt};
  inverse_inertia(w, 0, tdt, dw);  // R at the step's start
  w.step();
  const Dv got = velocity(w, 0);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(got.v[a], F[a] * dt / 2.0, kChangeTol<T>) << "v[" << a << "]";
    EXPECT_NEAR(got.w[a], dw[a], kChangeTol<T>) << "omega[" << a << "]";
  }
  EXPECT_EQ(d(w.pending_force(0).first.x), 0.0) << "cleared by the step";
  w.step();
  const Dv after = velocity(w, 0);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(after.v[a], got.v[a]) << "the force acted a second time";
}

// eq 122 then a step: the body is where the pose put it, moved by v dt; the
// run equals, bit for bit, a world whose scene has the body at that pose.
TYPED_TEST(InputTest, SetPoseThenStepEqualsTheSceneWithThatPose) {
  using T = TypeParam;
  Scene s = *builtin_scene("stack5");
  World<T> w(s);
  for (int f = 0; f < 5; ++f) w.step();  // a warm-start cache and contacts exist
  const Vec3d p{0.375, 6.5, -0.25};
  const Quatd q{0.8, 0.1, -0.2, 0.3};
  World<T> moved = w;
  moved.set_pose(moved.id_of(4), p, q);
  EXPECT_EQ(d(moved.body(4).p.y), 6.5);
  EXPECT_FALSE(moved.body(4).asleep);
  // The same pose given through the scene (the other bodies as the snapshot has them).
  World<T> loaded = World<T>::load_state(w.save_state());
  Scene posed = loaded.scene();
  posed.bodies[4].position = p;
  posed.bodies[4].orientation = q;
  World<T> fresh(posed);
  // fresh has no warm-start cache at all; moved dropped body 4's entries only:
  // they agree on body 4 at once, and moved steps on from there.
  EXPECT_EQ(d(fresh.body(4).q.x), d(moved.body(4).q.x)) << "q normalised as the loader does";
  const double y0 = d(moved.body(4).p.y), vy = d(moved.body(4).v.y);
  moved.step();
  EXPECT_NEAR(d(moved.body(4).p.y), y0 + (vy - 9.81 / 60.0) / 60.0, 1e-3) << "a free step from the new pose";
}

// eq 119: destroying the bottom box of a sleeping stack wakes the box that
// rests on it; the stack then falls onto the ground.
TYPED_TEST(InputTest, DestroyWakesTheSleepersRestingOnIt) {
  using T = TypeParam;
  if constexpr (std::is_same_v<T, Mp>) GTEST_SKIP() << "stack5 to sleep is slow on mp";
  else {
    World<T> w(*builtin_scene("stack5"));
    for (int f = 0; f < 400; ++f) w.step();
    ASSERT_TRUE(w.all_asleep());
    int bottom = 0;
    for (int i = 1; i < 5; ++i)
      if (w.body(i).p.y < w.body(bottom).p.y) bottom = i;
    const double top_y = d(w.body(4).p.y);
    const std::uint64_t wakes = w.counters().wakes;
    w.destroy_body(w.id_of(bottom));
    ASSERT_EQ(w.bodies().size(), 4u);
    EXPECT_GT(w.awake_count(), 0) << "the box on the destroyed one must wake";
    EXPECT_GT(w.counters().wakes, wakes);
    for (int f = 0; f < 120; ++f) w.step();
    EXPECT_LT(d(w.body(3).p.y), top_y - 0.5) << "the stack falls into the gap";
  }
}

// Touched sleepers wake: impulse, force, pose, velocity and wake each wake a
// sleeping body; an input on a static body that cannot move it does nothing.
TYPED_TEST(InputTest, ATouchedBodyWakes) {
  using T = TypeParam;
  Scene s = *builtin_scene("stack5");
  for (BodyDesc& b : s.bodies) b.asleep = true;
  BodyDesc slab;
  slab.is_static = true;
  slab.position = {10, 0.5, 0};
  s.bodies.push_back(slab);
  for (int kind = 0; kind < 5; ++kind) {
    World<T> w(s);
    const BodyId id = w.id_of(2);
    ASSERT_TRUE(w.body(2).asleep);
    Input in;
    in.id = id;
    in.kind = std::array{InputKind::impulse, InputKind::force, InputKind::set_pose, InputKind::set_velocity, InputKind::wake}[static_cast<std::size_t>(kind)];
    in.a = {0.0, 0.5, 0.0};
    in.b = {d(w.body(2).p.x), d(w.body(2).p.y), d(w.body(2).p.z)};
    if (in.kind == InputKind::set_pose) in.a = in.b;
    w.apply(in);
    EXPECT_FALSE(w.body(2).asleep) << input_kind_name(in.kind);
    const std::uint64_t hash = w.state_hash();
    in.id = w.id_of(5);  // the static slab
    if (in.kind != InputKind::set_pose) {
      w.apply(in);
      EXPECT_EQ(w.state_hash(), hash) << input_kind_name(in.kind) << " moved a static body";
    }
  }
}

// Stale and unknown ids, bad descriptions and values, the wrong frame: each a
// std::invalid_argument naming the field, the value and a fix; the world unchanged.
TEST(InputErrors, NameTheFieldTheValueAndAFix) {
  World<Q16> w(*builtin_scene("stack5"));
  const BodyId first = w.id_of(0);
  w.destroy_body(first);
  const std::uint64_t hash = w.state_hash();
  auto message = [&](auto&& f) -> std::string {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  const std::string stale = message([&] { w.apply_impulse(first, {1, 0, 0}, {0, 0, 0}); });
  EXPECT_NE(stale.find("apply_impulse: body (slot 0, generation 0) is stale"), std::string::npos) << stale;
  EXPECT_NE(stale.find("destroyed"), std::string::npos) << stale;
  const std::string unknown = message([&] { w.wake(BodyId{99, 0}); });
  EXPECT_NE(unknown.find("slot 99"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("names no body"), std::string::npos) << unknown;
  BodyDesc heavy;
  heavy.mass = -1.0;
  const std::string desc = message([&] { w.create_body(heavy); });
  EXPECT_NE(desc.find("create_body: input.body.mass"), std::string::npos) << desc;
  EXPECT_NE(desc.find("-1"), std::string::npos) << desc;
  BodyDesc tiny;  // the fixed engine's 1/m overflows (validate_scene_for)
  tiny.mass = 1e-6;
  const std::string fixed = message([&] { w.create_body(tiny); });
  EXPECT_NE(fixed.find("input.body.mass"), std::string::npos) << fixed;
  EXPECT_NE(fixed.find("fixed"), std::string::npos) << fixed;
  const std::string far = message([&] { w.set_pose(w.id_of(0), {40000, 0, 0}, {}); });
  EXPECT_NE(far.find("input.position"), std::string::npos) << far;
  const std::string nan = message([&] { w.apply_impulse(w.id_of(0), {std::nan(""), 0, 0}, {0, 0, 0}); });
  EXPECT_NE(nan.find("input.a (J)"), std::string::npos) << nan;
  EXPECT_NE(nan.find("not finite"), std::string::npos) << nan;
  const std::string fast = message([&] { w.set_velocity(w.id_of(0), {2000, 0, 0}, {}); });
  EXPECT_NE(fast.find("input.velocity"), std::string::npos) << fast;
  Input late;
  late.frame = 5;
  late.id = w.id_of(0);
  const std::string frame = message([&] { w.apply(late); });
  EXPECT_NE(frame.find("input.frame = 5 but the world is at frame 0"), std::string::npos) << frame;
  EXPECT_EQ(w.state_hash(), hash) << "a refused input changed the world";
  EXPECT_EQ(w.bodies().size(), 4u);
}

// Ids: a removal stales the id and moves the later bodies down (their ids
// kept); a creation appends and takes the lowest free slot, one generation up.
TEST(InputIds, StableAcrossRemovalsAndReusedLowestFirst) {
  World<double> w(*builtin_scene("stack5"));
  const BodyId b1 = w.id_of(1), b3 = w.id_of(3), b4 = w.id_of(4);
  const double y4 = w.body(4).p.y;
  w.destroy_body(b3);
  w.destroy_body(b1);
  EXPECT_FALSE(w.contains(b1));
  EXPECT_EQ(w.index_of(b4), 2);
  EXPECT_EQ(w.body(w.index_of(b4)).p.y, y4);
  EXPECT_EQ(w.next_id(), (BodyId{1, 1}));
  const BodyId c = w.create_body(BodyDesc{});
  EXPECT_EQ(c, (BodyId{1, 1}));
  EXPECT_EQ(w.index_of(c), 3);
  EXPECT_EQ(w.create_body(BodyDesc{}), (BodyId{3, 1}));
  EXPECT_EQ(w.create_body(BodyDesc{}), (BodyId{5, 0}));
  EXPECT_EQ(w.scene().bodies.size(), 6u) << "scene() holds the created bodies' shapes";
  // The id table survives a snapshot.
  World<double> back = World<double>::load_state(w.save_state());
  for (int i = 0; i < 6; ++i) EXPECT_EQ(back.id_of(i), w.id_of(i));
  EXPECT_EQ(back.next_id(), w.next_id());
  EXPECT_FALSE(back.contains(b1));
}

// The snapshot's id table and pending forces (docs/SNAPSHOTS.md "Then") are
// checked like the rest: a slot past the table or held twice, a force
// naming no body, each refused with a SnapshotError naming the field.
TEST(InputSnapshots, BadIdTablesAndForcesAreRefused) {
  World<Q16> w(*builtin_scene("stack5"));
  w.destroy_body(w.id_of(1));  // slots 0..4, slot 1 free at generation 1; frame 0: every counter 0
  w.add_force(w.id_of(0), {1, 2, 3}, {0, 0, 1});
  const std::vector<std::uint8_t> good = w.save_state();
  ASSERT_NO_THROW(World<Q16>::load_state(good));
  // ... the ids (5; 0 1 0 0 0; 0 2 3 4), forces (1; 0; 6 numbers), 16 counters (0), checksum.
  const std::size_t forces = good.size() - 8 - 16 - 2 - 24, last_slot = forces - 1;
  ASSERT_EQ(good[last_slot], 4);
  ASSERT_EQ(good[forces], 1);
  auto refusal = [](std::vector<std::uint8_t> b, std::size_t at, std::uint8_t value) -> std::string {
    b[at] = value;
    const std::uint64_t sum = snap::checksum(b.data(), b.size() - 8);
    for (int i = 0; i < 8; ++i) b[b.size() - 8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(sum >> (8 * i));
    try {
      (void)World<Q16>::load_state(b);
    } catch (const SnapshotError& e) {
      return e.field + ": " + e.what();
    }
    return "";
  };
  const std::string twice = refusal(good, last_slot, 0);
  EXPECT_NE(twice.find("holds another body"), std::string::npos) << twice;
  const std::string past = refusal(good, last_slot, 9);
  EXPECT_NE(past.find("ids.slot[3]"), std::string::npos) << past;
  const std::string body = refusal(good, forces + 1, 7);
  EXPECT_NE(body.find("forces[0]"), std::string::npos) << body;
  const std::string count = refusal(good, forces, 9);
  EXPECT_NE(count.find("forces.count"), std::string::npos) << count;
}

// Inputs before the first step equal a scene built with their result, bit
// for bit, frame after frame: a creation (the body appended), a removal (the
// body left out), a velocity and a pose.
TYPED_TEST(InputTest, InputsBeforeTheFirstStepEqualTheResultingScene) {
  using T = TypeParam;
  const int frames = std::is_same_v<T, Mp> ? 20 : 150;
  const Scene base = *builtin_scene("stack5");
  BodyDesc crate;
  crate.half_extents = {0.375, 0.25, 0.5};
  crate.mass = 3.0;
  crate.position = {1.5, 3.0, 0.25};
  crate.orientation = {0.95, 0.05, 0.2, 0.0};
  crate.velocity = {-2.0, 0.0, 0.0};
  World<T> a(base);
  a.create_body(crate);
  a.destroy_body(a.id_of(2));
  a.set_velocity(a.id_of(0), {0.25, 0.0, 0.0}, {0.0, 0.5, 0.0});
  a.set_pose(a.id_of(3), {0.125, 6.0, 0.0}, {1.0, 0.0, 0.1, 0.0});
  Scene s = base;
  s.bodies.push_back(crate);
  s.bodies.erase(s.bodies.begin() + 2);
  s.bodies[0].velocity = {0.25, 0.0, 0.0};
  s.bodies[0].angular_velocity = {0.0, 0.5, 0.0};
  s.bodies[3].position = {0.125, 6.0, 0.0};
  s.bodies[3].orientation = {1.0, 0.0, 0.1, 0.0};
  World<T> b(s);
  ASSERT_EQ(a.state_hash(), b.state_hash());
  for (int f = 1; f <= frames; ++f) {
    a.step();
    b.step();
    ASSERT_EQ(a.state_hash(), b.state_hash()) << "frame " << f;
  }
}

// ---- The property: random scenes, inputs and save frames ---------------------

// Steps w from its frame to `last`, applying inputs[k] (those of frame f
// before step f) and collecting the hash after each step. `applied`: those of
// the next frame are in w already (a snapshot saved between inputs and step).
template <class T>
std::vector<std::uint64_t> run(World<T>& w, const std::vector<Input>& inputs, int last, bool applied = false) {
  std::vector<std::uint64_t> h;
  std::size_t k = 0;
  while (k < inputs.size() && inputs[k].frame <= w.frame() + (applied ? 1 : 0)) ++k;
  while (w.frame() < last) {
    for (; k < inputs.size() && inputs[k].frame == w.frame() + 1; ++k) w.apply(inputs[k]);
    w.step();
    h.push_back(w.state_hash());
  }
  return h;
}

template <class T>
void random_inputs_resume(int max_frames) {
  const Scene scene = *random_scene();
  const int frames = *rc::gen::inRange(1, max_frames + 1);
  const int save = *rc::gen::inRange(0, frames + 1);
  // Saved between the inputs of frame save + 1 and its step (forces pending,
  // bodies just created or moved), or before those inputs.
  const bool mid = save < frames && *rc::gen::arbitrary<bool>();
  const std::vector<Drawn> drawn = *drawn_inputs(frames);
  const std::vector<Drawn> other_drawn = *drawn_inputs(20);
  const int other_frames = *rc::gen::inRange(0, 20);
  try {
    // The uninterrupted run, recording the concrete inputs it applied.
    World<T> w(scene);
    std::vector<Input> applied;
    std::vector<std::uint64_t> want;
    std::vector<std::uint8_t> bytes;
    std::size_t k = 0;
    for (int f = 1; f <= frames; ++f) {
      if (f - 1 == save && !mid) bytes = w.save_state();
      for (; k < drawn.size() && drawn[k].frame == f; ++k) {
        if (drawn[k].kind != InputKind::create && w.bodies().empty()) continue;
        const Input in = concrete(drawn[k], w);
        try {
          w.apply(in);
          applied.push_back(in);
        } catch (const std::invalid_argument&) {  // refused (a value out of T's range): the world is unchanged
        }
      }
      if (f - 1 == save && mid) bytes = w.save_state();
      w.step();
      want.push_back(w.state_hash());
    }
    if (save == frames) bytes = w.save_state();
    const std::vector<std::uint64_t> tail(want.begin() + save, want.end());
    // Resumed from the bytes alone.
    World<T> loaded = World<T>::load_state(bytes);
    RC_ASSERT(loaded.frame() == save);
    RC_ASSERT(run(loaded, applied, frames, mid) == tail);
    RC_ASSERT(loaded.save_state() == w.save_state());
    // Restored into another world of the scene, which had inputs of its own.
    World<T> other(scene);
    std::vector<Input> other_applied;
    for (const Drawn& x : other_drawn) {
      if (x.frame > other_frames || (x.kind != InputKind::create && other.bodies().empty())) continue;
      while (other.frame() < x.frame - 1) other.step();
      try {
        other.apply(concrete(x, other));
      } catch (const std::invalid_argument&) {
      }
    }
    other.restore_state(bytes);
    RC_ASSERT(run(other, applied, frames, mid) == tail);
    RC_ASSERT(other.save_state() == w.save_state());
  } catch (const RunError&) {
    RC_DISCARD("the run stopped (RunError)");
  }
}

RC_GTEST_PROP(InputProperty, RandomInputsResumeFixed, ()) { random_inputs_resume<Q16>(200); }
RC_GTEST_PROP(InputProperty, RandomInputsResumeFloat, ()) { random_inputs_resume<float>(200); }
RC_GTEST_PROP(InputProperty, RandomInputsResumeDouble, ()) { random_inputs_resume<double>(200); }

// mp is slow: a few fixed seeds' worth, 30 frames each.
TEST(InputProperty, RandomInputsResumeMp) {
  const auto result = rc::check("mp", [] { random_inputs_resume<Mp>(30); });
  EXPECT_TRUE(result);
}

}  // namespace
}  // namespace lockstep::test
