// The `lockstep` command: `lockstep run`, `lockstep compare`, `lockstep vectors`, ...
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "commands.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/world.hpp"

namespace {
void usage() {
  std::printf("usage: lockstep <command> [options]\n\ncommands:\n");
  for (const auto& c : lockstep::cli::commands()) std::printf("  %-58s %s\n", c.usage.c_str(), c.summary.c_str());
  std::printf("\nWith no command, `lockstep run` runs the default scene on the fixed engine.\n");
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string name = args.empty() ? "run" : args[0];
  if (!args.empty()) args.erase(args.begin());
  if (name == "-h" || name == "--help" || name == "help") { usage(); return 0; }
  for (const auto& c : lockstep::cli::commands()) {
    if (c.name != name) continue;
    try {
      return c.run(args);
    } catch (const lockstep::SceneError& e) {
      std::fprintf(stderr, "lockstep %s: scene error: %s\n", name.c_str(), e.what());
      return 2;
    } catch (const lockstep::RunError& e) {
      std::fprintf(stderr, "lockstep %s: run stopped: %s\n", name.c_str(), e.what());
      return 3;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lockstep %s: %s\n", name.c_str(), e.what());
      return 2;
    }
  }
  std::fprintf(stderr, "lockstep: unknown command '%s'\n\n", name.c_str());
  usage();
  return 2;
}
