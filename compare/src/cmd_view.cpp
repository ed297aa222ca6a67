// `lockstep view RUN... [--out FILE.html]`: the replay page of one or more
// runs of one scene (trajectory CSVs written by `lockstep run`, with the run
// record beside each): one self-contained HTML file (view.hpp). `lockstep
// view FILE.rec.json` plays a recording (`lockstep run --record`): it replays
// it, marks the inputs' frames and shows "DIVERGED at frame N" from the first
// frame whose hash differs from the recorded one (docs/RECORDINGS.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "commands.hpp"
#include "lockstep/body_ids.hpp"
#include "lockstep/compare/recording.hpp"
#include "lockstep/compare/replay.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/compare/tolerances.hpp"
#include "lockstep/compare/view.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep::cli {
namespace {

struct ViewArgs {
  std::vector<std::string> runs;
  std::string out, title, tolerances, engine;
  long long max_mb = 48;
};

// Whether the file is a recording ("format": "lockstep-recording" near its start).
bool is_recording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(256, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find(std::string("\"") + compare::kRecordingFormat + "\"") != std::string::npos;
}

// A body as the page shows it where it does not exist (not yet created, or
// removed): at its creation pose, at rest.
BodySnapshot at_rest(const BodyDesc& d) {
  const double n = std::sqrt(d.orientation.w * d.orientation.w + d.orientation.x * d.orientation.x +
                             d.orientation.y * d.orientation.y + d.orientation.z * d.orientation.z);
  return {{d.position.x, d.position.y, d.position.z},
          {d.orientation.w / n, d.orientation.x / n, d.orientation.y / n, d.orientation.z / n},
          {0, 0, 0},
          {0, 0, 0},
          false,
          -1};
}

// The page of a recording: its replay's trajectory on `engine`, the inputs'
// frames, and where the replay's hashes leave the recorded ones. The page's
// bodies are every body that exists at some frame, in order of first
// appearance (the scene's, then each created one); a body is marked absent
// (asleep byte 2) in the frames where it does not exist.
int view_recording(const ViewArgs& a) {
  const std::string& path = a.runs.front();
  compare::RunRecording rec;
  try {
    rec = compare::load_recording_file(path);
  } catch (const compare::RecordingError& e) {
    throw std::invalid_argument(std::string("RUN: ") + e.what());
  }
  const std::string engine_name = a.engine.empty() ? rec.engine : a.engine;
  set_quiet_engines(true);
  std::unique_ptr<EngineRun> engine = make_engine(engine_name, rec.scene);
  const int frames = rec.frames();
  Scene shown_scene = rec.scene;            // the page's bodies: the scene's, then each created one
  std::vector<int> column(rec.scene.bodies.size());  // per engine body index: its page body
  for (std::size_t i = 0; i < column.size(); ++i) column[i] = static_cast<int>(i);
  BodyIds ids;
  ids.reset(column.size());
  std::size_t creations = 0;
  for (const Input& in : rec.inputs) creations += in.kind == InputKind::create ? 1 : 0;
  const int stride = compare::view_stride(frames, static_cast<int>(column.size() + creations), 1,
                                          static_cast<std::size_t>(a.max_mb) << 20);
  compare::ViewRecorder recorder("replay on " + engine_name, engine_name, false, false);  // the per-frame series
  struct Kept {
    int frame;
    std::vector<BodySnapshot> bodies;  // by engine index
    std::vector<int> column;
  };
  std::vector<Kept> kept;
  auto keep = [&] {
    Kept k{engine->frame(), {}, column};
    for (int i = 0; i < engine->body_count(); ++i) k.bodies.push_back(engine->body(i));
    kept.push_back(std::move(k));
  };
  recorder.add(*engine, false);
  keep();
  compare::ViewRecording shown;
  shown.recorded_engine = rec.engine;
  shown.engine = engine_name;
  for (const Input& in : rec.inputs) shown.inputs.emplace_back(in.frame, input_kind_name(in.kind));
  std::size_t next = 0;
  for (int f = 1; f <= frames; ++f) {
    for (; next < rec.inputs.size() && rec.inputs[next].frame == f; ++next) {
      const Input& in = rec.inputs[next];
      compare::apply_input(*engine, in);
      if (in.kind == InputKind::create) {  // appended at the end, with the next id
        (void)ids.add();
        column.push_back(static_cast<int>(shown_scene.bodies.size()));
        shown_scene.bodies.push_back(in.body);
      } else if (in.kind == InputKind::destroy) {  // the bodies after it move down one
        const std::size_t index = ids.require(in.id, "destroy");
        ids.remove(index);
        column.erase(column.begin() + static_cast<std::ptrdiff_t>(index));
      }
    }
    engine->step();
    if (shown.diverged_frame < 0 && engine->state_hash() != rec.hashes[static_cast<std::size_t>(f - 1)]) shown.diverged_frame = f;
    recorder.add(*engine, false);
    if (f % stride == 0 || f == frames) keep();
  }
  const std::size_t columns = shown_scene.bodies.size();
  compare::ViewRun run = recorder.take();
  run.bodies = static_cast<int>(columns);
  std::vector<BodySnapshot> last(columns);  // where each body was last seen (before its creation: where it is created)
  for (std::size_t c = 0; c < columns; ++c) last[c] = at_rest(shown_scene.bodies[c]);
  std::vector<char> seen(columns, 0);
  for (const Kept& k : kept)  // a body's first state seen is where it waits before it appears
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      const auto c = static_cast<std::size_t>(k.column[i]);
      if (!seen[c]) last[c] = k.bodies[i];
      seen[c] = 1;
    }
  for (const Kept& k : kept) {
    std::vector<char> present(columns, 0);
    for (std::size_t i = 0; i < k.bodies.size(); ++i) {
      const auto c = static_cast<std::size_t>(k.column[i]);
      last[c] = k.bodies[i];
      present[c] = 1;
    }
    run.frames.push_back(k.frame);
    for (std::size_t c = 0; c < columns; ++c) {
      const BodySnapshot& b = last[c];
      for (double x : {b.p[0], b.p[1], b.p[2], b.q[0], b.q[1], b.q[2], b.q[3], b.v[0], b.v[1], b.v[2], b.w[0], b.w[1], b.w[2]})
        run.state.push_back(static_cast<float>(x));
      run.asleep.push_back(present[c] ? (b.asleep ? 1 : 0) : 2);
    }
  }
  shown.note = "recording " + path + " (" + rec.engine + ", " + std::to_string(rec.inputs.size()) + " inputs) replayed on " +
               engine_name + ": " +
               (shown.diverged_frame < 0 ? "the hashes agree on all " + std::to_string(frames) + " frames"
                                         : "DIVERGED at frame " + std::to_string(shown.diverged_frame) +
                                               " (lockstep replay " + path + (a.engine.empty() ? "" : " --engine " + engine_name) +
                                               " names the body, field and stage)");
  compare::ViewPage page;
  page.stride = stride;
  page.scene = shown_scene;
  page.runs.push_back(std::move(run));
  page.title = a.title.empty() ? "lockstep view " + rec.scene.name + " (recording)" : a.title;
  page.recording = shown;
  std::string out = a.out;
  if (out.empty()) {
    out = path;
    if (out.size() > 5 && out.substr(out.size() - 5) == ".json") out.resize(out.size() - 5);
    out += ".html";
  }
  const std::string html = compare::view_html(page, compare::load_view_libraries());
  compare::write_file(out, html);
  std::printf("view: %s (recording of scene '%s', %s, %d frames, %zu inputs marked; %s)\n", out.c_str(),
              rec.scene.name.c_str(), count_of(static_cast<long long>(columns), "body", "bodies").c_str(), frames,
              rec.inputs.size(),
              shown.diverged_frame < 0 ? ("the replay on " + engine_name + " agrees with it on every frame").c_str()
                                       : ("DIVERGED at frame " + std::to_string(shown.diverged_frame) + " on " + engine_name).c_str());
  return 0;
}

