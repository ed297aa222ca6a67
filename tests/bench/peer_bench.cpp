// peer_bench: one scene on one engine, measured the same way for every engine
// (peer_metrics.hpp): ms per step over all frames and over the busy frames
// 31-120 (stepping only, one thread unless --threads N (lockstep's CPU
// engines: then read the wall clock); the process's CPU time, and the wall
// clock), the frame from which every body stayed asleep, columns standing at
// the end, and the worst penetration into the ground and between two boxes
// over all frames. tests/bench/peers.py runs it for Bullet, lockstep's engines
// and Jolt side by side (README "Speed").
//
//   peer_bench run SCENE --engine bullet|fixed|float|double|mp|gpu [--frames N] [--step-times OUT] [--threads N]
//   peer_bench measure SCENE TRAJECTORY.csv --engine NAME [--step-times FILE]
//                      [--ms-per-step CPU] [--wall-ms-per-step WALL]
//   peer_bench columns --engine E [--count N] [--all]
//
// SCENE is a built-in scene name or a scene JSON file. `run` steps the engine
// in this process (Bullet when it was found at build time; lockstep's engines
// through make_engine, the code behind `lockstep run`); `measure`
// reads a trajectory with a row per body per frame, in `lockstep run`'s CSV
// columns (frame,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,asleep), as
// written by `lockstep run` or by peers.py for Jolt. Each prints one JSON line.
// Step times: a text file with one line per frame, "CPU_SECONDS WALL_SECONDS"
// of that frame's step (frame 1 first). `run --step-times OUT` writes its
// own; `measure --step-times FILE` reads one (peers.py's Jolt worker writes
// it) and summarises it by the same code as `run` (StepTimes below):
// ms_per_step over all frames, busy_ms_per_step over frames 31-120 (1-based:
// the 90 steps while the cubes of pile1000 and boxfall1000 land and collide;
// over the frames there are when a run is shorter, null when it has fewer
// than 31). Without step times, `measure` reports --ms-per-step and
// --wall-ms-per-step as given and no busy figure.
// `columns` runs the harder columns of tests/peer (columns.hpp, the seed of
// peer_stacking_test) on one engine and prints each column that does not
// stand and why (--all: every column), then the count.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/scene_json.hpp"
#include "peer_metrics.hpp"
#if LOCKSTEP_HAVE_BULLET
#include "bullet_run.hpp"
#include "columns.hpp"
#endif

namespace lockstep::peer {
namespace {

Scene resolve(const std::string& arg) {
  if (auto s = builtin_scene(arg)) return *s;
  return load_scene_file(arg);
}

// CPU time of this process (s): what a step costs on a machine shared with
// other work, where the wall clock also counts the time others took.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The busy frames (1-based, inclusive): pile1000's and boxfall1000's cubes
// land and collide, nothing is asleep yet (issue 29).
constexpr int kBusyFirst = 31, kBusyLast = 120;

// Per-frame step times (s) and what peer_bench reports of them: one code for
// every engine, whether stepped here or measured from a file.
struct StepTimes {
  std::vector<double> cpu, wall;  // [f - 1]: frame f's step
  void add(double c, double w) {
    cpu.push_back(c);
    wall.push_back(w);
  }
  // Mean ms per step over frames [first, last] (1-based, clipped to the
  // frames there are); negative when none is there.
  static double mean_ms(const std::vector<double>& t, int first, int last) {
    const int hi = std::min(last, static_cast<int>(t.size()));
    if (first < 1 || hi < first) return -1;
    double sum = 0;
    for (int f = first; f <= hi; ++f) sum += t[static_cast<std::size_t>(f - 1)];
    return 1e3 * sum / (hi - first + 1);
  }
  double cpu_ms() const { return cpu.empty() ? 0.0 : mean_ms(cpu, 1, static_cast<int>(cpu.size())); }
  double wall_ms() const { return wall.empty() ? 0.0 : mean_ms(wall, 1, static_cast<int>(wall.size())); }
  double busy_cpu_ms() const { return mean_ms(cpu, kBusyFirst, kBusyLast); }
  double busy_wall_ms() const { return mean_ms(wall, kBusyFirst, kBusyLast); }

