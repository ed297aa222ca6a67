// `lockstep compare [SCENE] --engines fixed,double,...`: runs engines side by
// side on one scene and judges their agreement (docs/COMPARE.md). Exit 0 when
// they agree, 1 on disagreement (each failed check names engine, body, frame
// and quantity; an engine that cannot run the scene, e.g. fixed on a body
// Q16.16 cannot hold, is a failed column with the reason, and the others are
// still judged), 2 on a usage or scene error.
#include <algorithm>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "lockstep/compare/harness.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/compare/tolerances.hpp"
#include "lockstep/compare/view.hpp"
#include "lockstep/scene_limits.hpp"
#include "progress.hpp"

namespace lockstep::cli {
namespace {

std::vector<std::string> split_engines(const std::string& list) {
  std::vector<std::string> out;
  for (const std::string& name : split_list(list)) {
    if (std::find(out.begin(), out.end(), name) != out.end())
      throw std::invalid_argument("--engines: '" + name + "' is listed twice");
    out.push_back(name);
  }
  return out;
}

struct CompareArgs {
  std::string scene, engines, baseline, tolerances, report;
  int frames = -1, max_failures = 20;
  long long page_mb = 48;
  bool no_report = false, no_progress = false, quiet = false, print_tolerances = false, no_page = false;
};

int compare_command(const CompareArgs& a) {
  Scene scene = resolve_scene(a.scene);
  if (a.frames >= 0) scene.frames = a.frames;
  if (a.engines.empty() && !a.quiet)
    for (const std::string& e : engine_names())
      if (const std::string why = engine_limitation(e, scene); !why.empty())
        std::fprintf(stderr, "lockstep compare: %s is left out: %s\n", e.c_str(), why.c_str());
  const std::vector<std::string> engines = split_engines(a.engines.empty() ? join(engine_names_for(scene)) : a.engines);
  for (const std::string& e : engines) {
    const auto all = accepted_engine_names();
    if (std::find(all.begin(), all.end(), e) == all.end())
      throw std::invalid_argument("--engines: unknown engine '" + e + "'; available: " + join(all));
  }
  if (engines.size() < 2) throw std::invalid_argument("--engines: name at least two engines to compare");
  // The default baseline: double if listed, else the first; an engine that
  // cannot run the scene (scene_limits.hpp) is passed over. It still runs as a
  // failed column (record), and the comparison fails.
  auto can_run = [&scene](const std::string& e) {
    try {
      validate_scene_for(number_type_of_engine(e), scene);
      return true;
    } catch (const SceneError&) {
      return false;
    }
  };
  const bool have_double = std::find(engines.begin(), engines.end(), "double") != engines.end() && can_run("double");
  const auto first_runnable = std::find_if(engines.begin(), engines.end(), can_run);
  const std::string baseline = !a.baseline.empty() ? a.baseline
                               : have_double      ? "double"
                               : first_runnable != engines.end() ? *first_runnable
                                                                 : engines.front();
  if (std::find(engines.begin(), engines.end(), baseline) == engines.end())
    throw std::invalid_argument("--baseline: '" + baseline + "' is not among the engines compared (" + join(engines) + ")");

  compare::CompareTolerances tol = compare::tolerances_for(scene);
  const std::string& tol_file = a.tolerances;
  if (!tol_file.empty()) tol = compare::load_tolerances_file(tol_file, tol);
  if (a.print_tolerances) {
    std::printf("%s", compare::tolerances_to_json(tol).c_str());
    return 0;
  }
  const bool quiet = a.quiet;
  set_quiet_engines(quiet);  // no gpu host-build note either
  if (!quiet) {
    std::fprintf(stderr, "lockstep compare: scene '%s' (%s, %d frames), engines %s, baseline %s, tolerances %s\n",
                 scene.name.c_str(), count_of(static_cast<long long>(scene.bodies.size()), "body", "bodies").c_str(), scene.frames, join(engines).c_str(), baseline.c_str(),
                 tol_file.empty() ? "built in (docs/COMPARE.md)" : tol_file.c_str());
    if (std::find(engines.begin(), engines.end(), "mp") != engines.end() && scene.bodies.size() > 100)
      std::fprintf(stderr, "note: the mp engine is 30-70x slower than double; on %zu bodies this takes a while "
                           "(--engines fixed,float,double leaves it out)\n", scene.bodies.size());
  }
  Progress progress(scene.frames, !a.no_progress && !quiet);
  compare::RecordOptions opts;
  opts.progress = [&](int done, int) { progress.update(done); };
  // The replay page's data (index.html): every engine's states every
  // `stride` frames, the stride keeping them under --page-mb.
  bool page = !a.no_report && !a.no_page;
  const int stride = compare::view_stride(scene.frames, static_cast<int>(scene.bodies.size()), static_cast<int>(engines.size()),
                                          static_cast<std::size_t>(a.page_mb) << 20);
  // Contacts of every kept frame too when they stay small (at most 10^5 body-frames).
  const bool contacts = static_cast<long long>(scene.bodies.size()) * (scene.frames / stride + 1) <= 100'000;
  std::vector<compare::ViewRecorder> views;
  for (const std::string& e : engines) views.emplace_back(e, e, contacts);
  if (page)
    opts.observe = [&](int e, const EngineRun& run) {
      views[static_cast<std::size_t>(e)].add(run, run.frame() % stride == 0 || run.frame() == scene.frames);
    };
  const compare::Recording rec = compare::record(scene, engines, baseline, opts);
  progress.finish();
  const compare::Verdict verdict = compare::judge(rec, tol);
  std::printf("%s", compare::summary_table(rec, verdict, a.max_failures).c_str());
  if (!a.no_report) {
    const std::string dir = a.report.empty() ? "compare-" + scene.name : a.report;
    compare::write_report(dir, rec, verdict);
    std::string page_note;
    compare::ViewPage view;
    if (page) {
      view.title = "lockstep compare " + scene.name;
      view.scene = scene;
      view.stride = stride;
      // The baseline first: the page measures divergence from runs[0]. An
      // engine that refused the scene has no frames and is left off the page
      // (the summary and checks.csv say why).
      auto refused = [&rec](std::size_t e) { return rec.engines[e].failed && rec.engines[e].failure.refused; };
      const std::size_t b = static_cast<std::size_t>(rec.baseline);
      if (!refused(b)) view.runs.push_back(views[b].take());
      for (std::size_t e = 0; e < views.size(); ++e)
        if (e != b && !refused(e)) view.runs.push_back(views[e].take());
      if (view.runs.empty()) page = false;
    }
    if (page) {
      // The divergence and where each engine parts: the harness's (computed
      // in double on every frame), not the page's float32 copy.
      compare::ViewComparison c = compare::compare_runs(view.runs, tol);
      for (std::size_t r = 0; r < view.runs.size(); ++r) {
        for (const compare::EngineVerdict& ev : verdict.engines)
          if (ev.engine == view.runs[r].engine) {
            c.parted_frame[r] = ev.parted_frame;
            c.parted_body[r] = ev.parted_body;
          }
        for (const compare::EngineTrack& t : rec.engines)
          if (t.name == view.runs[r].engine) {
            c.divergence[r].clear();
            for (const int f : view.runs.front().frames)
              if (f < static_cast<int>(t.frames.size())) c.divergence[r].push_back(t.frames[static_cast<std::size_t>(f)].pos_max);
          }
      }
      view.comparison = std::move(c);
      compare::ViewLibraries libraries;
      try {
        libraries = compare::load_view_libraries();
      } catch (const std::runtime_error& e) {
        // The verdict stands without the page: say why it is missing.
        std::fprintf(stderr, "lockstep compare: no index.html in the report: %s\n", e.what());
        page = false;
      }
      if (page) {
        compare::write_file(dir + "/index.html", compare::view_html(view, libraries));
        page_note = ", index.html (the replay page: " + std::to_string(compare::view_data_bytes(view) >> 10) +
                    " KiB of trajectories, " +
                    (stride == 1 ? std::string("every frame") : "1 frame in " + std::to_string(stride)) + ")";
      }
    }
    std::printf("report: %s/ (summary.txt, frames.csv, bodies.csv, checks.csv, sleep.csv, statistics.csv, "
                "divergence.svg, divergence_orientation.svg, energy.svg, sleep_timeline.svg%s)\n", dir.c_str(),
                page_note.c_str());
  }
  return verdict.agree() ? 0 : 1;
}

std::function<int()> define(CLI::App& app) {
  auto a = std::make_shared<CompareArgs>();
  app.add_option("SCENE", a->scene, "built-in scene name or JSON scene file; default: " + std::string(kDefaultSceneName));
  app.add_option("--engines", a->engines, "comma-separated engines, at least two (default: " + join(engine_names()) +
                                               ", less those the scene rules out)");
  app.add_option("--baseline", a->baseline, "the engine the others are judged against (default: double if listed, "
                                            "else the first)");
  app.add_option("--frames", a->frames, "frames to run (default: the scene's)")->check(integer_in(0, 10'000'000));
  app.add_option("--tolerances", a->tolerances, "tolerances JSON file (docs/COMPARE.md; default: built in)");
  app.add_option("--report", a->report, "report folder (default: compare-SCENE): CSVs, SVGs and index.html, the replay page");
  app.add_option("--max-failures", a->max_failures, "failed checks listed in the summary")->check(integer_in(0, 1'000'000))
      ->capture_default_str();
  app.add_option("--page-mb,--max-mb", a->page_mb, "MiB of trajectories the replay page holds at most; above, every k-th "
                                                  "frame (--max-mb: as in view)")
      ->check(integer_in(1, 4096))->capture_default_str();
  app.add_flag("--no-report", a->no_report, "write no report folder");
  app.add_flag("--no-page", a->no_page, "no index.html in the report");
  app.add_flag("--no-progress", a->no_progress, "no progress bar");
  app.add_flag("--quiet", a->quiet, "no progress or notes on stderr");
  app.add_flag("--print-tolerances", a->print_tolerances, "print the scene's tolerances as JSON and exit");
  return [a] { return compare_command(*a); };
}

const bool registered = register_command({"compare",
    "run engines side by side; judge trajectories, rest, sleep (exit 1 on disagreement)",
    "  lockstep compare stack5 --engines fixed,float,double --report compare-stack5   # then open compare-stack5/index.html\n",
    define});

}  // namespace
}  // namespace lockstep::cli
