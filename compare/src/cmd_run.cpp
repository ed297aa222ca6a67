// `lockstep run [SCENE] --engine E`: runs a scene and writes its trajectory
// (CSV or JSON lines), the per-frame state hashes (eq 92) and the run record
// that `lockstep view` reads (lockstep/compare/view.hpp). --save-state writes
// the engine's snapshot after the last frame; --load-state resumes from one
// (docs/SNAPSHOTS.md): the scene and the engine are the snapshot's, frame
// numbers go on from its frame. --record writes a recording of the run (its
// scene, the inputs of --inputs, the per-frame hashes and snapshots) that
// `lockstep replay` and `lockstep view` read (docs/RECORDINGS.md).
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/recording.hpp"
#include "lockstep/compare/replay.hpp"
#include "lockstep/compare/report.hpp"
#include "lockstep/compare/view.hpp"
#include "progress.hpp"

namespace lockstep::cli {
namespace {

using compare::hash_hex;
using compare::kRunRecordSuffix;

struct RunOptions {
  std::string scene, engine = "fixed", out, format = "csv", save_state, load_state, record, inputs;
  bool engine_given = false;
  int snapshot_every = 0;
  int frames = -1;
  int threads = 1;
  long long every = 1;
  bool raw = false, quiet = false, no_progress = false, contacts = false;
};

void write_csv_header(std::ostream& out) {
  out << "frame,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,asleep\n";
}

void write_frame(std::ostream& out, const EngineRun& e, bool jsonl, bool raw) {
  if (jsonl) {
    nlohmann::json bodies = nlohmann::json::array();
    for (int i = 0; i < e.body_count(); ++i) {
      const BodySnapshot b = e.body(i);
      nlohmann::json j;
      if (raw) {
        const std::vector<std::int32_t> r = e.raw_state(i);
        j = {{"p", {r[0], r[1], r[2]}}, {"q", {r[3], r[4], r[5], r[6]}}, {"v", {r[7], r[8], r[9]}}, {"w", {r[10], r[11], r[12]}}};
      } else {
        j = {{"p", b.p}, {"q", b.q}, {"v", b.v}, {"w", b.w}};
      }
      j["asleep"] = b.asleep;
      bodies.push_back(std::move(j));
    }
    out << nlohmann::json{{"frame", e.frame()}, {"hash", hash_hex(e.state_hash())}, {"bodies", std::move(bodies)}}.dump()
        << "\n";
    return;
  }
  char buf[512];
  for (int i = 0; i < e.body_count(); ++i) {
    const BodySnapshot b = e.body(i);
    if (raw) {
      const std::vector<std::int32_t> r = e.raw_state(i);
      std::snprintf(buf, sizeof buf, "%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d\n", e.frame(), i, r[0], r[1], r[2], r[3],
                    r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12], b.asleep ? 1 : 0);
    } else {
      std::snprintf(buf, sizeof buf, "%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", e.frame(), i,
                    b.p[0], b.p[1], b.p[2], b.q[0], b.q[1], b.q[2], b.q[3], b.v[0], b.v[1], b.v[2], b.w[0], b.w[1], b.w[2],
                    b.asleep ? 1 : 0);
    }
    out << buf;
  }
}

std::string penetration_text(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g m", m);
  return buf;
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("--load-state: cannot read '" + path + "'");
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

int run_command(RunOptions o) {
  Scene scene;
  std::unique_ptr<EngineRun> engine;
  set_quiet_engines(o.quiet);
  if (o.snapshot_every > 0 && o.record.empty())
    throw std::invalid_argument("--snapshot-every " + std::to_string(o.snapshot_every) +
                                ": snapshots go into a recording; add --record FILE");
  if (!o.load_state.empty() && !o.record.empty())
    throw std::invalid_argument("--record and --load-state: a recording starts at frame 0 of its scene; record from SCENE");
  if (!o.load_state.empty() && !o.inputs.empty())
    throw std::invalid_argument("--inputs and --load-state: inputs name frames from a scene's frame 0; give SCENE");
  if (!o.load_state.empty()) {
    if (!o.scene.empty())
      throw std::invalid_argument("SCENE '" + o.scene + "' and --load-state: the scene is in the snapshot; give one of them");
    ResumedEngine resumed;
    try {
      resumed = engine_from_snapshot(read_bytes(o.load_state));
    } catch (const SnapshotError& e) {
      throw std::invalid_argument("--load-state: " + o.load_state + ": " + e.what());
    }
    if (o.engine_given && o.engine != resumed.engine->name())
      throw std::invalid_argument("--engine " + o.engine + ": '" + o.load_state + "' is a snapshot of the " +
                                  resumed.engine->name() + " engine; omit --engine or give --engine " + resumed.engine->name());
    o.engine = resumed.engine->name();
    engine = std::move(resumed.engine);
    scene = std::move(resumed.scene);
    // --frames: frames to run from the snapshot's; by default what is left of the scene's.
    scene.frames = o.frames >= 0 ? o.frames : std::max(0, scene.frames - engine->frame());
  } else {
    scene = resolve_scene(o.scene);
    if (o.frames >= 0) scene.frames = o.frames;
  }
  const bool jsonl = o.format == "jsonl";
  if (o.raw && o.engine != "fixed") throw std::invalid_argument("--raw: only the fixed engine has raw Q16.16 state");
  const std::string out_path = o.out.empty() ? scene.name + "-" + o.engine + "." + o.format : o.out;

  if (!engine) engine = make_engine(o.engine, scene);
  engine->set_threads(o.threads);
  if (!o.save_state.empty() || !o.record.empty()) (void)engine->save_state();  // an engine without snapshots is refused before the run
  std::unique_ptr<compare::RunRecorder> recorder;
  if (!o.record.empty() || !o.inputs.empty()) {
    compare::RecordRunOptions ro;
    ro.snapshot_every = o.snapshot_every;
    ro.build = build_text();
    std::vector<Input> inputs;
    if (!o.inputs.empty()) inputs = compare::load_inputs_file(o.inputs);
    recorder = std::make_unique<compare::RunRecorder>(o.engine, scene, std::move(inputs), scene.frames, ro);
  }
  std::ofstream file;
  std::ostream* out = &std::cout;
  if (out_path != "-") {
    file.open(out_path);
    if (!file) throw std::invalid_argument("--out: cannot write '" + out_path + "'");
    out = &file;
  }
  std::ofstream hashes;
  if (!jsonl && out_path != "-") hashes.open(out_path + ".hashes");
  if (!jsonl) write_csv_header(*out);
  if (hashes) hashes << "frame,hash\n";
  if (!o.quiet)
    std::fprintf(stderr, "lockstep run: scene '%s' (%s, %d frames) on %s\n", scene.name.c_str(),
                 count_of(static_cast<long long>(scene.bodies.size()), "body", "bodies").c_str(), scene.frames,
                 engine->description().c_str());
  compare::ViewRecorder record(scene.name + "-" + o.engine, o.engine, o.contacts, false);
  record.set_static_bodies(static_cast<int>(
      std::count_if(scene.bodies.begin(), scene.bodies.end(), [](const BodyDesc& b) { return b.is_static; })));
  Progress progress(scene.frames, !o.no_progress && !o.quiet);
  write_frame(*out, *engine, jsonl, o.raw);
  record.add(*engine, o.contacts);
  double step_seconds = 0;
  for (int f = 0; f < scene.frames; ++f) {
    if (recorder) recorder->before_step(*engine);
    const auto t0 = std::chrono::steady_clock::now();
    engine->step();
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (recorder) recorder->after_step(*engine);
    const bool written = engine->frame() % o.every == 0 || f + 1 == scene.frames;
    if (written) write_frame(*out, *engine, jsonl, o.raw);
    record.add(*engine, written && o.contacts);
    if (hashes) hashes << engine->frame() << "," << hash_hex(engine->state_hash()) << "\n";
    progress.update(f + 1);
  }
  progress.finish();
  if (!o.save_state.empty()) {
    const std::vector<std::uint8_t> bytes = engine->save_state();
    std::ofstream state(o.save_state, std::ios::binary);
    if (!state.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
      throw std::invalid_argument("--save-state: cannot write '" + o.save_state + "'");
    if (!o.quiet)
      std::fprintf(stderr, "lockstep run: state after frame %d written to %s (%zu bytes)\n", engine->frame(),
                   o.save_state.c_str(), bytes.size());
  }
  if (!o.record.empty()) {
    compare::write_file(o.record, compare::recording_to_json(recorder->recording()));
    if (!o.quiet)
      std::fprintf(stderr, "lockstep run: recording of %d frames (%zu inputs, %zu snapshots) written to %s\n",
                   recorder->recording().frames(), recorder->recording().inputs.size(),
                   recorder->recording().snapshots.size(), o.record.c_str());
  }
  const double ms = scene.frames ? 1e3 * step_seconds / scene.frames : 0.0;
  const int asleep_at = record.all_asleep_frame();
  const std::string record_path = out_path + kRunRecordSuffix;
  if (hashes) compare::write_file(record_path, compare::run_record_json(scene, record.run(), static_cast<int>(o.every), o.raw));
  if (o.quiet) {
    // One line; on stderr when the trajectory goes to stdout.
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s %s: %d frames, %s ms/step, hash %s, %s, worst penetration %s\n", scene.name.c_str(),
                  o.engine.c_str(), engine->frame(), significant(ms).c_str(), hash_hex(engine->state_hash()).c_str(),
                  asleep_at >= 0 ? ("all asleep at frame " + std::to_string(asleep_at)).c_str() : "not all asleep",
                  record.run().has_contacts ? penetration_text(record.worst_penetration()).c_str() : "n/a (engine reports no contacts)");
    std::fputs(line, out_path == "-" ? stderr : stdout);
    return 0;
  }
  // The summary; on stderr when the trajectory goes to stdout.
  std::FILE* summary = out_path == "-" ? stderr : stdout;
  std::fprintf(summary, "scene %s, engine %s: %d frames, %s, %s ms/step (stepping only), final hash %s, ",
               scene.name.c_str(), o.engine.c_str(), engine->frame(), count_of(engine->body_count(), "body", "bodies").c_str(),
               significant(ms).c_str(),
               hash_hex(engine->state_hash()).c_str());
  if (asleep_at >= 0) std::fprintf(summary, "all asleep at frame %d\n", asleep_at);
  else std::fprintf(summary, "not all asleep\n");
  if (out_path != "-")
    std::printf("trajectory: %s%s\n", out_path.c_str(),
                hashes ? (", hashes: " + out_path + ".hashes, run record: " + record_path).c_str() : "");
  return 0;
}

std::function<int()> define(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  app.add_option("SCENE", o->scene, "built-in scene name (lockstep scenes) or a JSON scene file; default: " +
                                        std::string(kDefaultSceneName));
  CLI::Option* engine = app.add_option("--engine", o->engine, "the engine (with --load-state: the snapshot's)")
                           ->check(one_of(accepted_engine_names()))->capture_default_str();
  app.add_option("--frames", o->frames, "frames to run (default: the scene's; with --load-state, what is left of them)")
      ->check(integer_in(0, 10'000'000));
  app.add_option("--save-state", o->save_state, "write the engine's snapshot after the last frame to FILE (docs/SNAPSHOTS.md)");
  app.add_option("--load-state", o->load_state,
                 "resume from the snapshot in FILE (its scene and engine; frame numbers go on from its frame)");
  app.add_option("--record", o->record,
                 "write a recording of the run to FILE: scene, inputs, per-frame hashes, snapshots "
                 "(docs/RECORDINGS.md; `lockstep replay FILE`)");
  app.add_option("--inputs", o->inputs, "apply the run-time inputs of this JSON file (docs/RECORDINGS.md \"Inputs\")");
  app.add_option("--snapshot-every", o->snapshot_every,
                 "with --record: a snapshot every K frames besides the last (0: the last only)")
      ->check(integer_in(0, 10'000'000))->capture_default_str();
  app.add_option("--out", o->out,
                 "trajectory file, or - for stdout (default: SCENE-ENGINE.FORMAT); a CSV file gets FILE.hashes and "
                 "FILE" + std::string(kRunRecordSuffix) + " (what `lockstep view` reads) beside it");
  app.add_option("--format", o->format, "trajectory format")->check(one_of({"csv", "jsonl"}))->capture_default_str();
  app.add_option("--every", o->every, "write every K-th frame (and the last)")->check(integer_in(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--threads", o->threads,
                 "threads to step on (fixed, float, double, mp; the same bits for every count, docs/SPEC.md 7.7 \"Threads\")")
      ->check(integer_in(1, 256))
      ->capture_default_str();
  app.add_flag("--raw", o->raw, "raw Q16.16 integers instead of decimals (fixed engine only)");
  app.add_flag("--contacts", o->contacts, "also record each written frame's contacts in the run record (for view)");
  app.add_flag("--quiet", o->quiet,
               "no progress or summary; one final line: frames, ms/step, hash, all-asleep frame, worst penetration");
  app.add_flag("--no-progress", o->no_progress, "no progress bar");
  return [o, engine] {
    o->engine_given = engine->count() > 0;
    return run_command(*o);
  };
}

const bool registered = register_command(
    {"run", "run a scene; write its trajectory, per-frame hashes and run record",
     "  lockstep run stack5 --engine double --every 10 --out stack5.csv\n"
     "  lockstep run drop --quiet --out -  > /dev/null\n"
     "  lockstep run stack5 --frames 100 --save-state s.bin && lockstep run --load-state s.bin --frames 100\n"
     "  lockstep run pyramid --frames 120 --inputs kicks.json --record pyramid.rec.json && lockstep replay pyramid.rec.json\n",
     define});

}  // namespace
}  // namespace lockstep::cli
