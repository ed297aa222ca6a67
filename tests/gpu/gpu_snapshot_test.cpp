// The GPU engine's snapshots (docs/SNAPSHOTS.md "The GPU engine"), host
// build: a world restored from a snapshot steps, frame for frame, to the
// hashes of the world that was never interrupted, and ends with the same
// snapshot bytes; restoring into a world at another frame (rollback) and
// loading a world from the bytes alone both do; bad snapshots (truncated,
// corrupt, foreign, inconsistent behind a good checksum) are refused with a
// SnapshotError naming the field.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "../../reference/src/snapshot_bytes.hpp"
#include "../../reference/src/snapshot_scene.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "reference/random_inputs_gen.hpp"
#include "reference/random_scene_gen.hpp"

namespace lockstep::test {
namespace {

using gpu::GpuOptions;
using gpu::GpuWorld;

GpuOptions host(bool jacobi = false) {
  GpuOptions o;
  o.backend = gpu::Backend::kHost;
  o.quiet = true;
  if (jacobi) o.pair_solver = GpuOptions::PairSolver::kJacobi;
  return o;
}

// `w` saved, then resumed twice (restore_state into `other`, a world of the
// same scene at another frame, and load_state from the bytes alone): each
// steps `frames` frames to w's hashes and ends with w's snapshot bytes.
template <class World>
::testing::AssertionResult resumes(World& w, World& other, int frames) {
  const std::vector<std::uint8_t> bytes = w.save_state();
  other.restore_state(bytes.data(), bytes.size());
  std::unique_ptr<World> loaded = World::load_state(bytes.data(), bytes.size(), host());
  if (other.save_state() != bytes) return ::testing::AssertionFailure() << "restore_state then save_state: other bytes";
  if (loaded->save_state() != bytes) return ::testing::AssertionFailure() << "load_state then save_state: other bytes";
  for (int f = 0; f < frames; ++f) {
    w.step();
    other.step();
    loaded->step();
    if (other.state_hash() != w.state_hash())
      return ::testing::AssertionFailure() << "restored: hash differs at frame " << w.frame();
    if (loaded->state_hash() != w.state_hash())
      return ::testing::AssertionFailure() << "loaded: hash differs at frame " << w.frame();
  }
  const std::vector<std::uint8_t> end = w.save_state();
  if (other.save_state() != end) return ::testing::AssertionFailure() << "restored: the final snapshots differ";
  if (loaded->save_state() != end) return ::testing::AssertionFailure() << "loaded: the final snapshots differ";
  return ::testing::AssertionSuccess();
}

TEST(GpuSnapshot, BuiltinScenesResume) {
  for (const char* name : {"stack5", "pyramid", "bowl", "tip_corner", "terrain", "bounce", "drop"}) {
    const Scene scene = *builtin_scene(name);
    for (int save : {0, 1, 7, 25}) {
      GpuWorld w(scene, host());
      for (int f = 0; f < save; ++f) w.step();
      GpuWorld other(scene, host());
      for (int f = 0; f < 3; ++f) other.step();
      EXPECT_TRUE(resumes(w, other, 40)) << name << " saved at frame " << save;
    }
  }
}

// gpu-fixed (docs/GPU.md "gpu-fixed"): its snapshots (number type 6, each
// value's raw Q16.16) resume bit for bit; a gpu snapshot is refused by
// gpu-fixed and the other way round, naming the header's number type.
TEST(GpuSnapshot, FixedScenesResume) {
  for (const char* name : {"stack5", "pyramid", "bowl", "terrain"}) {
    const Scene scene = *builtin_scene(name);
    for (int save : {0, 9, 30}) {
      gpu::GpuFixedWorld w(scene, host());
      for (int f = 0; f < save; ++f) w.step();
      gpu::GpuFixedWorld other(scene, host());
      for (int f = 0; f < 3; ++f) other.step();
      EXPECT_TRUE(resumes(w, other, 40)) << name << " saved at frame " << save;
    }
  }
  const Scene scene = *builtin_scene("stack5");
  GpuWorld f(scene, host());
  gpu::GpuFixedWorld q(scene, host());
  const std::vector<std::uint8_t> fb = f.save_state(), qb = q.save_state();
  try {
    (void)gpu::GpuFixedWorld::load_state(fb.data(), fb.size(), host());
    ADD_FAILURE() << "a gpu snapshot loaded into gpu-fixed";
  } catch (const SnapshotError& e) {
    EXPECT_EQ(e.field, "header.number_type");
    EXPECT_NE(std::string(e.what()).find("the gpu engine cannot be loaded into the gpu-fixed engine"), std::string::npos) << e.what();
  }
  try {
    f.restore_state(qb.data(), qb.size());
    ADD_FAILURE() << "a gpu-fixed snapshot restored into gpu";
  } catch (const SnapshotError& e) {
    EXPECT_EQ(e.field, "header.number_type");
  }
}

TEST(GpuSnapshot, JacobiSolverAndPileResume) {
  GpuWorld w(*builtin_scene("pyramid"), host(true));
  for (int f = 0; f < 12; ++f) w.step();
  GpuWorld other(*builtin_scene("pyramid"), host(true));
  EXPECT_TRUE(resumes(w, other, 30));
  const std::vector<std::uint8_t> bytes = w.save_state();
  EXPECT_TRUE(GpuWorld::load_state(bytes.data(), bytes.size(), host())->jacobi());
  GpuWorld coloured(*builtin_scene("pyramid"), host());
  try {
    coloured.restore_state(bytes.data(), bytes.size());
    ADD_FAILURE() << "a gpu-jacobi snapshot restored into the gpu engine";
  } catch (const SnapshotError& e) {
    EXPECT_NE(std::string(e.what()).find("gpu-jacobi engine cannot be restored into the gpu engine"), std::string::npos);
  }
  Scene pile = *builtin_scene("pile1000");
  GpuWorld p(pile, host());
  for (int f = 0; f < 45; ++f) p.step();
  GpuWorld q(pile, host());
  EXPECT_TRUE(resumes(p, q, 15));
}

RC_GTEST_PROP(GpuSnapshotProperty, RandomScenesResume, ()) {
  const Scene scene = *random_scene();
  const int frames = *rc::gen::inRange(1, 201);
  const int save = *rc::gen::inRange(0, frames + 1);
  const int other_frames = *rc::gen::inRange(0, 20);
  try {
    GpuWorld w(scene, host());
    GpuWorld other(scene, host());
    for (int f = 0; f < save; ++f) w.step();
    for (int f = 0; f < other_frames; ++f) other.step();
    const auto r = resumes(w, other, frames - save);
    RC_LOG() << r.message() << "\n";
    RC_ASSERT(static_cast<bool>(r));
  } catch (const RunError&) {
    RC_DISCARD("the run stopped (RunError)");
  }
}

// The concrete input a drawn one becomes in the GPU world (names a live body).
Input concrete_gpu(const Drawn& x, const GpuWorld& w) {
  Input in;
  in.frame = x.frame;
  in.kind = x.kind;
  in.body = x.body;
  in.a = x.a;
  in.b = x.b;
  in.q = x.q;
  if (x.kind == InputKind::create) return in;
  if (w.body_count() == 0) throw std::invalid_argument("no body left");
  const int i = x.pick % w.body_count();
  in.id = w.id_of(i);
  if (x.kind == InputKind::impulse) {
    const BodySnapshot b = w.body(i);
    in.b = {b.p[0] + x.b.x, b.p[1] + x.b.y, b.p[2] + x.b.z};
  }
  return in;
}

// With run-time inputs (creations, removals, impulses, forces, poses) before
// and after the save, some in the frame saved at (pending when it is saved).
RC_GTEST_PROP(GpuSnapshotProperty, RandomInputsResume, ()) {
  const Scene scene = *random_scene();
  const int frames = *rc::gen::inRange(1, 121);
  const int save = *rc::gen::inRange(0, frames + 1);
  const std::vector<Drawn> drawn = *drawn_inputs(frames);
  try {
    GpuWorld w(scene, host());
    std::unique_ptr<GpuWorld> resumed;
    std::size_t next = 0;
    auto apply_upto = [&](GpuWorld& g, int f, std::size_t& k) {
      for (; k < drawn.size() && drawn[k].frame == f; ++k) {
        try {
          g.apply(concrete_gpu(drawn[k], g));
        } catch (const std::invalid_argument&) {  // refused (e.g. the last body removed): both sides alike
        }
      }
    };
    std::size_t next_resumed = 0;
    for (int f = 1; f <= frames; ++f) {
      if (f == save + 1) {  // the inputs of frame f are applied, then saved (pending), then resumed
        apply_upto(w, f, next);
        const std::vector<std::uint8_t> bytes = w.save_state();
        resumed = GpuWorld::load_state(bytes.data(), bytes.size(), host());
        next_resumed = next;
        RC_ASSERT(resumed->save_state() == bytes);
      } else {
        apply_upto(w, f, next);
        if (resumed) apply_upto(*resumed, f, next_resumed);
      }
      w.step();
      if (resumed) {
        resumed->step();
        RC_ASSERT(resumed->state_hash() == w.state_hash());
      }
    }
    if (resumed) RC_ASSERT(resumed->save_state() == w.save_state());
  } catch (const RunError&) {
    RC_DISCARD("the run stopped (RunError)");
  }
}

std::string refusal(const std::vector<std::uint8_t>& bytes) {
  try {
    (void)GpuWorld::load_state(bytes.data(), bytes.size(), host());
  } catch (const SnapshotError& e) {
    return std::string(e.field) + " | " + e.what();
  }
  return "accepted";
}

// The bytes with the checksum made right again (a corruption that only the
// checks behind the checksum can find).
std::vector<std::uint8_t> resealed(std::vector<std::uint8_t> b) {
  b.resize(b.size() - kSnapshotChecksumSize);
  snap::finish(b);
  return b;
}

TEST(GpuSnapshot, BadSnapshotsAreRefused) {
  GpuWorld w(*builtin_scene("pyramid"), host());
  for (int f = 0; f < 20; ++f) w.step();
  const std::vector<std::uint8_t> good = w.save_state();
  EXPECT_EQ(refusal(good), "accepted");
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_NE(refusal(std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<long>(n))), "accepted") << n;
  for (std::size_t i = 0; i < good.size(); i += 7) {
    std::vector<std::uint8_t> b = good;
    b[i] ^= 0x10;
    EXPECT_NE(refusal(b), "accepted") << "byte " << i;
  }
  // Behind a good checksum: every byte of the engine's part changed, resealed:
  // refused or loaded, never undefined behaviour (ASan and UBSan in CI).
  const std::size_t engine_part = kSnapshotHeaderSize + snap::encode_scene_section(*builtin_scene("pyramid")).size();
  int refused = 0;
  for (std::size_t i = engine_part; i + kSnapshotChecksumSize < good.size(); ++i) {
    std::vector<std::uint8_t> b = good;
    b[i] ^= 0xff;
    refused += refusal(resealed(b)) != "accepted" ? 1 : 0;
  }
  EXPECT_GT(refused, 0);
  // A snapshot of another engine, and the GPU engine's into World<float>.
  World<float> f(*builtin_scene("pyramid"));
  const std::vector<std::uint8_t> cpu = f.save_state();
  EXPECT_NE(refusal(cpu).find("a snapshot of the float engine cannot be loaded into the gpu engine"), std::string::npos);
  try {
    (void)World<float>::load_state(good);
    ADD_FAILURE() << "a gpu snapshot loaded into World<float>";
  } catch (const SnapshotError& e) {
    EXPECT_NE(std::string(e.what()).find("a snapshot of the gpu engine cannot be loaded into the float engine"), std::string::npos);
  }
  // The awake list naming a body twice (the first awake body's entry).
  std::vector<std::uint8_t> b = good;
  b.push_back(0);  // trailing bytes
  EXPECT_NE(refusal(resealed(b)).find("bytes after the counters"), std::string::npos);
  EXPECT_NE(refusal(std::vector<std::uint8_t>(good.begin(), good.end() - 1)), "accepted");
}

}  // namespace
}  // namespace lockstep::test
