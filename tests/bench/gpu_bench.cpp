// gpu_bench: the GPU engine's time per step on the settling pile (docs/GPU.md
// "Performance"), awake and asleep, with the per-stage breakdown (CUDA events
// on the device), the device's copy bandwidth, and the fixed and double CPU
// engines on the same scenes. Prints a table and writes JSON (--json F).
//
//   gpu_bench [--sizes 10000,100000,1000000,10000000] [--cpu-sizes 10000]
//             [--sleep-size 1000000] [--sleep-frames 1500] [--backend auto|host]
//             [--json out.json] [--profile N] [--solver coloured|jacobi]
//             [--model aabb|oriented_box] [--number float|fixed|both]
// --solver: GpuOptions::pair_solver of the GPU runs (default coloured).
// --number: the GPU engine's number type: float ("gpu", the default), fixed
// ("gpu-fixed", the pipeline on Q16.16: World<Q16>'s bits, docs/GPU.md
// "gpu-fixed") or both (each size on both, float first).
// --model: the pile's "pair_contacts" (default oriented_box, the engines'
// default; aabb is the source's model of docs/GPU.md's earlier tables).
// --profile N: only runs the awake pile of N cubes for 41 frames and
// captures frame 41 for `ncu --profile-from-start off` (docs/GPU.md); with
// --number fixed, gpu-fixed's.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lockstep/gpu/gpu_engine.hpp"
#include "scene_helpers.hpp"

