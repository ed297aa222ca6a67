// `lockstep replay FILE [--engine E]`: re-simulates a recording (`lockstep
// run --record`, docs/RECORDINGS.md) and says "no difference over N frames",
// or names the first frame whose hash differs, the body and field, and the
// stage of that frame. Exit 0: the same; 1: it differs; 2: a bad recording or
// option.
#include <algorithm>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/recording.hpp"
#include "lockstep/compare/replay.hpp"

namespace lockstep::cli {
namespace {

struct ReplayArgs {
  std::string file, engine;
  bool quiet = false;
};

int replay_command(const ReplayArgs& a) {
  compare::RunRecording rec;
  try {
    rec = compare::load_recording_file(a.file);
  } catch (const compare::RecordingError& e) {
    throw std::invalid_argument(std::string("FILE: ") + e.what());
  }
  const std::string engine = a.engine.empty() ? rec.engine : a.engine;
  const auto accepted = accepted_engine_names();
  if (std::find(accepted.begin(), accepted.end(), rec.engine) == accepted.end())
    throw std::invalid_argument("FILE: " + a.file + ": recorded by the engine '" + rec.engine +
                                "', which this build lacks (engines: " + join(accepted, ", ") + ")");
  set_quiet_engines(true);
  if (!a.quiet)
    std::fprintf(stderr, "lockstep replay: %s: scene '%s', %d frames, %zu inputs, recorded on %s by %s; replaying on %s\n",
                 a.file.c_str(), rec.scene.name.c_str(), rec.frames(), rec.inputs.size(), rec.engine.c_str(),
                 rec.build.c_str(), engine.c_str());
  const compare::ReplayReport r =
      compare::replay(rec, engine, [](const std::string& name, const Scene& scene) { return make_engine(name, scene); });
  std::fputs(compare::replay_text(r).c_str(), stdout);
  return r.same() ? 0 : 1;
}

std::function<int()> define(CLI::App& app) {
  auto a = std::make_shared<ReplayArgs>();
  app.add_option("FILE", a->file, "a recording written by `lockstep run --record` (docs/RECORDINGS.md)")->required();
  app.add_option("--engine", a->engine, "the engine that replays (default: the recording's)")
      ->check(one_of(accepted_engine_names()));
  app.add_flag("--quiet", a->quiet, "no line about the recording on stderr");
  return [a] { return replay_command(*a); };
}

const bool registered = register_command(
    {"replay", "re-simulate a recording; name the first frame, body, field and stage that differ",
     "  lockstep run pyramid --frames 120 --record pyramid.rec.json\n"
     "  lockstep replay pyramid.rec.json                  # exit 0: no difference over 120 frames\n"
     "  lockstep replay pyramid.rec.json --engine double  # exit 1: frame 1 differs (another number type)\n",
     define});

}  // namespace
}  // namespace lockstep::cli
