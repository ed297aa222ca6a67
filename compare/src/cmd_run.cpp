// `lockstep run [SCENE] --engine E`: runs a scene and writes its trajectory
// (CSV or JSON lines) and the per-frame state hashes (eq 92).
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "lockstep/compare/engine.hpp"
#include "progress.hpp"

namespace lockstep::cli {
namespace {

void write_csv_header(std::ostream& out) {
  out << "frame,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,asleep\n";
}

void write_frame(std::ostream& out, const EngineRun& e, bool jsonl, bool raw) {
  char buf[512];
  if (jsonl) {
    std::snprintf(buf, sizeof buf, "{\"frame\":%d,\"hash\":\"%016" PRIx64 "\",\"bodies\":[", e.frame(), e.state_hash());
    out << buf;
  }
  for (int i = 0; i < e.body_count(); ++i) {
    const BodySnapshot b = e.body(i);
    const std::vector<std::int32_t> r = raw ? e.raw_state(i) : std::vector<std::int32_t>{};
    if (jsonl) {
      out << (i ? "," : "") << "{\"p\":[";
      if (!r.empty()) {
        std::snprintf(buf, sizeof buf, "%d,%d,%d],\"q\":[%d,%d,%d,%d],\"v\":[%d,%d,%d],\"w\":[%d,%d,%d]", r[0], r[1], r[2], r[3],
                      r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12]);
      } else {
        std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g],\"q\":[%.9g,%.9g,%.9g,%.9g],\"v\":[%.9g,%.9g,%.9g],\"w\":[%.9g,%.9g,%.9g]",
                      b.p[0], b.p[1], b.p[2], b.q[0], b.q[1], b.q[2], b.q[3], b.v[0], b.v[1], b.v[2], b.w[0], b.w[1], b.w[2]);
      }
      out << buf << ",\"asleep\":" << (b.asleep ? "true" : "false") << "}";
    } else if (!r.empty()) {
      std::snprintf(buf, sizeof buf, "%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d\n", e.frame(), i, r[0], r[1], r[2], r[3],
                    r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12], b.asleep ? 1 : 0);
      out << buf;
    } else {
      std::snprintf(buf, sizeof buf, "%d,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", e.frame(), i,
                    b.p[0], b.p[1], b.p[2], b.q[0], b.q[1], b.q[2], b.q[3], b.v[0], b.v[1], b.v[2], b.w[0], b.w[1], b.w[2],
                    b.asleep ? 1 : 0);
      out << buf;
    }
  }
  if (jsonl) out << "]}\n";
}

int run_command(const std::vector<std::string>& argv) {
  const Args args = parse_args(argv, {"--engine", "--frames", "--out", "--format", "--every"}, {"--raw", "--quiet", "--no-progress"});
  if (args.positional.size() > 1) throw std::invalid_argument("run takes one SCENE; got " + std::to_string(args.positional.size()));
  Scene scene = resolve_scene(args.positional.empty() ? "" : args.positional[0]);
  scene.frames = static_cast<int>(args.get_int("--frames", scene.frames, 0, 10'000'000));
  const std::string engine_name = args.get("--engine", "fixed");
  const std::string format = args.get("--format", "csv");
  if (format != "csv" && format != "jsonl") throw std::invalid_argument("--format: '" + format + "' must be csv or jsonl");
  const long long every = args.get_int("--every", 1, 1, 1'000'000);
  const bool raw = args.has_flag("--raw");
  if (raw && engine_name != "fixed") throw std::invalid_argument("--raw: only the fixed engine has raw Q16.16 state");
  const std::string out_path = args.get("--out", scene.name + "-" + engine_name + "." + format);

  std::unique_ptr<EngineRun> engine = make_engine(engine_name, scene);
  std::ofstream file;
  std::ostream* out = &std::cout;
  if (out_path != "-") {
    file.open(out_path);
    if (!file) throw std::invalid_argument("--out: cannot write '" + out_path + "'");
    out = &file;
  }
  std::ofstream hashes;
  const bool jsonl = format == "jsonl";
  if (!jsonl && out_path != "-") hashes.open(out_path + ".hashes");
  if (!jsonl) write_csv_header(*out);
  if (hashes) hashes << "frame,hash\n";
  const bool quiet = args.has_flag("--quiet");
  if (!quiet) std::fprintf(stderr, "lockstep run: scene '%s' (%zu bodies, %d frames) on %s\n", scene.name.c_str(),
                           scene.bodies.size(), scene.frames, engine->description().c_str());
  Progress progress(scene.frames, !args.has_flag("--no-progress") && !quiet);
  write_frame(*out, *engine, jsonl, raw);
  int all_asleep_frame = -1;
  double step_seconds = 0;
  for (int f = 0; f < scene.frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    engine->step();
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (engine->frame() % every == 0 || f + 1 == scene.frames) write_frame(*out, *engine, jsonl, raw);
    if (hashes) { char h[64]; std::snprintf(h, sizeof h, "%d,%016" PRIx64 "\n", engine->frame(), engine->state_hash()); hashes << h; }
    if (all_asleep_frame < 0) {
      bool all = engine->body_count() > 0;
      for (int i = 0; i < engine->body_count() && all; ++i) all = engine->body(i).asleep;
      if (all) all_asleep_frame = engine->frame();
    }
    progress.update(f + 1);
  }
  const double secs = step_seconds;
  progress.finish();
  if (!quiet) {
    std::printf("scene %s, engine %s: %d frames, %d bodies, %.3f ms/step (stepping only), final hash %016" PRIx64 ", ", scene.name.c_str(),
                engine_name.c_str(), engine->frame(), engine->body_count(), scene.frames ? 1e3 * secs / scene.frames : 0.0,
                engine->state_hash());
    if (all_asleep_frame >= 0) std::printf("all asleep at frame %d\n", all_asleep_frame);
    else std::printf("not all asleep\n");
    if (out_path != "-") std::printf("trajectory: %s%s\n", out_path.c_str(), hashes ? (", hashes: " + out_path + ".hashes").c_str() : "");
  }
  return 0;
}

const bool registered = register_command({"run",
    "run [SCENE] [--engine fixed|float|double|mp|gpu|gpu-jacobi] [--frames N] [--out F|-] [--format csv|jsonl] [--every K] [--raw]",
    "run a scene; write its trajectory and per-frame hashes", run_command});

}  // namespace
}  // namespace lockstep::cli
