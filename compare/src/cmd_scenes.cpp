// `lockstep scenes`: lists the built-in scenes; `lockstep scenes NAME` prints one as JSON.
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep::cli {
namespace {
int scenes_command(const std::string& scene) {
  if (scene.empty()) {
    for (const auto& n : builtin_scene_names()) {
      const Scene s = *builtin_scene(n);
      std::printf("%-12s %5zu bodies %7d frames%s\n", n.c_str(), s.bodies.size(), s.frames, n == kDefaultSceneName ? "  (default)" : "");
    }
    return 0;
  }
  std::printf("%s\n", scene_to_json(resolve_scene(scene)).c_str());
  return 0;
}

std::function<int()> define(CLI::App& app) {
  auto scene = std::make_shared<std::string>();
  app.add_option("SCENE", *scene, "a built-in scene or JSON scene file to print as JSON (default: list the built-in scenes)");
  return [scene] { return scenes_command(*scene); };
}

const bool registered = register_command({"scenes", "list the built-in scenes, or print one as JSON",
                                          "  lockstep scenes\n  lockstep scenes stack5 > stack5.json\n", define});
}  // namespace
}  // namespace lockstep::cli
