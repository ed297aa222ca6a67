// `lockstep vectors generate DIR` writes the hand-off test vectors (three
// levels, vectors/README.md); `lockstep vectors verify DIR` checks the fixed
// engine against them and names the first differing test, or frame, body and
// field.
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>

#include "commands.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/vectors/vectors.hpp"

namespace lockstep::cli {
namespace {

struct VectorsArgs {
  std::string action, dir, level;
  std::vector<std::string> scenes;
  int frames = -1;
  bool quiet = false;
};

int vectors_command(const VectorsArgs& a) {
  const std::string& dir = a.dir;
  for (const std::string& v : a.scenes)
    if (!builtin_scene(v)) throw std::invalid_argument("--scene: '" + v + "' is not a built-in scene");
  const std::vector<std::string>& scenes = a.scenes;
  std::ostream* log = a.quiet ? nullptr : &std::cout;
  if (a.action == "generate") {
    if (!a.level.empty() || a.frames >= 0)
      throw std::invalid_argument("generate writes every level and every frame; --level and --frames are for verify");
    vectors::GenerateOptions o;
    o.scenes = scenes;
    vectors::generate_directory(dir, o, log);
    return 0;
  }
  vectors::VerifyOptions o;
  const std::string level = a.level.empty() ? "all" : a.level;
  o.arithmetic = level == "all" || level == "arithmetic";
  o.formulas = level == "all" || level == "formulas";
  o.scenes = level == "all" || level == "scenes";
  o.only_scenes = scenes;
  const long long frames = a.frames;
  if (frames >= 0)
    for (const std::string& n : builtin_scene_names()) o.max_frames[n] = static_cast<int>(frames);
  const std::vector<vectors::Verdict> verdicts = vectors::verify_directory(dir, o, log);
  int failed = 0;
  for (const vectors::Verdict& v : verdicts) failed += v.ok ? 0 : 1;
  if (failed == 0) {
    std::printf("vectors verify: %zu files agree with the fixed engine bit for bit\n", verdicts.size());
    return 0;
  }
  for (const vectors::Verdict& v : verdicts)
    if (!v.ok) std::fprintf(stderr, "MISMATCH %s\n", v.message.c_str());
  std::fprintf(stderr,
               "vectors verify: %d of %zu files differ. If the engine's bits changed on purpose, regenerate with\n"
               "  %s\nand review the diff.\n",
               failed, verdicts.size(), vectors::kRegenerateCommand);
  return 1;
}

std::function<int()> define(CLI::App& app) {
  auto a = std::make_shared<VectorsArgs>();
  app.add_option("ACTION", a->action, "generate: write the vectors; verify: check the fixed engine against them")
      ->required()->check(one_of({"generate", "verify"}));
  app.add_option("DIR", a->dir, "the vectors folder (vectors/data in the checkout)")->required();
  app.add_option("--scene", a->scenes, "only this built-in scene (repeatable; default: all)")->allow_extra_args(false);
  app.add_option("--level", a->level, "verify only this level (default: all)")
      ->check(one_of({"all", "arithmetic", "formulas", "scenes"}));
  app.add_option("--frames", a->frames, "verify only the first N frames of each scene")->check(integer_in(0, 10'000'000));
  app.add_flag("--quiet", a->quiet, "no per-file log");
  return [a] { return vectors_command(*a); };
}

const bool registered = register_command(
    {"vectors", "write the hand-off test vectors, or check the fixed engine against them",
     "  lockstep vectors generate vectors/data\n  lockstep vectors verify vectors/data --scene drop --frames 100\n", define});

}  // namespace
}  // namespace lockstep::cli
