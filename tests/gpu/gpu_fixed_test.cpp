// gpu-fixed, the GPU engine's pipeline on Q16.16 (docs/GPU.md "gpu-fixed"),
// host build: World<Q16>'s bits on every frame, so the hand-off vectors'
// hashes (vectors/data/scenes), and World<Q16>'s stop on an overflow.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "reference/random_scene_gen.hpp"
#include "scene_helpers.hpp"

namespace lockstep {
namespace {

using gpu::GpuFixedWorld;
using gpu_test::host_options;
using gpu_test::scene;

// The per-frame hashes of a scene's vector file (vectors/data/scenes,
// vectors/README.md level 3): hashes[f] after frame f, hashes[0] the loaded
// scene. Read with a plain scan: the array of 16-digit hex strings after "hashes".
std::vector<std::uint64_t> vector_hashes(const std::string& name) {
  std::ifstream in(std::string(LOCKSTEP_VECTORS_DIR) + "/scenes/" + name + ".json");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  std::vector<std::uint64_t> out;
  std::size_t at = doc.find("\"hashes\"");
  if (at == std::string::npos) return out;
  const std::size_t end = doc.find(']', at);
  for (at = doc.find('"', doc.find('[', at)); at < end; at = doc.find('"', at + 18)) {
    out.push_back(std::stoull(doc.substr(at + 1, 16), nullptr, 16));
  }
  return out;
}

// gpu-fixed and World<Q16> side by side: the same hash after every frame.
void expect_world_fixed_bits(const Scene& s, int frames) {
  GpuFixedWorld g(s, host_options());
  World<Q16> w(s);
  ASSERT_EQ(g.state_hash(), w.state_hash()) << "the loaded scene";
  for (int f = 1; f <= frames; ++f) {
    g.step();
    w.step();
    if (g.state_hash() != w.state_hash()) {
      ADD_FAILURE() << s.name << ": state hash differs from World<Q16>'s at frame " << f;
      return;
    }
  }
  const StageCounters a = g.counters(), b = w.counters();
  EXPECT_EQ(a.solver_contacts, b.solver_contacts);
  EXPECT_EQ(a.normal_impulses, b.normal_impulses);
  EXPECT_EQ(a.friction_steps, b.friction_steps);
  EXPECT_EQ(a.wakes, b.wakes);
}

// Every built-in scene as the vectors hold it (the oriented-box model), every
// frame: the vector file's hash, the one World<Q16> (and every certified
// build of it) gives.
TEST(GpuFixed, EveryBuiltinSceneGivesTheVectorHashes) {
  for (const std::string& name : builtin_scene_names()) {
    SCOPED_TRACE(name);
    const Scene s = *builtin_scene(name);
    const std::vector<std::uint64_t> want = vector_hashes(name);
    ASSERT_EQ(want.size(), static_cast<std::size_t>(s.frames) + 1) << "vectors/data/scenes/" << name << ".json";
    GpuFixedWorld g(s, host_options());
    ASSERT_EQ(g.state_hash(), want[0]) << "the loaded scene";
    for (int f = 1; f <= s.frames; ++f) {
      g.step();
      if (g.state_hash() != want[static_cast<std::size_t>(f)]) {
        ADD_FAILURE() << name << ": frame " << f << " differs from the vector file's hash";
        break;
      }
    }
  }
}

// Both pair models against World<Q16> itself, counters included (pile1000
// once, as the float engine's test).
TEST(GpuFixed, EveryBuiltinSceneMatchesWorldQ16BitForBit) {
  for (const PairModel model : gpu_test::kBothModels)
    for (const std::string& name : builtin_scene_names()) {
      if (name == "pile1000") continue;  // the vector test above runs it
      SCOPED_TRACE(name + " " + gpu_test::model_name(model));
      const Scene s = scene(name, model);
      expect_world_fixed_bits(s, s.frames);
    }
}

// The Jacobi pair solver and the threads' work order are schedules of the
// same pipeline on Q16 too: run-to-run deterministic, and the work order
// changes no bit.
TEST(GpuFixed, WorkOrderDoesNotChangeResults) {
  const Scene s = scene("pyramid", PairModel::kOrientedBox);
  gpu::GpuOptions ordered = host_options();
  ordered.work_order_min = 1;
  GpuFixedWorld a(s, host_options()), b(s, ordered);
  for (int f = 1; f <= 200; ++f) {
    a.step();
    b.step();
    ASSERT_EQ(a.state_hash(), b.state_hash()) << "frame " << f;
  }
}

// Random perturbed scenes (tests/reference/random_scene_gen.hpp, the float
// engine's property): every frame World<Q16>'s hash; where World<Q16> stops
// (a Q16 fault), gpu-fixed stops at the same frame with the same quantity.
RC_GTEST_PROP(GpuFixedProp, RandomScenesMatchWorldQ16BitForBit, ()) {
  Scene s = *test::random_scene();
  s.frames = 240;
  GpuFixedWorld g(s, host_options());
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
}

// A Q16.16 overflow stops the run as World<Q16> does (World<T>::check_faults):
// a RunError with the frame, the body and the quantity.
struct Stop {
  int frame = -1, body = -1;
  std::string quantity, what;
};
template <class World>
Stop run_to_stop(World& w, int frames) {
  for (int f = 0; f < frames; ++f) {
    try {
      w.step();
    } catch (const RunError& e) {
      return {e.frame, e.body, e.quantity, e.what()};
    }
  }
  return {};
}

TEST(GpuFixed, OverflowStopsWithFrameBodyAndQuantity) {
  // One cube driven into the ground at 30000 m/s: its impulse overflows.
  Scene s = scene("drop", PairModel::kOrientedBox);
  s.bodies[0].velocity = {0.0, -30000.0, 0.0};
  GpuFixedWorld g(s, host_options());
  World<Q16> w(s);
  const Stop gs = run_to_stop(g, 50), ws = run_to_stop(w, 50);
  ASSERT_GE(ws.frame, 1) << "World<Q16> overflows";
  EXPECT_EQ(gs.frame, ws.frame) << gs.what << " | " << ws.what;
  EXPECT_EQ(gs.body, ws.body) << gs.what << " | " << ws.what;
  EXPECT_EQ(gs.quantity, ws.quantity) << gs.what << " | " << ws.what;
  EXPECT_NE(gs.what.find("overflow"), std::string::npos) << gs.what;
}

TEST(GpuFixed, OverflowInAPileNamesFrameBodyAndQuantity) {
  // tests/reference/threads_test.cpp's case: a whole layer of pile1000
  // driven into the one below; World<Q16> stops in the solver.
  Scene s = scene("pile1000", PairModel::kOrientedBox);
  for (std::size_t i = 500; i < 600; ++i) s.bodies[i].velocity = {0.0, -30000.0, 0.0};
  GpuFixedWorld g(s, host_options());
  World<Q16> w(s);
  const Stop gs = run_to_stop(g, 200), ws = run_to_stop(w, 200);
  ASSERT_GE(ws.frame, 1);
  EXPECT_EQ(gs.frame, ws.frame) << gs.what << " | " << ws.what;
  EXPECT_EQ(gs.quantity, ws.quantity) << gs.what << " | " << ws.what;
  // World<Q16> names the first contact in its visiting order (eqs 125-127:
  // within a colour, edge key order), gpu-fixed the lowest index among the
  // bodies whose contacts overflowed in that stage (docs/GPU.md
  // "gpu-fixed"): here the lower side of an edge between the driven layer
  // (500-599) and the one below (400-499), as World's is.
  EXPECT_GE(gs.body, 400) << gs.what;
  EXPECT_LT(gs.body, 500) << gs.what;
  EXPECT_GE(ws.body, 400) << ws.what;
  EXPECT_LE(gs.body, ws.body) << gs.what << " | " << ws.what;
}

}  // namespace
}  // namespace lockstep
