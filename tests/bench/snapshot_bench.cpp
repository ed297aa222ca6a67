// Google Benchmark of snapshots (issue 32, docs/SNAPSHOTS.md): saving and
// restoring the built-in pile1000 (1,000 cubes) once it has settled, on the
// fixed engine (and float, double for comparison). restore is the rollback
// case: restore_state into a world of the same scene (only the moving state
// is read); load builds a new World from the bytes alone. Counters: the
// snapshot's bytes, bytes per body, and (fixed) the moving-state bytes per
// body (flags, pose, velocities, sleep counter and frame) apart from eq 108's
// records.
//   ./build/tests/bench/snapshot_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cstdio>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/world.hpp"

namespace lockstep {
namespace {

constexpr int kSettleFrames = 600;  // pile1000 on fixed is asleep well before (docs/SNAPSHOTS.md)

template <class T>
const World<T>& settled_pile() {
  static const World<T> w = [] {
    World<T> x(*builtin_scene("pile1000"));
    for (int f = 0; f < kSettleFrames; ++f) x.step();
    return x;
  }();
  return w;
}

template <class T>
void counters(benchmark::State& state, const World<T>& w, const std::vector<std::uint8_t>& bytes) {
  const double n = static_cast<double>(w.bodies().size());
  state.counters["bytes"] = static_cast<double>(bytes.size());
  state.counters["bytes/body"] = static_cast<double>(bytes.size()) / n;
  state.counters["awake"] = w.awake_count();
}

template <class T>
void BM_Save(benchmark::State& state) {
  const World<T>& w = settled_pile<T>();
  std::vector<std::uint8_t> bytes;
  for (auto _ : state) {
    w.save_state(bytes);
    benchmark::DoNotOptimize(bytes.data());
  }
  counters(state, w, bytes);
}

template <class T>
void BM_Restore(benchmark::State& state) {
  const World<T>& settled = settled_pile<T>();
  const std::vector<std::uint8_t> bytes = settled.save_state();
  World<T> w(*builtin_scene("pile1000"));  // another frame of the same scene: the rollback case
  for (int f = 0; f < 5; ++f) w.step();
  for (auto _ : state) {
    w.restore_state(bytes);
    benchmark::DoNotOptimize(&w);
  }
  counters(state, settled, bytes);
}

template <class T>
void BM_Load(benchmark::State& state) {
  const World<T>& settled = settled_pile<T>();
  const std::vector<std::uint8_t> bytes = settled.save_state();
  for (auto _ : state) {
    World<T> w = World<T>::load_state(bytes);
    benchmark::DoNotOptimize(&w);
  }
  counters(state, settled, bytes);
}

// A rollback across a run-time creation (docs/SPEC.md 7.8): the world holds
// a crate created after the snapshot, so the scene sections differ and
// restore_state rebuilds the world as load_state does.
template <class T>
void BM_RestoreAcrossCreate(benchmark::State& state) {
  const World<T>& settled = settled_pile<T>();
  const std::vector<std::uint8_t> bytes = settled.save_state();
  World<T> w = settled;
  BodyDesc crate;
  crate.half_extents = {0.75, 0.5, 0.75};
  crate.position = {0.0, 18.0, 0.0};
  for (auto _ : state) {
    state.PauseTiming();
    w.create_body(crate);
    state.ResumeTiming();
    w.restore_state(bytes);
    benchmark::DoNotOptimize(&w);
  }
  counters(state, settled, bytes);
}

// The cost a snapshot replaces: copying the whole World (the in-process save).
template <class T>
void BM_Copy(benchmark::State& state) {
  const World<T>& settled = settled_pile<T>();
  World<T> w(*builtin_scene("pile1000"));
  for (auto _ : state) {
    w = settled;
    benchmark::DoNotOptimize(&w);
  }
}

BENCHMARK_TEMPLATE(BM_Save, Q16)->Name("save/fixed/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Restore, Q16)->Name("restore/fixed/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Load, Q16)->Name("load/fixed/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_RestoreAcrossCreate, Q16)->Name("restore_across_create/fixed/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Copy, Q16)->Name("copy_world/fixed/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Save, float)->Name("save/float/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Restore, float)->Name("restore/float/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Save, double)->Name("save/double/pile1000")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_Restore, double)->Name("restore/double/pile1000")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace lockstep

BENCHMARK_MAIN();
