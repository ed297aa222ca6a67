// `lockstep scenes`: lists the built-in scenes; `lockstep scenes NAME` prints one as JSON.
#include <cstdio>

#include "commands.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep::cli {
namespace {
int scenes_command(const std::vector<std::string>& argv) {
  const Args args = parse_args(argv, {}, {});
  if (args.positional.empty()) {
    for (const auto& n : builtin_scene_names()) {
      const Scene s = *builtin_scene(n);
      std::printf("%-12s %5zu bodies %7d frames%s\n", n.c_str(), s.bodies.size(), s.frames, n == kDefaultSceneName ? "  (default)" : "");
    }
    return 0;
  }
  std::printf("%s\n", scene_to_json(resolve_scene(args.positional[0])).c_str());
  return 0;
}
const bool registered = register_command({"scenes", "scenes [SCENE]", "list the built-in scenes, or print one as JSON", scenes_command});
}  // namespace
}  // namespace lockstep::cli
