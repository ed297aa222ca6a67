// What accuracy costs in time: each engine's error against the truth (the mp
// engine, Boost.Multiprecision 113-bit) and its time per step, measured in one
// invocation (`lockstep accuracy`, docs/COMPARE.md).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "lockstep/scene.hpp"

namespace lockstep::compare {

inline constexpr const char* kTruthEngine = "mp";

struct AccuracyOptions {
  // The truth costs 30-70x a double step: a scene of B bodies is compared
  // over min(frames, max(1, truth_body_frames / B)) frames (every built-in
  // scene in full except pile1000: 120 of its 600 frames by default).
  long long truth_body_frames = 120'000;
  // Timing: each engine's run is repeated (without the comparison) until
  // min_timing_seconds of stepping or max_timing_runs runs; the fastest run's
  // time per step is reported (the least disturbed by other processes).
  double min_timing_seconds = 0.5;
  int max_timing_runs = 200;
  std::function<void(const std::string&)> log;  // progress lines, may be empty
};

struct AccuracyRow {
  std::string scene, engine, description;
  int bodies = 0;
  int frames = 0;          // frames compared with the truth and timed
  int scene_frames = 0;    // the scene's full length
  double ms_per_step = 0;  // fastest timed run (ms)
  int timing_runs = 0;
  // Against the truth, over frames 1..frames and all bodies:
  double pos_rms = 0, pos_max = 0;  // |p - p_truth| (m)
  double ori_rms = 0, ori_max = 0;  // angle(q, q_truth) (rad)
  int parted_frame = -1;            // first frame with |p - p_truth| > 1 mm (-1: never)
  bool failed = false;              // the run stopped (RunError): errors cover the frames before
  std::string failure;
};

inline constexpr double kPartedDistance = 1e-3;  // (m)

// The truth must be among engines (it gets zero error). Rows in engine order.
std::vector<AccuracyRow> measure_accuracy(const Scene& scene, const std::vector<std::string>& engines,
                                          const AccuracyOptions& options);

// The table as Markdown and CSV, and the accuracy-versus-time chart (SVG).
std::string accuracy_markdown(const std::vector<AccuracyRow>& rows, const std::string& machine, const std::string& date);
std::string accuracy_csv(const std::vector<AccuracyRow>& rows);
std::string accuracy_svg(const std::vector<AccuracyRow>& rows, const std::string& machine);

// The CPU model from /proc/cpuinfo ("unknown CPU" elsewhere).
std::string machine_name();

}  // namespace lockstep::compare
