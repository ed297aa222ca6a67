// The `lockstep` command's subcommands. Each cmd_*.cpp registers itself.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "lockstep/scene.hpp"

namespace lockstep::cli {

struct Command {
  std::string name;
  std::string usage;    // one line: "run [SCENE] [--engine E] ..."
  std::string summary;  // one line
  std::function<int(const std::vector<std::string>& args)> run;  // args after the name; returns the exit code
};

std::vector<Command>& commands();
bool register_command(Command c);

// SCENE: a built-in scene name or a path to a JSON scene file; empty -> the
// default scene. Throws SceneError (or std::invalid_argument) with the fix.
Scene resolve_scene(const std::string& arg);

// Small argument helpers: "--name value" options and flags.
struct Args {
  std::vector<std::string> positional;
  std::vector<std::pair<std::string, std::string>> options;  // in order
  std::vector<std::string> flags;
  bool has_flag(const std::string& f) const;
  std::string get(const std::string& name, const std::string& fallback) const;
  long long get_int(const std::string& name, long long fallback, long long lo, long long hi) const;
};
// value_options: the option names that take a value; any other --x is a flag.
Args parse_args(const std::vector<std::string>& args, const std::vector<std::string>& value_options,
                const std::vector<std::string>& flag_options);

}  // namespace lockstep::cli
