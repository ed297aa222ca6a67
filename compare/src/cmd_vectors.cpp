// `lockstep vectors generate DIR` writes the hand-off test vectors (three
// levels, vectors/README.md); `lockstep vectors verify DIR` checks the fixed
// engine against them and names the first differing test, or frame, body and
// field.
#include <cstdio>
#include <iostream>
#include <map>

#include "commands.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/vectors/vectors.hpp"

namespace lockstep::cli {
namespace {

int vectors_command(const std::vector<std::string>& argv) {
  const Args args = parse_args(argv, {"--scene", "--level", "--frames"}, {"--quiet"});
  if (args.positional.size() != 2 || (args.positional[0] != "generate" && args.positional[0] != "verify"))
    throw std::invalid_argument(
        "usage: lockstep vectors generate|verify DIR [--scene NAME]... [--level L] [--frames N]");
  const std::string& dir = args.positional[1];
  std::vector<std::string> scenes;
  for (const auto& [k, v] : args.options)
    if (k == "--scene") {
      if (!builtin_scene(v)) throw std::invalid_argument("--scene: '" + v + "' is not a built-in scene");
      scenes.push_back(v);
    }
  std::ostream* log = args.has_flag("--quiet") ? nullptr : &std::cout;
  if (args.positional[0] == "generate") {
    if (args.get("--level", "") != "" || args.get("--frames", "") != "")
      throw std::invalid_argument("generate writes every level and every frame; --level and --frames are for verify");
    vectors::GenerateOptions o;
    o.scenes = scenes;
    vectors::generate_directory(dir, o, log);
    return 0;
  }
  vectors::VerifyOptions o;
  const std::string level = args.get("--level", "all");
  if (level != "all" && level != "arithmetic" && level != "formulas" && level != "scenes")
    throw std::invalid_argument("--level: '" + level + "' must be all, arithmetic, formulas or scenes");
  o.arithmetic = level == "all" || level == "arithmetic";
  o.formulas = level == "all" || level == "formulas";
  o.scenes = level == "all" || level == "scenes";
  o.only_scenes = scenes;
  const long long frames = args.get_int("--frames", -1, 0, 10'000'000);
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

const bool registered = register_command(
    {"vectors", "vectors generate|verify DIR [--scene NAME]... [--level all|arithmetic|formulas|scenes] [--frames N]",
     "write the hand-off test vectors, or check the fixed engine against them", vectors_command});

}  // namespace
}  // namespace lockstep::cli
