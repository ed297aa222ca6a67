// Google Benchmark of the Level 1 engine (issue 3): time per step for 1,000
// and 10,000 cubes for each number type, and the cost of each effect switched
// on alone. Each iteration restores a pre-simulated snapshot (untimed) and
// times 10 steps of a pile that is still colliding: CPU time / 10 is the
// time per step; body-steps/s is bodies x steps per CPU second.
#include <benchmark/benchmark.h>

#include <string>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/math/num_mp.hpp"
#include "lockstep/world.hpp"

namespace lockstep {
namespace {

// N unit cubes in columns 0.2 m apart (the boxfall layout of ANCHORS.md), 8 high.
Scene boxfall(int n, const Effects& fx) {
  Scene s;
  s.effects = fx;
  const int per_layer = (n + 7) / 8;
  int side = 1;
  while (side * side < per_layer) ++side;
  for (int i = 0; i < n; ++i) {
    const int layer = i / per_layer, k = i % per_layer;
    BodyDesc b;
    b.position = {1.2 * (k % side), 0.6 + 1.2 * layer, 1.2 * (k / side)};
    b.orientation = {1.0, 0.01 * (i % 7), 0.0, 0.01 * (i % 5)};
    s.bodies.push_back(b);
  }
  return s;
}

constexpr int kStepsPerIteration = 10;
constexpr int kWarmFrames = 40;  // the lowest layers have landed, the rest are falling onto them

template <class T>
void step_pile(benchmark::State& state, const Effects& fx) {
  const int n = static_cast<int>(state.range(0));
  World<T> snapshot(boxfall(n, fx));
  for (int f = 0; f < kWarmFrames; ++f) snapshot.step();
  World<T> w = snapshot;
  for (auto _ : state) {
    state.PauseTiming();
    w = snapshot;
    state.ResumeTiming();
    for (int s = 0; s < kStepsPerIteration; ++s) w.step();
  }
  state.counters["body-steps/s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kStepsPerIteration * n,
                                                      benchmark::Counter::kIsRate);
}

template <class T>
void BM_StepAllEffects(benchmark::State& state) { step_pile<T>(state, Effects{}); }

BENCHMARK_TEMPLATE(BM_StepAllEffects, Q16)->Name("step/fixed")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_StepAllEffects, float)->Name("step/float")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_StepAllEffects, double)->Name("step/double")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_StepAllEffects, Mp)->Name("step/mp")->Arg(1000)->Iterations(2)->Unit(benchmark::kMillisecond);

// Each effect switched on alone (all others off), fixed engine, 1,000 cubes;
// "none" is integration only, "all" every effect. Friction, restitution and
// settling act only through contacts, so alone they must cost nothing.
Effects only(bool Effects::*flag) {
  Effects fx{false, false, false, false, false, false, false, false, false};
  if (flag != nullptr) fx.*flag = true;
  return fx;
}

void register_effect_benchmarks() {
  const std::pair<const char*, bool Effects::*> effects[] = {
      {"none", nullptr}, {"gravity", &Effects::gravity}, {"damping", &Effects::damping}, {"ground", &Effects::ground},
      {"contacts", &Effects::contacts}, {"friction", &Effects::friction}, {"restitution", &Effects::restitution},
      {"settling", &Effects::settling}, {"sleep", &Effects::sleep}};
  for (const auto& [name, flag] : effects) {
    const Effects fx = only(flag);
    benchmark::RegisterBenchmark((std::string("effect_alone/") + name).c_str(),
                                 [fx](benchmark::State& st) { step_pile<Q16>(st, fx); })
        ->Arg(1000)->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("effect_alone/all", [](benchmark::State& st) { step_pile<Q16>(st, Effects{}); })
      ->Arg(1000)->Unit(benchmark::kMillisecond);
}
const bool registered = (register_effect_benchmarks(), true);

}  // namespace
}  // namespace lockstep

BENCHMARK_MAIN();
