// Run-time inputs on the GPU engine's host build (docs/GPU.md "Run-time
// inputs"): the same inputs as World<T>, taken up by rebuilding the pipeline.
// Bodies that touch nothing keep World<float>'s bits through every input
// (no warm-start cache or eq 108 record is lost); with contacts the engine
// is deterministic: the same inputs in the same frames, through EngineRun,
// give the same hashes, with World<float>'s ids, body order and refusals.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "reference/random_inputs_gen.hpp"
#include "scene_helpers.hpp"

namespace lockstep {
namespace {

using gpu::GpuWorld;
using gpu_test::host_options;

// Two boxes falling in empty space (no ground), and the inputs of every kind.
TEST(GpuInputs, FreeBodiesMatchWorldFloatBitForBit) {
  Scene s;
  s.ground.present = false;
  BodyDesc a, b;
  a.half_extents = {0.5, 0.25, 0.75};
  a.mass = 2.0;
  a.position = {0, 50, 0};
  a.orientation = {0.9, 0.1, 0.3, -0.2};
  b = a;
  b.position = {20, 50, 0};
  s.bodies = {a, b};
  GpuWorld g(s, host_options());
  World<float> w(s);
  std::vector<Input> inputs;
  auto at = [&inputs](int frame, InputKind kind, BodyId id, Vec3d x, Vec3d y) {
    Input in;
    in.frame = frame;
    in.kind = kind;
    in.id = id;
    in.a = x;
    in.b = y;
    inputs.push_back(in);
    return &inputs.back();
  };
  at(3, InputKind::impulse, {0, 0}, {1.5, -0.5, 2.0}, {0.25, 50.125, -0.5});
  at(5, InputKind::force, {1, 0}, {30, -12, 6}, {1, 2, -0.5});
  at(5, InputKind::force, {1, 0}, {3, 0, 0}, {0, 0, 0});
  Input* create = at(8, InputKind::create, {}, {}, {});
  create->body = a;
  create->body.position = {-20, 40, 0};
  at(12, InputKind::destroy, {0, 0}, {}, {});
  at(15, InputKind::set_pose, {2, 0}, {-25, 45, 1}, {});
  inputs.back().q = {0.5, 0.5, 0.5, 0.5};
  at(18, InputKind::set_velocity, {1, 0}, {1, 2, 3}, {0.5, 0, 0});
  at(20, InputKind::create, {}, {}, {})->body = b;  // slot 0 again, generation 1
  at(22, InputKind::impulse, {0, 1}, {0, 5, 0}, {20, 30, 0});
  std::size_t k = 0;
  for (int f = 1; f <= 40; ++f) {
    for (; k < inputs.size() && inputs[k].frame == f; ++k) {
      const BodyId gid = g.apply(inputs[k]);
      const BodyId wid = w.apply(inputs[k]);
      ASSERT_EQ(gid, wid) << "frame " << f;
    }
    ASSERT_EQ(g.body_count(), static_cast<int>(w.bodies().size())) << "frame " << f;
    g.step();
    w.step();
    ASSERT_EQ(g.state_hash(), w.state_hash()) << "frame " << f;
  }
  EXPECT_EQ(g.id_of(2), (BodyId{0, 1}));
  EXPECT_EQ(g.frame(), 40);
  EXPECT_THROW(g.index_of(BodyId{0, 0}), std::invalid_argument);
}

// Random perturbed scenes and random inputs through EngineRun: two GPU runs
// give the same hash after every frame, and accept or refuse each input as
// World<float> does (so that their ids and body order agree).
RC_GTEST_PROP(GpuInputsProperty, SameInputsSameHashes, ()) {
  const Scene scene = *test::random_scene();
  const int frames = *rc::gen::inRange(1, 121);
  const std::vector<test::Drawn> drawn = *test::drawn_inputs(frames);
  std::unique_ptr<EngineRun> g1 = make_gpu_engine(scene, false, true), g2 = make_gpu_engine(scene, false, true);
  World<float> w(scene);
  std::size_t k = 0;
  try {
    for (int f = 1; f <= frames; ++f) {
      for (; k < drawn.size() && drawn[k].frame == f; ++k) {
        if (drawn[k].kind != InputKind::create && w.bodies().empty()) continue;
        const Input in = test::concrete(drawn[k], w);
        bool world_ok = true, gpu_ok = true;
        try {
          w.apply(in);
        } catch (const std::invalid_argument&) {
          world_ok = false;
        }
        try {
          g1->apply(in);
          g2->apply(in);
        } catch (const std::invalid_argument&) {
          gpu_ok = false;
        }
        RC_ASSERT(world_ok == gpu_ok);
      }
      RC_ASSERT(g1->body_count() == static_cast<int>(w.bodies().size()));
      g1->step();
      g2->step();
      w.step();
      RC_ASSERT(g1->state_hash() == g2->state_hash());
    }
  } catch (const RunError&) {
    RC_DISCARD("the run stopped (RunError)");
  }
}

}  // namespace
}  // namespace lockstep
