// `lockstep accuracy [SCENE...]`: each engine's error against the mp truth and
// its time per step, for the built-in scenes (or those named); writes
// accuracy.md, accuracy.csv and accuracy_vs_time.svg (docs/COMPARE.md).
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "commands.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/accuracy.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/report.hpp"

namespace lockstep::cli {
namespace {

int accuracy_command(const std::vector<std::string>& argv) {
  const Args args = parse_args(argv, {"--engines", "--out", "--truth-body-frames", "--machine", "--date", "--timing-runs"},
                               {"--quiet"});
  std::vector<std::string> scenes = args.positional;
  if (scenes.empty()) scenes = builtin_scene_names();
  std::vector<std::string> engines;
  {
    std::string list = args.get("--engines", "");
    if (list.empty())
      for (const std::string& e : engine_names()) list += (list.empty() ? "" : ",") + e;
    std::stringstream ss(list);
    for (std::string e; std::getline(ss, e, ',');)
      if (!e.empty()) engines.push_back(e);
    if (std::find(engines.begin(), engines.end(), compare::kTruthEngine) == engines.end())
      engines.push_back(compare::kTruthEngine);
    for (const std::string& e : engines) {
      const auto all = accepted_engine_names();
      if (std::find(all.begin(), all.end(), e) == all.end())
        throw std::invalid_argument("--engines: unknown engine '" + e + "'");
    }
  }
  compare::AccuracyOptions opts;
  opts.truth_body_frames = args.get_int("--truth-body-frames", opts.truth_body_frames, 1, 1'000'000'000'000LL);
  opts.max_timing_runs = static_cast<int>(args.get_int("--timing-runs", opts.max_timing_runs, 1, 1000));
  if (!args.has_flag("--quiet")) opts.log = [](const std::string& s) { std::fprintf(stderr, "%s\n", s.c_str()); };
  const std::string machine = args.get("--machine", compare::machine_name());
  const std::string date = args.get("--date", "");
  const std::string out = args.get("--out", "accuracy");

  std::vector<compare::AccuracyRow> rows;
  for (const std::string& name : scenes) {
    const Scene scene = resolve_scene(name);
    for (compare::AccuracyRow& r : compare::measure_accuracy(scene, engines, opts)) rows.push_back(std::move(r));
  }
  const std::string md = compare::accuracy_markdown(rows, machine, date);
  std::printf("%s", md.c_str());
  compare::write_file(out + "/accuracy.md", md);
  compare::write_file(out + "/accuracy.csv", compare::accuracy_csv(rows));
  compare::write_file(out + "/accuracy_vs_time.svg", compare::accuracy_svg(rows, machine));
  std::printf("written: %s/accuracy.md, %s/accuracy.csv, %s/accuracy_vs_time.svg\n", out.c_str(), out.c_str(), out.c_str());
  return 0;
}

const bool registered = register_command({"accuracy",
    "accuracy [SCENE...] [--engines a,b,..] [--out DIR] [--truth-body-frames N] [--machine M] [--date D]",
    "each engine's error against the mp truth and its time per step; table + chart", accuracy_command});

}  // namespace
}  // namespace lockstep::cli