  void write(const std::string& path) const {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::invalid_argument("--step-times: cannot write '" + path + "'");
    for (std::size_t i = 0; i < cpu.size(); ++i) std::fprintf(f, "%.9f %.9f\n", cpu[i], wall[i]);
    std::fclose(f);
  }
  static StepTimes read(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::invalid_argument("--step-times: cannot read '" + path + "'");
    StepTimes t;
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      std::istringstream row(line);
      double c = 0, w = 0;
      if (!(row >> c >> w) || c < 0 || w < 0)
        throw std::invalid_argument("--step-times: '" + path + "' line " + std::to_string(t.cpu.size() + 1) + " '" + line +
                                    "' is not \"CPU_SECONDS WALL_SECONDS\"");
      t.add(c, w);
    }
    return t;
  }
};

// A figure in ms, or null when there is none (negative).
std::string ms_or_null(double ms) {
  if (ms < 0) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", ms);
  return buf;
}

void print(const std::string& engine, const std::string& description, const Scene& s, int frames, double cpu_ms, double wall_ms,
           double busy_cpu_ms, double busy_wall_ms, const PeerMetrics& m) {
  std::printf("{\"engine\": \"%s\", \"description\": \"%s\", \"scene\": \"%s\", \"bodies\": %zu, \"frames\": %d, "
              "\"ms_per_step\": %.4f, \"wall_ms_per_step\": %.4f, \"busy_frames\": [%d, %d], \"busy_ms_per_step\": %s, "
              "\"busy_wall_ms_per_step\": %s, \"all_asleep_frame\": %d, \"asleep_at_end\": %d, "
              "\"columns\": %d, \"standing\": %d, \"upright\": %d, \"worst_ground_mm\": %.2f, \"worst_ground_at\": [%d, %d], "
              "\"worst_pair_mm\": %.2f, \"worst_pair_at\": [%d, %d, %d], \"end_ground_mm\": %.2f, \"end_pair_mm\": %.2f}\n",
              engine.c_str(), description.c_str(), s.name.c_str(), s.bodies.size(), frames, cpu_ms, wall_ms, kBusyFirst, kBusyLast,
              ms_or_null(busy_cpu_ms).c_str(), ms_or_null(busy_wall_ms).c_str(), m.all_asleep_frame,
              m.asleep_at_end, m.columns, m.standing, m.upright, 1e3 * m.worst_ground_m, m.worst_ground_frame, m.worst_ground_body,
              1e3 * m.worst_pair_m, m.worst_pair_frame, m.worst_pair_a, m.worst_pair_b, 1e3 * m.end_ground_m, 1e3 * m.end_pair_m);
}

std::unique_ptr<EngineRun> make(const std::string& engine, const Scene& s) {
#if LOCKSTEP_HAVE_BULLET
  if (engine == "bullet") return std::make_unique<BulletRun>(s);
#else
  if (engine == "bullet") throw std::invalid_argument("--engine bullet: this peer_bench was built without Bullet (Debian: libbullet-dev)");
#endif
  return make_engine(engine, s);
}

int run(const Scene& s, const std::string& engine, const std::string& times_out, int threads) {
  std::unique_ptr<EngineRun> e = make(engine, s);
  e->set_threads(threads);  // lockstep's CPU engines (docs/SPEC.md 7.7 "Threads"); others take 1
  MetricsRecorder rec(s);
  std::vector<BodySnapshot> b(static_cast<std::size_t>(e->body_count()));
  StepTimes t;
  for (int f = 0; f < s.frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_seconds();
    e->step();
    const double c = cpu_seconds() - c0;
    t.add(c, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    for (int i = 0; i < e->body_count(); ++i) b[static_cast<std::size_t>(i)] = e->body(i);
    rec.frame(e->frame(), b);
  }
  if (!times_out.empty()) t.write(times_out);
  print(threads > 1 ? engine + " x" + std::to_string(threads) : engine, e->description(), s, s.frames, t.cpu_ms(), t.wall_ms(), t.busy_cpu_ms(), t.busy_wall_ms(), rec.finish());
  return 0;
}

#if LOCKSTEP_HAVE_BULLET
int columns(const std::string& engine, int count, bool all) {
  int standing = 0;
  for (const Column& c : harder_columns(count, kPeerColumnSeed)) {
    std::unique_ptr<EngineRun> e = make(engine, c.scene);
    const ColumnResult r = run_column(*e, c);
    standing += r.stands;
    if (!r.stands || all)
      std::printf("column %d (%zu cubes of %.3f m): %s; all asleep from frame %d; largest energy change %+.3g J at frame %d; "
                  "largest rise above an earlier frame's energy %.3g J at frame %d\n", c.index, c.scene.bodies.size(), c.size,
                  r.stands ? "stands" : r.why.c_str(), r.all_asleep_frame, r.energy_gain, r.gain_frame, r.rebound, r.rebound_frame);
  }
  std::printf("%s: %d of %d columns stand\n", engine.c_str(), standing, count);
  return 0;
}
#endif

int measure(const Scene& s, const std::string& path, const std::string& engine, const std::string& times_path, double cpu_ms,
            double wall_ms) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("TRAJECTORY: cannot read '" + path + "'");
  std::string line;
  std::getline(in, line);
  if (line.rfind("frame,body,px,py,pz,qw,qx,qy,qz", 0) != 0)
    throw std::invalid_argument("TRAJECTORY: '" + path + "' does not start with lockstep run's CSV header (frame,body,px,...)");
  const std::size_t n = s.bodies.size();
  MetricsRecorder rec(s);
  std::vector<BodySnapshot> b(n);
  int current = -1, frames = 0;
  std::size_t seen = 0;
  auto flush = [&] {
    if (current < 0) return;
    if (seen != n)
      throw std::invalid_argument("TRAJECTORY: frame " + std::to_string(current) + " has " + std::to_string(seen) + " rows, the scene " +
                                  std::to_string(n) + " bodies");
    rec.frame(current, b);
    frames = current;
  };
  while (std::getline(in, line)) {
    const char* c = line.c_str();
    char* end = nullptr;
    double v[16];
    for (double& x : v) {
      x = std::strtod(c, &end);
      if (end == c) throw std::invalid_argument("TRAJECTORY: '" + path + "': bad row '" + line + "'");
      c = *end == ',' ? end + 1 : end;
    }
    const int frame = static_cast<int>(v[0]);
    const std::size_t i = static_cast<std::size_t>(v[1]);
    if (frame != current) {
      flush();
      current = frame;
      seen = 0;
    }
    if (i >= n) throw std::invalid_argument("TRAJECTORY: body " + std::to_string(i) + " but the scene has " + std::to_string(n));
    b[i] = {{v[2], v[3], v[4]}, {v[5], v[6], v[7], v[8]}, {v[9], v[10], v[11]}, {v[12], v[13], v[14]}, v[15] != 0.0, -1};
    ++seen;
  }
  flush();
  double busy_cpu_ms = -1, busy_wall_ms = -1;
  if (!times_path.empty()) {
    const StepTimes t = StepTimes::read(times_path);
    if (static_cast<int>(t.cpu.size()) != frames)
      throw std::invalid_argument("--step-times: '" + times_path + "' has " + std::to_string(t.cpu.size()) + " frames, the trajectory " +
                                  std::to_string(frames));
    cpu_ms = t.cpu_ms();
    wall_ms = t.wall_ms();
    busy_cpu_ms = t.busy_cpu_ms();
    busy_wall_ms = t.busy_wall_ms();
  }
  print(engine, "trajectory " + path, s, frames, cpu_ms, wall_ms, busy_cpu_ms, busy_wall_ms, rec.finish());
  return 0;
}

// A number option's value, or an error naming the option, the value and the fix.
double number(const std::string& name, const std::string& value, double lo, double hi, const char* example) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !(x >= lo && x <= hi))
    throw std::invalid_argument(name + ": '" + value + "' is not a number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                "]; give one such as " + example);
  return x;
}