int view_command(const ViewArgs& a) {
  if (a.runs.size() == 1 && is_recording(a.runs.front())) return view_recording(a);
  if (!a.engine.empty()) throw std::invalid_argument("--engine: only for a recording (lockstep view FILE.rec.json --engine E)");
  for (const std::string& path : a.runs)
    if (is_recording(path))
      throw std::invalid_argument("RUN '" + path + "' is a recording: view shows one recording at a time, without other runs");
  // Choose the stride from the runs' shapes before loading them.
  int frames = 0, bodies = 0;
  for (const std::string& path : a.runs) {
    const compare::RunShape s = compare::run_shape(path);
    frames = std::max(frames, s.written_frames - 1);
    bodies = std::max(bodies, s.bodies);
  }
  const int stride = compare::view_stride(frames, bodies, static_cast<int>(a.runs.size()),
                                          static_cast<std::size_t>(a.max_mb) << 20);
  compare::ViewPage page;
  page.stride = stride;
  for (const std::string& path : a.runs) {
    compare::LoadedRun loaded = compare::load_run(path, stride);
    if (page.runs.empty()) {
      page.scene = loaded.scene;
    } else {
      Scene s = loaded.scene;
      s.frames = page.scene.frames;
      if (const std::string diff = scene_difference(page.scene, s); !diff.empty())
        throw std::invalid_argument("RUN '" + path + "' is a run of another scene than '" + a.runs.front() + "' (" + diff +
                                    "); view compares runs of one scene");
    }
    page.runs.push_back(std::move(loaded.run));
  }
  page.title = a.title.empty() ? "lockstep view " + page.scene.name : a.title;
  if (page.runs.size() > 1) {
    compare::CompareTolerances tol = compare::tolerances_for(page.scene);
    if (!a.tolerances.empty()) tol = compare::load_tolerances_file(a.tolerances, tol);
    page.comparison = compare::compare_runs(page.runs, tol);
  }
  std::string out = a.out;
  if (out.empty()) {
    out = a.runs.size() == 1 ? a.runs.front() : "view-" + page.scene.name + ".html";
    if (a.runs.size() == 1) {
      if (out.size() > 4 && out.substr(out.size() - 4) == ".csv") out.resize(out.size() - 4);
      out += ".html";
    }
  }
  const std::string html = compare::view_html(page, compare::load_view_libraries());
  compare::write_file(out, html);
  const std::size_t kept = page.runs.front().frames.size();
  std::printf("view: %s (%zu run%s of scene '%s', %s, %zu frames kept%s; %.2f MiB of trajectories as float32, "
              "page %.2f MiB)\n",
              out.c_str(), page.runs.size(), page.runs.size() == 1 ? "" : "s", page.scene.name.c_str(),
              count_of(static_cast<long long>(page.scene.bodies.size()), "body", "bodies").c_str(),
              kept, stride == 1 ? "" : (", 1 written frame in " + std::to_string(stride)).c_str(),
              static_cast<double>(compare::view_data_bytes(page)) / (1 << 20), static_cast<double>(html.size()) / (1 << 20));
  if (page.comparison) {
    const compare::ViewComparison& c = *page.comparison;
    const std::size_t base_frames = page.runs.front().frames.size();
    std::printf("  trajectory tolerance %g m, %g rad (as `lockstep compare`); rest tolerance %g m for the final pose\n",
                c.position_tolerance, c.orientation_tolerance, c.rest_position_tolerance);
    for (std::size_t r = 1; r < page.runs.size(); ++r) {
      const std::string common =
          static_cast<std::size_t>(c.common_frames[r]) == base_frames
              ? std::string("every kept frame")
              : "the " + std::to_string(c.common_frames[r]) + " frames both runs hold (of " + std::to_string(base_frames) +
                    " kept; written with different --every)";
      std::printf("  %s parts from %s %s\n", page.runs[r].label.c_str(), page.runs[0].label.c_str(),
                  c.parted_frame[r] < 0 ? ("nowhere (within the trajectory tolerance on " + common + ")").c_str()
                                        : ("at frame " + std::to_string(c.parted_frame[r]) + " (body " +
                                           std::to_string(c.parted_body[r]) + "; compared on " + common + ")").c_str());
      if (c.final_distance[r] >= 0)
        std::printf("    final pose: %.3g m from %s at most (body %d), %s the rest tolerance %g m\n", c.final_distance[r],
                    page.runs[0].label.c_str(), c.final_body[r],
                    c.final_distance[r] > c.rest_position_tolerance ? "beyond" : "within", c.rest_position_tolerance);
    }
    if (!c.note.empty()) std::printf("  %s\n", c.note.c_str());
  }
  return 0;
}

