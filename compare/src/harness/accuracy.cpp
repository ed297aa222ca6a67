#include "lockstep/compare/accuracy.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/resting.hpp"
#include "lockstep/compare/svg.hpp"

namespace lockstep::compare {
namespace {

using Clock = std::chrono::steady_clock;

struct Pose {
  double p[3], q[4];
};

std::string g(double v, const char* f) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The fastest of up to max_runs whole runs of `frames` steps (s per step).
double time_runs(const Scene& scene, const std::string& engine, int frames, const AccuracyOptions& o, double first_run_s,
                 int* runs) {
  double best = frames > 0 ? first_run_s / frames : 0;
  double total = first_run_s;
  *runs = 1;
  while (frames > 0 && total < o.min_timing_seconds && *runs < o.max_timing_runs) {
    std::unique_ptr<EngineRun> e = make_engine(engine, scene);
    const auto t0 = Clock::now();
    try {
      for (int f = 0; f < frames; ++f) e->step();
    } catch (const RunError&) {
      break;  // the first run recorded the failure
    }
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    total += s;
    best = std::min(best, s / frames);
    ++*runs;
  }
  return best;
}

}  // namespace

std::vector<AccuracyRow> measure_accuracy(const Scene& scene, const std::vector<std::string>& engines,
                                          const AccuracyOptions& o) {
  if (std::find(engines.begin(), engines.end(), kTruthEngine) == engines.end())
    throw std::invalid_argument(std::string("accuracy: the truth engine '") + kTruthEngine + "' must be among the engines");
  const int bodies = static_cast<int>(scene.bodies.size());
  const long long cap = std::max<long long>(1, o.truth_body_frames / std::max(1, bodies));
  const int frames = static_cast<int>(std::min<long long>(scene.frames, cap));
  auto log = [&](const std::string& s) { if (o.log) o.log(s); };

  // The truth's trajectory, then every engine against it.
  std::vector<Pose> truth;
  truth.reserve(static_cast<std::size_t>(frames) * static_cast<std::size_t>(bodies));
  std::vector<AccuracyRow> rows;
  std::vector<std::string> order{kTruthEngine};
  for (const std::string& e : engines) {
    if (e == kTruthEngine) continue;
    if (const std::string why = engine_limitation(e, scene); !why.empty()) {
      log("  " + scene.name + ": " + e + " left out: " + why);
      continue;
    }
    order.push_back(e);
  }
  for (const std::string& name : order) {
    log("  " + scene.name + ": " + name + ", " + std::to_string(frames) + " frames");
    std::unique_ptr<EngineRun> e = make_engine(name, scene);
    AccuracyRow r;
    r.scene = scene.name;
    r.engine = name;
    r.description = e->description();
    r.bodies = bodies;
    r.frames = frames;
    r.scene_frames = scene.frames;
    const bool is_truth = name == kTruthEngine;
    double step_s = 0, pos_sq = 0, ori_sq = 0;
    long long samples = 0;
    int done = 0;
    for (int f = 1; f <= frames; ++f) {
      const auto t0 = Clock::now();
      try {
        e->step();
      } catch (const RunError& err) {
        r.failed = true;
        r.failure = err.what();
        if (is_truth) throw;
        break;
      }
      step_s += std::chrono::duration<double>(Clock::now() - t0).count();
      done = f;
      for (int i = 0; i < bodies; ++i) {
        const BodySnapshot b = e->body(i);
        const std::size_t k = static_cast<std::size_t>(f - 1) * static_cast<std::size_t>(bodies) + static_cast<std::size_t>(i);
        if (is_truth) {
          Pose p;
          std::copy(b.p, b.p + 3, p.p);
          std::copy(b.q, b.q + 4, p.q);
          truth.push_back(p);
          continue;
        }
        const Pose& t = truth[k];
        const double dp = std::sqrt((b.p[0] - t.p[0]) * (b.p[0] - t.p[0]) + (b.p[1] - t.p[1]) * (b.p[1] - t.p[1]) +
                                    (b.p[2] - t.p[2]) * (b.p[2] - t.p[2]));
        const double dq = orientation_angle(t.q, b.q);
        pos_sq += dp * dp;
        ori_sq += dq * dq;
        ++samples;
        r.pos_max = std::max(r.pos_max, dp);
        r.ori_max = std::max(r.ori_max, dq);
        if (r.parted_frame < 0 && dp > kPartedDistance) r.parted_frame = f;
      }
    }
    if (samples > 0) {
      r.pos_rms = std::sqrt(pos_sq / static_cast<double>(samples));
      r.ori_rms = std::sqrt(ori_sq / static_cast<double>(samples));
    }
    r.ms_per_step = 1e3 * (r.failed ? (done ? step_s / done : 0) : time_runs(scene, name, frames, o, step_s, &r.timing_runs));
    rows.push_back(r);
  }
  // Back to the caller's engine order.
  std::vector<AccuracyRow> out;
  for (const std::string& e : engines)
    for (const AccuracyRow& r : rows)
      if (r.engine == e) out.push_back(r);
  return out;
}

std::string accuracy_markdown(const std::vector<AccuracyRow>& rows, const std::string& machine, const std::string& date) {
  std::ostringstream o;
  o << "Measured on " << machine << (date.empty() ? "" : ", " + date)
    << ": error against `mp` (the Boost.Multiprecision 113-bit truth) over the frames shown, and the fastest of "
       "repeated runs' time per step (CPU engines on one thread).\n\n";
  std::vector<std::string> seen;
  for (const AccuracyRow& r : rows) {
    if (std::find(seen.begin(), seen.end(), r.engine) != seen.end()) continue;
    seen.push_back(r.engine);
    o << "- `" << r.engine << "`: " << r.description << "\n";
  }
  o << "\n";
  o << "| scene | bodies | frames | engine | ms/step | pos RMS error (m) | pos max error (m) | ori max error (rad) | "
       "parts from truth (> 1 mm) |\n";
  o << "|---|---:|---:|---|---:|---:|---:|---:|---:|\n";
  for (const AccuracyRow& r : rows) {
    const bool truth = r.engine == kTruthEngine;
    std::string frames = std::to_string(r.frames);
    if (r.frames < r.scene_frames) frames += " of " + std::to_string(r.scene_frames);
    o << "| " << r.scene << " | " << r.bodies << " | " << frames << " | " << r.engine << " | " << g(r.ms_per_step, "%.4f")
      << " | " << (truth ? "0 (truth)" : g(r.pos_rms, "%.2e")) << " | " << (truth ? "0" : g(r.pos_max, "%.2e")) << " | "
      << (truth ? "0" : g(r.ori_max, "%.2e")) << " | "
      << (truth ? "-" : r.parted_frame < 0 ? "never" : "frame " + std::to_string(r.parted_frame))
      << (r.failed ? " (run stopped: " + r.failure + ")" : "") << " |\n";
  }
  bool limited = false;
  for (const AccuracyRow& r : rows) limited = limited || r.frames < r.scene_frames;
  if (limited)
    o << "\n\"N of M\" frames: the truth (mp) costs 30-70x a double step, so that scene was compared and timed over its "
         "first N frames only (`--truth-body-frames`).\n";
  return o.str();
}

std::string accuracy_csv(const std::vector<AccuracyRow>& rows) {
  std::ostringstream o;
  o << "scene,bodies,frames,scene_frames,engine,ms_per_step,timing_runs,pos_rms_m,pos_max_m,ori_rms_rad,ori_max_rad,"
       "parted_frame,failed\n";
  for (const AccuracyRow& r : rows)
    o << r.scene << ',' << r.bodies << ',' << r.frames << ',' << r.scene_frames << ',' << r.engine << ','
      << g(r.ms_per_step, "%.6g") << ',' << r.timing_runs << ',' << g(r.pos_rms, "%.6g") << ',' << g(r.pos_max, "%.6g") << ','
      << g(r.ori_rms, "%.6g") << ',' << g(r.ori_max, "%.6g") << ',' << r.parted_frame << ',' << (r.failed ? 1 : 0) << '\n';
  return o.str();
}

std::string accuracy_svg(const std::vector<AccuracyRow>& rows, const std::string& machine) {
  svg::Chart c;
  c.title = "Accuracy versus time per step (built-in scenes)";
  c.x_label = "time per step (ms, log)";
  c.y_label = "RMS position error against mp (m, log)";
  c.log_x = c.log_y = true;
  c.width = 1000;
  c.height = 620;
  c.notes.push_back(machine + "; one point per scene and engine, labelled with the scene;");
  c.notes.push_back("mp is the truth (error 0 by definition), drawn on the bottom axis");
  double lo = INFINITY;
  for (const AccuracyRow& r : rows)
    if (r.engine != kTruthEngine && r.pos_rms > 0) lo = std::min(lo, r.pos_rms);
  const double floor_y = std::isfinite(lo) ? std::pow(10.0, std::floor(std::log10(lo)) - 1) : 1e-12;
  auto y_of = [&](const AccuracyRow& r) { return r.engine == kTruthEngine ? floor_y : r.pos_rms; };
  std::vector<std::string> engines;
  for (const AccuracyRow& r : rows)
    if (std::find(engines.begin(), engines.end(), r.engine) == engines.end()) engines.push_back(r.engine);
  for (std::size_t e = 0; e < engines.size(); ++e) {
    svg::Series s;
    s.name = engines[e] == kTruthEngine ? engines[e] + " (truth)" : engines[e];
    s.lines = false;
    s.markers = true;
    s.color = static_cast<int>(e);
    for (const AccuracyRow& r : rows) {
      if (r.engine != engines[e]) continue;
      s.x.push_back(r.ms_per_step);
      s.y.push_back(y_of(r));
      s.point_labels.push_back(r.scene);
    }
    c.series.push_back(std::move(s));
  }
  return svg::render(c);
}

std::string machine_name() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string m = line.substr(colon + 1);
        m.erase(0, m.find_first_not_of(" \t"));
        return m;
      }
    }
  }
  return "unknown CPU";
}

}  // namespace lockstep::compare
