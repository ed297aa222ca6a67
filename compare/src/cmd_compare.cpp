// `lockstep compare [SCENE] --engines fixed,double,...`: runs engines side by
// side on one scene and judges their agreement (docs/COMPARE.md). Exit 0 when
// they agree, 1 on disagreement (each failed check names engine, body, frame
// and quantity), 2 on a usage or scene error.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "commands.hpp"
#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/compare/tolerances.hpp"
#include "progress.hpp"

namespace lockstep::cli {
namespace {

std::vector<std::string> split_engines(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string name;
  while (std::getline(ss, name, ',')) {
    if (name.empty()) continue;
    if (std::find(out.begin(), out.end(), name) != out.end())
      throw std::invalid_argument("--engines: '" + name + "' is listed twice");
    out.push_back(name);
  }
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

int compare_command(const std::vector<std::string>& argv) {
  const Args args = parse_args(argv, {"--engines", "--baseline", "--frames", "--tolerances", "--report", "--max-failures"},
                               {"--no-report", "--no-progress", "--quiet", "--print-tolerances"});
  if (args.positional.size() > 1)
    throw std::invalid_argument("compare takes one SCENE; got " + std::to_string(args.positional.size()));
  Scene scene = resolve_scene(args.positional.empty() ? "" : args.positional[0]);
  scene.frames = static_cast<int>(args.get_int("--frames", scene.frames, 0, 10'000'000));
  if (args.get("--engines", "").empty())
    for (const std::string& e : engine_names())
      if (const std::string why = engine_limitation(e, scene); !why.empty())
        std::fprintf(stderr, "lockstep compare: %s is left out: %s\n", e.c_str(), why.c_str());
  const std::vector<std::string> engines = split_engines(args.get("--engines", join(engine_names_for(scene))));
  for (const std::string& e : engines) {
    const auto all = accepted_engine_names();
    if (std::find(all.begin(), all.end(), e) == all.end())
      throw std::invalid_argument("--engines: unknown engine '" + e + "'; available: " + join(all));
  }
  if (engines.size() < 2) throw std::invalid_argument("--engines: name at least two engines to compare");
  const bool have_double = std::find(engines.begin(), engines.end(), "double") != engines.end();
  const std::string baseline = args.get("--baseline", have_double ? "double" : engines.front());

  compare::CompareTolerances tol = compare::tolerances_for(scene);
  const std::string tol_file = args.get("--tolerances", "");
  if (!tol_file.empty()) tol = compare::load_tolerances_file(tol_file, tol);
  if (args.has_flag("--print-tolerances")) {
    std::printf("%s", compare::tolerances_to_json(tol).c_str());
    return 0;
  }
  const bool quiet = args.has_flag("--quiet");
  if (!quiet) {
    std::fprintf(stderr, "lockstep compare: scene '%s' (%zu bodies, %d frames), engines %s, baseline %s, tolerances %s\n",
                 scene.name.c_str(), scene.bodies.size(), scene.frames, join(engines).c_str(), baseline.c_str(),
                 tol_file.empty() ? "built in (docs/COMPARE.md)" : tol_file.c_str());
    if (std::find(engines.begin(), engines.end(), "mp") != engines.end() && scene.bodies.size() > 100)
      std::fprintf(stderr, "note: the mp engine is 30-70x slower than double; on %zu bodies this takes a while "
                           "(--engines fixed,float,double leaves it out)\n", scene.bodies.size());
  }
  Progress progress(scene.frames, !args.has_flag("--no-progress") && !quiet);
  compare::RecordOptions opts;
  opts.progress = [&](int done, int) { progress.update(done); };
  const compare::Recording rec = compare::record(scene, engines, baseline, opts);
  progress.finish();
  const compare::Verdict verdict = compare::judge(rec, tol);
  const int max_failures = static_cast<int>(args.get_int("--max-failures", 20, 0, 1'000'000));
  std::printf("%s", compare::summary_table(rec, verdict, max_failures).c_str());
  if (!args.has_flag("--no-report")) {
    const std::string dir = args.get("--report", "compare-" + scene.name);
    compare::write_report(dir, rec, verdict);
    std::printf("report: %s/ (summary.txt, frames.csv, bodies.csv, checks.csv, sleep.csv, statistics.csv, "
                "divergence.svg, divergence_orientation.svg, energy.svg, sleep_timeline.svg)\n", dir.c_str());
  }
  return verdict.agree() ? 0 : 1;
}

const bool registered = register_command({"compare",
    "compare [SCENE] [--engines a,b,..] [--baseline E] [--frames N] [--tolerances F] [--report DIR|--no-report]",
    "run engines side by side; judge trajectories, rest, sleep (exit 1 on disagreement)", compare_command});

}  // namespace
}  // namespace lockstep::cli
