// The `lockstep` command's subcommands. Each cmd_*.cpp registers itself with
// its CLI11 options; main.cpp parses the command line and runs the one named.
#pragma once
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::cli {

struct Command {
  std::string name;
  std::string summary;  // one line
  std::string example;  // one or more example lines, shown at the end of `lockstep NAME --help`
  // Adds the command's positionals and options to `app` (bound to state the
  // returned function owns) and returns what runs the command once the
  // command line is parsed; it returns the exit code.
  std::function<std::function<int()>(CLI::App& app)> define;
};

std::vector<Command>& commands();
bool register_command(Command c);

// SCENE: a built-in scene name or a path to a JSON scene file; empty -> the
// default scene. Throws SceneError (or std::invalid_argument) with the fix.
Scene resolve_scene(const std::string& arg);

// Validators whose messages name what is allowed ("--frames: 'x' must be an
// integer in [0, 10000000]"); CLI11 puts the option's name in front.
CLI::Validator integer_in(long long lo, long long hi);
CLI::Validator one_of(const std::vector<std::string>& allowed);

// "1 body", "2 bodies": n and the word for n.
std::string count_of(long long n, const std::string& one, const std::string& many);
// v with `digits` significant digits, without an exponent: 0.0123, 1.23, 123
// (for times such as ms/step, from tiny scenes to large ones).
std::string significant(double v, int digits = 3);

// The exit codes of every command, as --help and the README list them.
inline constexpr const char* kExitCodes =
    "exit codes: 0 success; 1 the engines disagree (compare), a replay differs (replay), a check failed (vectors verify, certify) or the "
    "accuracy is out of bounds; 2 a usage, scene or file error (the message names the option or field and the fix); "
    "3 a run stopped (an engine reported a state it cannot go on from, e.g. a non-finite value)";

// This build in words, for recordings: "lockstep 0.1.0, g++ 12.2.0, x86_64,
// optimised, commit abc123".
std::string build_text();

// Splits "a,b,c" into its non-empty names.
std::vector<std::string> split_list(const std::string& list);
std::string join(const std::vector<std::string>& v, const std::string& sep = ",");

// Parses argv (after the program name) with the registered commands and runs
// the one named; no command runs `run`. Help goes to stdout (exit 0); a usage
// error is one line on stderr naming the option and what it allows (exit 2).
int run_command_line(const std::vector<std::string>& args);

}  // namespace lockstep::cli
