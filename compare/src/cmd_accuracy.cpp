// `lockstep accuracy [SCENE...]`: each engine's error against the mp truth and
// its time per step, for the built-in scenes (or those named); writes
// accuracy.md, accuracy.csv and accuracy_vs_time.svg (docs/COMPARE.md).
#include <algorithm>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/accuracy.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/report.hpp"

namespace lockstep::cli {
namespace {

struct AccuracyArgs {
  std::vector<std::string> scenes;
  std::string engines, out = "accuracy", machine = compare::machine_name(), date;
  long long truth_body_frames = compare::AccuracyOptions{}.truth_body_frames;
  int timing_runs = compare::AccuracyOptions{}.max_timing_runs;
  bool quiet = false;
};

int accuracy_command(const AccuracyArgs& a) {
  std::vector<std::string> scenes = a.scenes;
  if (scenes.empty()) scenes = builtin_scene_names();
  std::vector<std::string> engines = split_list(a.engines.empty() ? join(engine_names()) : a.engines);
  if (std::find(engines.begin(), engines.end(), compare::kTruthEngine) == engines.end())
    engines.push_back(compare::kTruthEngine);
  for (const std::string& e : engines) {
    const auto all = accepted_engine_names();
    if (std::find(all.begin(), all.end(), e) == all.end())
      throw std::invalid_argument("--engines: unknown engine '" + e + "'; allowed: " + join(all, ", "));
  }
  compare::AccuracyOptions opts;
  opts.truth_body_frames = a.truth_body_frames;
  opts.max_timing_runs = a.timing_runs;
  if (!a.quiet) opts.log = [](const std::string& s) { std::fprintf(stderr, "%s\n", s.c_str()); };
  const std::string& machine = a.machine;
  const std::string& date = a.date;
  const std::string& out = a.out;

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

std::function<int()> define(CLI::App& app) {
  auto a = std::make_shared<AccuracyArgs>();
  app.add_option("SCENE", a->scenes, "scenes to measure (default: every built-in scene)");
  app.add_option("--engines", a->engines, "comma-separated engines (default: " + join(engine_names()) +
                                              "); mp, the truth, is always added");
  app.add_option("--out", a->out, "folder for accuracy.md, accuracy.csv, accuracy_vs_time.svg")->capture_default_str();
  app.add_option("--truth-body-frames", a->truth_body_frames, "bodies x frames the mp truth runs at most per scene")
      ->check(integer_in(1, 1'000'000'000'000LL))->capture_default_str();
  app.add_option("--timing-runs", a->timing_runs, "timed runs per engine (the fastest counts)")
      ->check(integer_in(1, 1000))->capture_default_str();
  app.add_option("--machine", a->machine, "machine name in the table")->capture_default_str();
  app.add_option("--date", a->date, "date in the table");
  app.add_flag("--quiet", a->quiet, "no progress log on stderr");
  return [a] { return accuracy_command(*a); };
}

const bool registered = register_command({"accuracy",
    "each engine's error against the mp truth and its time per step; table + chart",
    "  lockstep accuracy drop stack5 --engines fixed,float,double --out accuracy\n", define});

}  // namespace
}  // namespace lockstep::cli