std::function<int()> define(CLI::App& app) {
  auto a = std::make_shared<ViewArgs>();
  app.add_option("RUN", a->runs, "trajectory CSVs written by `lockstep run` (each with its FILE.run.json); two or more "
                                 "runs of one scene are compared, the first as the baseline; or one recording "
                                 "(`lockstep run --record`), replayed")->required();
  app.add_option("--out", a->out, "the page (default: RUN with .html for one run, view-SCENE.html for several)");
  app.add_option("--engine", a->engine, "a recording's replay engine (default: the recording's)")
      ->check(one_of(accepted_engine_names()));
  app.add_option("--page-mb,--max-mb", a->max_mb, "MiB of trajectories the page holds at most; above, every k-th "
                                                  "written frame (--max-mb: the old name)")
      ->check(integer_in(1, 4096))->capture_default_str();
  app.add_option("--title", a->title, "the page's title (default: lockstep view SCENE)");
  app.add_option("--tolerances", a->tolerances, "tolerances JSON file for the divergence marks (docs/COMPARE.md; default: "
                                                "the scene's built-in ones)");
  return [a] { return view_command(*a); };
}

const bool registered = register_command(
    {"view", "the replay page of runs of one scene: boxes in 3D, charts, divergence (one HTML file, works offline)",
     "  lockstep run stack5 --engine fixed --out fixed.csv --contacts\n"
     "  lockstep run stack5 --engine float --out float.csv\n"
     "  lockstep view fixed.csv float.csv --out stack5.html   # open stack5.html in a browser\n"
     "  lockstep run pyramid --record p.rec.json && lockstep view p.rec.json --engine double   # DIVERGED at frame 1\n",
     define});

}  // namespace
}  // namespace lockstep::cli