namespace {

using lockstep::Scene;
using lockstep::gpu::GpuWorld;
using Clock = std::chrono::steady_clock;

constexpr int kColumn = 4;        // cubes per column of the pile
constexpr double kJitter = 0.01;  // turn of each cube (about radians per axis)
constexpr int kWarmFrames = 40;   // frames before timing: the columns have landed and are toppling
constexpr int kTimedFrames = 20;  // frames timed by wall clock, then as many with stage timing

// The GPU runs' options (--backend, --solver) and the pile's pair model (--model).
lockstep::gpu::GpuOptions g_options;
lockstep::PairModel g_model = lockstep::PairModel::kOrientedBox;

// The pile; `awake_only` turns sleep off so that every cube stays awake
// (the awake measurements), `asleep` builds it resting and asleep.
Scene gpu_test_pile(long n, bool asleep, bool awake_only = false) {
  Scene s = lockstep::gpu_test::settling_pile(static_cast<int>(n), kColumn, asleep, kJitter);
  s.pair_contacts = g_model;
  if (awake_only) s.effects.sleep = false;
  return s;
}

std::vector<long> parse_list(const std::string& s) {
  std::vector<long> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(std::atol(item.c_str()));
  return out;
}

struct Timing {
  double ms_per_step = 0.0;  // median over the timed frames
  double mean_ms = 0.0;
  std::vector<double> stage_ms;  // per frame, by stage
  int awake = 0;
};

template <class StepFn>
std::vector<double> time_frames(int frames, StepFn&& step) {
  std::vector<double> ms;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    step();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  return ms;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

template <class T>
Timing time_gpu(const Scene& s, int warm) {
  lockstep::gpu::GpuOptions o = g_options;
  o.stage_timing = true;
  lockstep::gpu::BasicGpuWorld<T> g(s, o);
  for (int f = 0; f < warm; ++f) g.step();
  Timing t;
  // Wall clock per step (a step ends when the device has finished it), with
  // the stage events recorded (about a microsecond each); then the stages'
  // times of the next frames.
  const std::vector<double> ms = time_frames(kTimedFrames, [&] { g.step(); });
  t.ms_per_step = median(ms);
  t.mean_ms = mean(ms);
  t.stage_ms.assign(lockstep::gpu::kStageCount, 0.0);
  g.reset_stage_times();
  for (int f = 0; f < kTimedFrames; ++f) g.step();
  const lockstep::gpu::StageTimes st2 = g.stage_times();
  for (int k = 0; k < lockstep::gpu::kStageCount; ++k)
    t.stage_ms[static_cast<std::size_t>(k)] = st2.frames ? st2.ms[static_cast<std::size_t>(k)] / st2.frames : 0.0;
  t.awake = g.awake_count();
  return t;
}

template <class T>
Timing time_cpu(const Scene& s, int warm, int frames) {
  lockstep::World<T> e(s);
  for (int f = 0; f < warm; ++f) e.step();
  Timing t;
  const std::vector<double> ms = time_frames(frames, [&] { e.step(); });
  t.ms_per_step = median(ms);
  t.mean_ms = mean(ms);
  t.awake = e.awake_count();
  return t;
}

Timing time_cpu(const Scene& s, const std::string& engine, int warm, int frames) {
  return engine == "fixed" ? time_cpu<lockstep::Q16>(s, warm, frames) : time_cpu<double>(s, warm, frames);
}

std::string json_row(const char* engine, const char* state, long n, const Timing& t) {
  std::ostringstream o;
  o << "{\"engine\":\"" << engine << "\",\"state\":\"" << state << "\",\"bodies\":" << n
    << ",\"ms_per_step\":" << t.ms_per_step << ",\"mean_ms\":" << t.mean_ms
    << ",\"body_steps_per_s\":" << (t.ms_per_step > 0 ? static_cast<double>(n) / (t.ms_per_step * 1e-3) : 0.0)
    << ",\"awake\":" << t.awake;
  if (!t.stage_ms.empty()) {
    o << ",\"stages_ms\":{";
    for (int k = 0; k < lockstep::gpu::kStageCount; ++k)
      o << (k ? "," : "") << "\"" << lockstep::gpu::stage_name(k) << "\":" << t.stage_ms[static_cast<std::size_t>(k)];
    o << "}";
  }
  o << "}";
  return o.str();
}

void print_row(const char* engine, const char* state, long n, const Timing& t) {
  std::printf("%-9s %-7s %9ld %10.3f %12.3e %9d", engine, state, n, t.ms_per_step,
              t.ms_per_step > 0 ? static_cast<double>(n) / (t.ms_per_step * 1e-3) : 0.0, t.awake);
  for (double ms : t.stage_ms) std::printf(" %7.3f", ms);
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> sizes{10000, 100000, 1000000, 10000000}, cpu_sizes{10000};
  long sleep_size = 1000000;
  int sleep_frames = 1500;
  std::string json_path, backend_name = "auto", solver_name = "coloured", model_name = "oriented_box",
              number_name = "float";
  long profile = 0;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string k = argv[a], v = argv[a + 1];
    if (k == "--sizes") sizes = parse_list(v);
    else if (k == "--cpu-sizes") cpu_sizes = parse_list(v);
    else if (k == "--sleep-size") sleep_size = std::atol(v.c_str());
    else if (k == "--sleep-frames") sleep_frames = std::atoi(v.c_str());
    else if (k == "--json") json_path = v;
    else if (k == "--backend") backend_name = v;
    else if (k == "--profile") profile = std::atol(v.c_str());
    else if (k == "--solver") solver_name = v;
    else if (k == "--model") model_name = v;
    else if (k == "--number") number_name = v;
    else { std::fprintf(stderr, "gpu_bench: unknown option %s\n", k.c_str()); return 2; }
  }
  if (solver_name != "coloured" && solver_name != "jacobi") {
    std::fprintf(stderr, "gpu_bench: --solver %s: expected coloured or jacobi\n", solver_name.c_str());
    return 2;
  }
  if (model_name != "aabb" && model_name != "oriented_box") {
    std::fprintf(stderr, "gpu_bench: --model %s: expected aabb or oriented_box\n", model_name.c_str());
    return 2;
  }
  if (number_name != "float" && number_name != "fixed" && number_name != "both") {
    std::fprintf(stderr, "gpu_bench: --number %s: expected float, fixed or both\n", number_name.c_str());
    return 2;
  }
  const bool gpu_float = number_name != "fixed", gpu_fixed = number_name != "float";
  g_model = model_name == "aabb" ? lockstep::PairModel::kAabb : lockstep::PairModel::kOrientedBox;
  g_options.backend = backend_name == "host" ? lockstep::gpu::Backend::kHost : lockstep::gpu::Backend::kAuto;
  g_options.pair_solver = solver_name == "jacobi" ? lockstep::gpu::GpuOptions::PairSolver::kJacobi
                                                  : lockstep::gpu::GpuOptions::PairSolver::kColoured;
  if (profile > 0) {  // float, or with --number fixed gpu-fixed
    auto capture = [&](auto& g) {
      for (int f = 0; f < kWarmFrames; ++f) g.step();
      lockstep::gpu::profiler_capture(true);
      g.step();
      lockstep::gpu::profiler_capture(false);
      std::printf("profiled frame %d of the %ld-cube pile (%d awake)\n", g.frame(), profile, g.awake_count());
    };
    if (number_name == "fixed") {
      lockstep::gpu::GpuFixedWorld g(gpu_test_pile(profile, false, true), g_options);
      capture(g);
    } else {
      GpuWorld g(gpu_test_pile(profile, false, true), g_options);
      capture(g);
    }
    return 0;
  }
  const lockstep::gpu::DeviceInfo dev = lockstep::gpu::device_info();
  const double copy_gbs = lockstep::gpu::measure_copy_bandwidth(std::size_t{1} << 30, 20);
  std::printf("device: %s (%d SMs, %.1f GiB); copy bandwidth %.1f GB/s (read + write); pair solver %s, pair model %s\n",
              dev.name.empty() ? "none (host build)" : dev.name.c_str(), dev.multiprocessors, dev.memory_gib, copy_gbs,
              solver_name.c_str(), model_name.c_str());
  std::printf("scene: settling pile, columns of %d unit cubes 0.2 m apart, turned by up to %.2f; awake: sleep off,"
              " timed frames %d..%d; asleep: built resting and asleep\n",
              kColumn, kJitter, kWarmFrames + 1, kWarmFrames + kTimedFrames);
  std::printf("%-9s %-7s %9s %10s %12s %9s", "engine", "state", "bodies", "ms/step", "body-steps/s", "awake");
  for (int k = 0; k < lockstep::gpu::kStageCount; ++k) std::printf(" %7.7s", lockstep::gpu::stage_name(k));
  std::printf("\n");
  std::vector<std::string> rows;
  for (long n : sizes) {
    for (const bool fixed : {false, true}) {
      if (fixed ? !gpu_fixed : !gpu_float) continue;
      const char* name = fixed ? "gpu-fixed" : "gpu";
      auto time = [&](const Scene& s, int warm) {
        return fixed ? time_gpu<lockstep::Q16>(s, warm) : time_gpu<float>(s, warm);
      };
      const Timing awake = time(gpu_test_pile(n, false, true), kWarmFrames);
      print_row(name, "awake", n, awake);
      rows.push_back(json_row(name, "awake", n, awake));
      const Timing asleep = time(gpu_test_pile(n, true), 2);
      print_row(name, "asleep", n, asleep);
      rows.push_back(json_row(name, "asleep", n, asleep));
    }
  }
  for (long n : cpu_sizes) {
    for (const char* engine : {"fixed", "double"}) {
      const Timing awake = time_cpu(gpu_test_pile(n, false, true), engine, kWarmFrames, kTimedFrames / 2);
      print_row(engine, "awake", n, awake);
      rows.push_back(json_row(engine, "awake", n, awake));
      const Timing asleep = time_cpu(gpu_test_pile(n, true), engine, 2, kTimedFrames / 2);
      print_row(engine, "asleep", n, asleep);
      rows.push_back(json_row(engine, "asleep", n, asleep));
    }
  }
  // The awake pile run until it falls asleep (or sleep_frames): awake count
  // and time per step along the way.
  std::vector<std::string> sleep_rows;
  if (sleep_size > 0) {
    GpuWorld g(gpu_test_pile(sleep_size, false), g_options);
    std::printf("settling run, %ld cubes: frame, awake, ms/step (mean of the last 50 frames)\n", sleep_size);
    double window = 0.0;
    for (int f = 1; f <= sleep_frames; ++f) {
      const auto t0 = Clock::now();
      g.step();
      window += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      if (f % 50 == 0 || g.awake_count() == 0) {
        std::printf("  %5d %9d %9.3f\n", f, g.awake_count(), window / (f % 50 == 0 ? 50 : f % 50));
        std::ostringstream r;
        r << "{\"frame\":" << f << ",\"awake\":" << g.awake_count() << ",\"ms_per_step\":" << window / (f % 50 == 0 ? 50 : f % 50) << "}";
        sleep_rows.push_back(r.str());
        window = 0.0;
        if (g.awake_count() == 0) break;
      }
    }
    std::fflush(stdout);
  }
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\"device\":\"" << dev.name << "\",\"multiprocessors\":" << dev.multiprocessors
        << ",\"copy_bandwidth_gbs\":" << copy_gbs << ",\"pair_solver\":\"" << solver_name << "\"" << ",\"pair_contacts\":\"" << model_name << "\"" << ",\"number\":\"" << number_name << "\"" << ",\"column\":" << kColumn << ",\"jitter\":" << kJitter << ",\"warm_frames\":" << kWarmFrames
        << ",\"timed_frames\":" << kTimedFrames << ",\"rows\":[";
    for (std::size_t k = 0; k < rows.size(); ++k) out << (k ? ",\n" : "\n") << rows[k];
    out << "],\"settling_run\":[";
    for (std::size_t k = 0; k < sleep_rows.size(); ++k) out << (k ? ",\n" : "\n") << sleep_rows[k];
    out << "]}\n";
  }
  return 0;
}
