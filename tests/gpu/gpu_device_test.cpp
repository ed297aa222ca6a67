// The GPU engine on a CUDA device (label gpu; skipped, with a message, where
// there is none): the device build gives the host build's bits, run to run
// and scene by scene, and the kernels' formulas give the host's results.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <rapidcheck.h>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/gpu/formula_cases.hpp"
#include "reference/random_scene_gen.hpp"
#include "scene_helpers.hpp"

namespace lockstep {
namespace {

using gpu::GpuWorld;

#define LOCKSTEP_REQUIRE_DEVICE()                                  \
  do {                                                             \
    if (!gpu::cuda_device_available()) GTEST_SKIP() << "no CUDA device"; \
  } while (false)

gpu::GpuOptions device_options() {
  gpu::GpuOptions o;
  o.backend = gpu::Backend::kDevice;
  return o;
}

TEST(GpuDevice, RunsOnTheDevice) {
  LOCKSTEP_REQUIRE_DEVICE();
  GpuWorld g(gpu_test::scene("drop"), device_options());
  EXPECT_TRUE(g.on_device());
  EXPECT_EQ(g.description().rfind("gpu: CUDA on ", 0), 0u) << g.description();
}

// Built with --fmad=false, the device rounds every operation as the host
// build does, and the schedule is the same: identical bits every frame, on
// both pair models.
TEST(GpuDevice, MatchesHostBuildBitForBit) {
  LOCKSTEP_REQUIRE_DEVICE();
  for (const PairModel model : gpu_test::kBothModels)
  for (const auto& [name, frames] : {std::pair<const char*, int>{"drop", 300}, {"stack5", 300}, {"pyramid", 300},
                                     {"pile1000", 300}, {"bowl", 400}, {"terrain", 400}}) {
    SCOPED_TRACE(std::string(name) + " " + gpu_test::model_name(model));
    const Scene s = gpu_test::scene(name, model);
    GpuWorld d(s, device_options()), h(s, gpu_test::host_options());
    for (int f = 1; f <= frames; ++f) {
      d.step();
      h.step();
      ASSERT_EQ(d.state_hash(), h.state_hash()) << "frame " << f;
    }
    const StageCounters a = d.counters(), b = h.counters();
    EXPECT_EQ(a.pairs_tested, b.pairs_tested);
    EXPECT_EQ(a.body_contacts, b.body_contacts);
    EXPECT_EQ(a.solver_contacts, b.solver_contacts);
    EXPECT_EQ(a.normal_impulses, b.normal_impulses);
    EXPECT_EQ(a.wakes, b.wakes);
    EXPECT_EQ(a.sleep_updates, b.sleep_updates);
  }
}

// gpu-fixed (docs/GPU.md "gpu-fixed") on the device: Q16.16 is integer
// arithmetic, so the device gives the host build's bits, which are
// World<Q16>'s, every frame, both pair models; and a Q16 overflow stops the
// run as on the host (the device's fault flags: each thread's status word
// in block-shared memory, the frame's lowest fault by atomicMin).
TEST(GpuDevice, FixedMatchesHostBuildBitForBit) {
  LOCKSTEP_REQUIRE_DEVICE();
  for (const PairModel model : gpu_test::kBothModels)
  for (const auto& [name, frames] : {std::pair<const char*, int>{"drop", 300}, {"stack5", 300}, {"pyramid", 300},
                                     {"pile1000", 300}, {"bowl", 400}, {"terrain", 400}}) {
    SCOPED_TRACE(std::string(name) + " " + gpu_test::model_name(model));
    const Scene s = gpu_test::scene(name, model);
    gpu::GpuFixedWorld d(s, device_options()), h(s, gpu_test::host_options());
    ASSERT_TRUE(d.on_device());
    for (int f = 1; f <= frames; ++f) {
      d.step();
      h.step();
      ASSERT_EQ(d.state_hash(), h.state_hash()) << "frame " << f;
    }
    const StageCounters a = d.counters(), b = h.counters();
    EXPECT_EQ(a.solver_contacts, b.solver_contacts);
    EXPECT_EQ(a.normal_impulses, b.normal_impulses);
    EXPECT_EQ(a.wakes, b.wakes);
  }
  Scene s = gpu_test::scene("pile1000", PairModel::kOrientedBox);
  for (std::size_t i = 500; i < 600; ++i) s.bodies[i].velocity = {0.0, -30000.0, 0.0};
  auto stop = [&](const gpu::GpuOptions& o) {
    gpu::GpuFixedWorld w(s, o);
    for (int f = 0; f < 50; ++f) {
      try {
        w.step();
      } catch (const RunError& e) {
        return std::string(e.what());
      }
    }
    return std::string("no stop");
  };
  const std::string on_device = stop(device_options());
  EXPECT_NE(on_device.find("contact impulse"), std::string::npos) << on_device;
  EXPECT_EQ(on_device, stop(gpu_test::host_options()));
}

// Issue 33's proof on the device: random perturbed scenes (the host
// properties' generator, tests/reference/random_scene_gen.hpp: 1-6 boxes,
// ground, slab or SDF bowl, either pair model, effects now and then off), 240
// frames each, through CUDA: gpu-fixed gives World<Q16>'s hash every frame
// (and where World<Q16> stops on a Q16 fault, the same frame and quantity),
// and gpu World<float>'s. RapidCheck's cases (100, or RC_PARAMS).
TEST(GpuDevice, FixedRandomScenesMatchWorldQ16BitForBit) {
  LOCKSTEP_REQUIRE_DEVICE();
  EXPECT_TRUE(rc::check("gpu-fixed on the device: World<Q16>'s hash every frame", [] {
    Scene s = *test::random_scene();
    s.frames = 240;
    gpu::GpuFixedWorld g(s, device_options());
    RC_ASSERT(g.on_device());
    World<Q16> w(s);
    for (int f = 1; f <= s.frames; ++f) {
      std::string gpu_stop, world_stop;
      try {
        g.step();
      } catch (const RunError& e) {
        gpu_stop = std::to_string(e.frame) + " " + e.quantity;
      }
      try {
        w.step();
      } catch (const RunError& e) {
        world_stop = std::to_string(e.frame) + " " + e.quantity;
      }
      RC_ASSERT(gpu_stop == world_stop);
      if (!world_stop.empty()) return;
      if (g.state_hash() != w.state_hash()) RC_FAIL("frame " + std::to_string(f) + " differs from World<Q16>'s");
    }
  }));
}
TEST(GpuDevice, FloatRandomScenesMatchWorldFloatBitForBit) {
  LOCKSTEP_REQUIRE_DEVICE();
  EXPECT_TRUE(rc::check("gpu on the device: World<float>'s hash every frame", [] {
    Scene s = *test::random_scene();
    s.frames = 240;
    GpuWorld g(s, device_options());
    RC_ASSERT(g.on_device());
    World<float> w(s);
    for (int f = 1; f <= s.frames; ++f) {
      g.step();
      w.step();
      if (g.state_hash() != w.state_hash()) RC_FAIL("frame " + std::to_string(f) + " differs from World<float>'s");
    }
  }));
}

// Run-time inputs (docs/GPU.md "Run-time inputs") on the device: the full
// download (sleep counters, eq 108's supporters), the edits and the rebuilt
// pipeline give the host build's bits, frame after frame, on pile1000 with an
// impulse, a removal while it falls and one once it sleeps, a crate, a force,
// a pose and a velocity.
TEST(GpuDevice, InputsMatchHostBuildBitForBit) {
  LOCKSTEP_REQUIRE_DEVICE();
  for (const PairModel model : gpu_test::kBothModels) {
    SCOPED_TRACE(gpu_test::model_name(model));
    const Scene s = gpu_test::scene("pile1000", model);
    GpuWorld d(s, device_options()), h(s, gpu_test::host_options());
    auto input = [](int frame, InputKind kind, std::uint32_t slot) {
      Input in;
      in.frame = frame;
      in.kind = kind;
      in.id = BodyId{slot, 0};
      return in;
    };
    std::vector<Input> inputs;
    Input kick = input(10, InputKind::impulse, 905);
    kick.a = {4, 6, 0};
    kick.b = {0.3, 13.0, 0.2};
    inputs.push_back(kick);
    inputs.push_back(input(30, InputKind::destroy, 455));
    Input crate = input(40, InputKind::create, 0);
    crate.body.half_extents = {0.75, 0.5, 0.75};
    crate.body.mass = 4.0;
    crate.body.position = {0, 18, 0};
    inputs.push_back(crate);
    Input push = input(50, InputKind::force, 990);
    push.a = {0, 0, 600};
    inputs.push_back(push);
    Input pose = input(60, InputKind::set_pose, 999);
    pose.a = {3, 20, 3};
    pose.q = {0.9, 0.1, 0.2, 0.3};
    inputs.push_back(pose);
    Input velocity = input(70, InputKind::set_velocity, 998);
    velocity.a = {0, 5, 0};
    inputs.push_back(velocity);
    inputs.push_back(input(400, InputKind::destroy, 5));  // the pile asleep: its sleepers' records
    std::size_t k = 0;
    for (int f = 1; f <= 460; ++f) {
      for (; k < inputs.size() && inputs[k].frame == f; ++k) {
        d.apply(inputs[k]);
        h.apply(inputs[k]);
      }
      d.step();
      h.step();
      ASSERT_EQ(d.state_hash(), h.state_hash()) << "frame " << f;
    }
    EXPECT_EQ(d.counters().wakes, h.counters().wakes);
    EXPECT_EQ(d.body_count(), 999);
  }
}

// The device's solver with its threads in work order (a CUB radix sort of
// the slots) gives the host build's bits in slot order.
TEST(GpuDevice, WorkOrderMatchesHostBuild) {
  LOCKSTEP_REQUIRE_DEVICE();
  for (const PairModel model : gpu_test::kBothModels)
  for (const auto& [name, frames] : {std::pair<const char*, int>{"pile1000", 200}, {"bowl", 200}}) {
    SCOPED_TRACE(std::string(name) + " " + gpu_test::model_name(model));
    const Scene s = gpu_test::scene(name, model);
    gpu::GpuOptions ordered = device_options(), unordered = gpu_test::host_options();
    ordered.work_order_min = 1;
    unordered.work_order_min = 1 << 30;
    GpuWorld d(s, ordered), h(s, unordered);
    for (int f = 1; f <= frames; ++f) {
      d.step();
      h.step();
      ASSERT_EQ(d.state_hash(), h.state_hash()) << "frame " << f;
    }
    EXPECT_EQ(d.counters().normal_impulses, h.counters().normal_impulses);
  }
}

// Two runs on the same GPU give identical bits (no float atomics; integer
// atomics only where their order cannot matter).
TEST(GpuDevice, RunToRunDeterministic) {
  LOCKSTEP_REQUIRE_DEVICE();
  for (const PairModel model : gpu_test::kBothModels) {
    SCOPED_TRACE(gpu_test::model_name(model));
    Scene s = gpu_test::settling_pile(50000, 10, false);
    s.pair_contacts = model;
    GpuWorld a(s, device_options()), b(s, device_options());
    for (int f = 1; f <= 240; ++f) {
      a.step();
      b.step();
      if (f % 40 == 0) {
        ASSERT_EQ(a.state_hash(), b.state_hash()) << "frame " << f;
      }
    }
    EXPECT_EQ(a.counters().normal_impulses, b.counters().normal_impulses);
  }
}

// Snapshots on the device (docs/SNAPSHOTS.md "The GPU engine"): a device
// world saved mid-run and resumed (load_state on the device, restore_state
// into a device world at another frame, load_state on the host build) steps
// to the uninterrupted device world's hashes, which are the host build's;
// the bytes saved on the device are the host build's bytes.
TEST(GpuDevice, SnapshotsResumeOnTheDevice) {
  LOCKSTEP_REQUIRE_DEVICE();
  gpu::GpuOptions host;
  host.backend = gpu::Backend::kHost;
  for (const PairModel model : gpu_test::kBothModels) {
    SCOPED_TRACE(gpu_test::model_name(model));
    Scene s = gpu_test::settling_pile(4000, 10, false);
    s.pair_contacts = model;
    GpuWorld a(s, device_options()), h(s, host), other(s, device_options());
    for (int f = 0; f < 30; ++f) { a.step(); h.step(); }
    for (int f = 0; f < 7; ++f) other.step();
    const std::vector<std::uint8_t> bytes = a.save_state();
    ASSERT_EQ(bytes, h.save_state()) << "device and host build save the same bytes";
    auto loaded = GpuWorld::load_state(bytes.data(), bytes.size(), device_options());
    auto on_host = GpuWorld::load_state(bytes.data(), bytes.size(), host);
    other.restore_state(bytes.data(), bytes.size());
    for (int f = 31; f <= 90; ++f) {
      a.step();
      loaded->step();
      on_host->step();
      other.step();
      ASSERT_EQ(loaded->state_hash(), a.state_hash()) << "frame " << f;
      ASSERT_EQ(other.state_hash(), a.state_hash()) << "frame " << f;
      ASSERT_EQ(on_host->state_hash(), a.state_hash()) << "frame " << f;
    }
    EXPECT_EQ(loaded->save_state(), a.save_state());
  }
}

// Formula cases: the per-equation functions the kernels call, on random
// inputs, on the device against the host build: 0 ulps apart (IEEE + - * /
// and sqrt are correctly rounded on both, and --fmad=false forbids
// contraction).
constexpr std::int64_t kMaxUlps = 0;

std::int64_t ulps(float a, float b) {
  if (std::isnan(a) && std::isnan(b)) return 0;
  if (a == b) return 0;
  auto ordered = [](float x) {
    std::int32_t i;
    std::memcpy(&i, &x, sizeof i);
    return i < 0 ? static_cast<std::int64_t>(INT32_MIN) - i : static_cast<std::int64_t>(i);
  };
  return std::llabs(ordered(a) - ordered(b));
}

std::vector<float> random_cases(int kind, int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-2.0f, 2.0f), pos(0.05f, 1.5f), unit(0.0f, 1.0f);
  std::vector<float> in(static_cast<std::size_t>(n) * gpu::kFormulaInputs);
  for (int k = 0; k < n; ++k) {
    float* c = in.data() + static_cast<std::size_t>(k) * gpu::kFormulaInputs;
    for (int j = 0; j < gpu::kFormulaInputs; ++j) c[j] = u(rng);
    switch (kind) {
      case gpu::kFormulaPair: for (int j : {3, 4, 5, 9, 10, 11}) c[j] = pos(rng); break;
      case gpu::kFormulaSolve: c[29] = unit(rng); c[30] = unit(rng); c[31] = 0.06f * unit(rng) - 0.01f; break;
      case gpu::kFormulaGround: for (int j : {7, 8, 9}) c[j] = pos(rng); break;
      case gpu::kFormulaSleep: c[0] *= 0.05f; c[3] *= 0.05f; c[10] = std::floor(40.0f * unit(rng)); break;
      case gpu::kFormulaSdf: c[0] = unit(rng); c[1] = 2.0f * unit(rng); c[2] = unit(rng); break;
      default: break;
    }
  }
  return in;
}

TEST(GpuDevice, FormulaCasesMatchHostWithinUlps) {
  LOCKSTEP_REQUIRE_DEVICE();
  std::mt19937 rng(20261121u);
  for (int kind = 0; kind < gpu::kFormulaKinds; ++kind) {
    SCOPED_TRACE(gpu::formula_kind_name(kind));
    const std::vector<float> in = random_cases(kind, 20000, rng);
    const std::vector<float> host = gpu::evaluate_formula_cases_on_host(kind, in);
    const std::vector<float> dev = gpu::evaluate_formula_cases_on_device(kind, in);
    ASSERT_EQ(host.size(), dev.size());
    std::int64_t worst = 0;
    for (std::size_t k = 0; k < host.size(); ++k) worst = std::max(worst, ulps(host[k], dev[k]));
    EXPECT_LE(worst, kMaxUlps);
  }
}

}  // namespace
}  // namespace lockstep
