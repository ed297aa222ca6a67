#include "snapshot_fuzz_one.hpp"

#include <string>
#include <utility>

#include "../../reference/src/snapshot_bytes.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "lockstep/math/num_mp.hpp"
#include "lockstep/snapshot.hpp"
#include "lockstep/world.hpp"

namespace lockstep::fuzz {

namespace {

// Loads as T; checks the save/load round trip; steps the fixed engine.
template <class T>
Outcome load_as(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> once;
  bool small = false;
  try {
    const World<T> w = World<T>::load_state(data, size);
    once = w.save_state();
    small = w.bodies().size() <= kMaxFuzzBodies;
  } catch (const SnapshotError& e) {
    if (std::string(e.what()).size() <= 10) throw FuzzFinding("SnapshotError with an empty message");
    return Outcome::kRejected;
  }
  std::vector<std::uint8_t> twice;
  try {
    twice = World<T>::load_state(once).save_state();
  } catch (const SnapshotError& e) {
    throw FuzzFinding(std::string("load_state refused what save_state wrote: ") + e.what());
  }
  if (twice != once) throw FuzzFinding("save(load(save(load(x)))) differs from save(load(x))");
  if constexpr (!std::is_same_v<T, Q16>) {
    return Outcome::kLoaded;
  } else {
    if (!small) return Outcome::kLoaded;
    try {
      World<T> w = World<T>::load_state(once);
      for (int f = 0; f < kMaxSnapshotFuzzFrames; ++f) w.step();
      return Outcome::kRan;
    } catch (const RunError&) {
      return Outcome::kStopped;
    }
  }
}

// The GPU engine's loader (GpuWorld::load_state, host build): the same contract.
Outcome load_gpu(const std::uint8_t* data, std::size_t size) {
  gpu::GpuOptions o;
  o.backend = gpu::Backend::kHost;
  o.quiet = true;
  std::vector<std::uint8_t> once;
  bool small = false;
  try {
    const std::unique_ptr<gpu::GpuWorld> w = gpu::GpuWorld::load_state(data, size, o);
    once = w->save_state();
    small = w->body_count() <= static_cast<int>(kMaxFuzzBodies);
  } catch (const SnapshotError& e) {
    if (std::string(e.what()).size() <= 10) throw FuzzFinding("SnapshotError with an empty message");
    return Outcome::kRejected;
  }
  std::vector<std::uint8_t> twice;
  try {
    twice = gpu::GpuWorld::load_state(once.data(), once.size(), o)->save_state();
  } catch (const SnapshotError& e) {
    throw FuzzFinding(std::string("gpu: load_state refused what save_state wrote: ") + e.what());
  }
  if (twice != once) throw FuzzFinding("gpu: save(load(save(load(x)))) differs from save(load(x))");
  if (!small) return Outcome::kLoaded;
  try {
    const std::unique_ptr<gpu::GpuWorld> w = gpu::GpuWorld::load_state(once.data(), once.size(), o);
    for (int f = 0; f < kMaxSnapshotFuzzFrames; ++f) w->step();
    return Outcome::kRan;
  } catch (const RunError&) {
    return Outcome::kStopped;
  }
}

Outcome load_any(const std::uint8_t* data, std::size_t size) {
  const std::uint8_t number = size > 10 ? data[10] : 0;
  switch (number) {
    case 5: return load_gpu(data, size);
    case 2: return load_as<float>(data, size);
    case 3: return load_as<double>(data, size);
    case 4: return load_as<Mp>(data, size);
    default: return load_as<Q16>(data, size);
  }
}

}  // namespace

Outcome fuzz_one_snapshot(const std::uint8_t* data, std::size_t size) {
  const Outcome raw = load_any(data, size);
  if (size < kSnapshotHeaderSize + kSnapshotChecksumSize) return raw;
  std::vector<std::uint8_t> sealed(data, data + size);
  for (int i = 0; i < 8; ++i) sealed[24 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(std::uint64_t{size} >> (8 * i));
  const std::uint64_t sum = snap::checksum(sealed.data(), size - kSnapshotChecksumSize);
  for (int i = 0; i < 8; ++i) sealed[size - 8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(sum >> (8 * i));
  const Outcome resealed = load_any(sealed.data(), sealed.size());
  return raw != Outcome::kRejected ? raw : resealed;
}

std::vector<std::pair<std::string, std::vector<std::uint8_t>>> snapshot_seeds() {
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> out;
  auto add = [&](const std::string& name, const std::vector<std::uint8_t>& bytes) { out.emplace_back(name, bytes); };
  auto run = [](auto world, int frames) {
    for (int f = 0; f < frames; ++f) world.step();
    return world.save_state();
  };
  add("fixed_drop_0", run(World<Q16>(*builtin_scene("drop")), 0));
  add("fixed_drop_40", run(World<Q16>(*builtin_scene("drop")), 40));
  add("fixed_stack5_300", run(World<Q16>(*builtin_scene("stack5")), 300));
  add("fixed_tip_corner_60", run(World<Q16>(*builtin_scene("tip_corner")), 60));
  add("fixed_pyramid_80", run(World<Q16>(*builtin_scene("pyramid")), 80));
  add("float_stack5_60", run(World<float>(*builtin_scene("stack5")), 60));
  add("double_stack5_60", run(World<double>(*builtin_scene("stack5")), 60));
  add("mp_drop_5", run(World<Mp>(*builtin_scene("drop")), 5));
  // Run-time inputs (docs/SPEC.md "Run-time inputs"): a removed body (an id
  // table with a free slot), a created one (a second shape) and a force
  // pending for the next step.
  World<Q16> inputs(*builtin_scene("stack5"));
  for (int f = 0; f < 30; ++f) inputs.step();
  inputs.destroy_body(inputs.id_of(1));
  BodyDesc crate;
  crate.half_extents = {0.75, 0.5, 0.25};
  crate.position = {0.0, 8.0, 0.0};
  inputs.create_body(crate);
  inputs.add_force(inputs.id_of(2), {10.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  add("fixed_stack5_inputs_30", inputs.save_state());
  gpu::GpuOptions o;
  o.backend = gpu::Backend::kHost;
  o.quiet = true;
  auto run_gpu = [&o](const char* scene, int frames, bool jacobi) {
    if (jacobi) o.pair_solver = gpu::GpuOptions::PairSolver::kJacobi;
    gpu::GpuWorld w(*builtin_scene(scene), o);
    for (int f = 0; f < frames; ++f) w.step();
    return w.save_state();
  };
  add("gpu_pyramid_20", run_gpu("pyramid", 20, false));
  add("gpu_stack5_6", run_gpu("stack5", 6, false));
  add("gpu_jacobi_tip_corner_30", run_gpu("tip_corner", 30, true));
  return out;
}

}  // namespace lockstep::fuzz