int main_(int argc, char** argv) {
  std::vector<std::string> a(argv + 1, argv + argc);
  auto option = [&a](const std::string& name, const std::string& fallback) {
    for (std::size_t k = 0; k + 1 < a.size(); ++k)
      if (a[k] == name) return a[k + 1];
    return fallback;
  };
  if (a.size() >= 2 && a[0] == "run") {
    Scene s = resolve(a[1]);
    s.frames = static_cast<int>(number("--frames", option("--frames", std::to_string(s.frames)), 0, 1e7, "600"));
    return run(s, option("--engine", "bullet"), option("--step-times", ""),
               static_cast<int>(number("--threads", option("--threads", "1"), 1, 256, "2")));
  }
  if (a.size() >= 3 && a[0] == "measure")
    return measure(resolve(a[1]), a[2], option("--engine", "trajectory"), option("--step-times", ""),
                   number("--ms-per-step", option("--ms-per-step", "0"), 0, 1e9, "1.5"),
                   number("--wall-ms-per-step", option("--wall-ms-per-step", "0"), 0, 1e9, "1.5"));
#if LOCKSTEP_HAVE_BULLET
  if (!a.empty() && a[0] == "columns") {
    bool all = false;
    for (const std::string& x : a) all = all || x == "--all";
    return columns(option("--engine", "bullet"), static_cast<int>(number("--count", option("--count", "100"), 1, 1e6, "100")), all);
  }
#endif
  std::fprintf(stderr,
               "usage: peer_bench run SCENE --engine bullet|fixed|float|double|mp|gpu [--frames N] [--step-times OUT] [--threads N]\n"
               "       peer_bench measure SCENE TRAJECTORY.csv --engine NAME [--step-times FILE]\n"
               "                          [--ms-per-step CPU] [--wall-ms-per-step WALL]\n"
               "       peer_bench columns --engine E [--count N] [--all]   (built with Bullet)\n");
  return 2;
}

}  // namespace
}  // namespace lockstep::peer

int main(int argc, char** argv) {
  try {
    return lockstep::peer::main_(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_bench: %s\n", e.what());
    return 1;
  }
}
