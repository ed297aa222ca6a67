#include "commands.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <exception>
#include <sstream>
#include <stdexcept>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/world.hpp"

namespace lockstep::cli {

std::vector<Command>& commands() {
  static std::vector<Command> all;
  return all;
}

bool register_command(Command c) {
  auto& all = commands();
  all.push_back(std::move(c));
  std::sort(all.begin(), all.end(), [](const Command& a, const Command& b) { return a.name < b.name; });
  return true;
}

Scene resolve_scene(const std::string& arg) {
  const std::string name = arg.empty() ? kDefaultSceneName : arg;
  if (auto s = builtin_scene(name)) return *s;
  if (name.find('/') == std::string::npos && name.find(".json") == std::string::npos) {
    std::string names;
    for (const auto& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument("SCENE: '" + name + "' is neither a built-in scene (" + names +
                                ") nor a .json file path");
  }
  return load_scene_file(name);
}

CLI::Validator integer_in(long long lo, long long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        long long v = 0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc() || end != s.data() + s.size() || v < lo || v > hi)
          return "'" + s + "' must be an integer in " + range;
        return {};
      },
      "integer in " + range);
}

CLI::Validator one_of(const std::vector<std::string>& allowed) {
  const std::string list = join(allowed, ", ");
  return CLI::Validator(
      [allowed, list](std::string& s) -> std::string {
        if (std::find(allowed.begin(), allowed.end(), s) != allowed.end()) return {};
        return "'" + s + "' must be one of " + list;
      },
      "one of " + list);
}

std::vector<std::string> split_list(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string x; std::getline(ss, x, ',');)
    if (!x.empty()) out.push_back(x);
  return out;
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

namespace {

void print_usage() {
  std::printf("usage: lockstep COMMAND [options]   (lockstep COMMAND --help: its options, defaults and an example)\n\n"
              "commands:\n");
  for (const auto& c : commands()) std::printf("  %-10s %s\n", c.name.c_str(), c.summary.c_str());
  std::printf("\nWith no command, `lockstep run` runs the default scene on the fixed engine.\n");
}

// The option names (long form) of a command, for "unknown option" messages.
std::string option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options()) {
    if (o->get_positional() && o->get_lnames().empty()) continue;
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
  }
  return join(names, ", ");
}

// One line naming the option and what it allows.
std::string usage_error(const CLI::App& app, const CLI::ParseError& e) {
  std::string what = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
    std::string extra = what.substr(what.find(": ") == std::string::npos ? 0 : what.find(": ") + 2);
    const bool option = !extra.empty() && extra[0] == '-';
    if (option) return "unknown option " + extra + "; options: " + option_names(app);
    std::vector<std::string> positionals;
    for (const CLI::Option* o : app.get_options())
      if (o->get_positional()) positionals.push_back(o->get_name() + (o->get_items_expected_max() > 1 ? "..." : ""));
    return "unexpected argument '" + extra + "'; it takes " +
           (positionals.empty() ? std::string("no arguments") : join(positionals, " ")) + " and the options " +
           option_names(app);
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) || dynamic_cast<const CLI::ConversionError*>(&e)) {
    // "--frames: 1 required INT missing" -> "--frames needs a value: integer in [0, 10000000]"
    const std::string name = what.substr(0, what.find(':'));
    if (const CLI::Option* o = app.get_option_no_throw(name); o != nullptr) {
      std::string allowed = o->get_type_name();
      if (allowed.find(':') != std::string::npos) allowed = allowed.substr(allowed.find(':') + 1);
      return name + " needs a value: " + allowed;
    }
  }
  return what;
}

}  // namespace

int run_command_line(const std::vector<std::string>& args) {
  const std::string name = args.empty() ? "run" : args[0];
  if (name == "-h" || name == "--help" || name == "help") {
    print_usage();
    return 0;
  }
  const auto& all = commands();
  const auto it = std::find_if(all.begin(), all.end(), [&](const Command& c) { return c.name == name; });
  if (it == all.end()) {
    std::vector<std::string> names;
    for (const auto& c : all) names.push_back(c.name);
    std::fprintf(stderr, "lockstep: unknown command '%s'; commands: %s (lockstep --help)\n", name.c_str(),
                 join(names, ", ").c_str());
    return 2;
  }
  CLI::App app(it->summary, "lockstep " + it->name);
  app.footer("Example:\n" + it->example);
  app.get_formatter()->column_width(34);
  std::function<int()> run = it->define(app);
  std::vector<std::string> rest(args.empty() ? args.begin() : args.begin() + 1, args.end());
  std::reverse(rest.begin(), rest.end());  // CLI11 takes the arguments last first
  const std::string prefix = "lockstep " + it->name;
  try {
    app.parse(rest);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s (%s --help)\n", prefix.c_str(), usage_error(app, e).c_str(), prefix.c_str());
    return 2;
  }
  try {
    return run();
  } catch (const SceneError& e) {
    std::fprintf(stderr, "%s: scene error: %s\n", prefix.c_str(), e.what());
    return 2;
  } catch (const RunError& e) {
    std::fprintf(stderr, "%s: run stopped: %s\n", prefix.c_str(), e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", prefix.c_str(), e.what());
    return 2;
  }
}

}  // namespace lockstep::cli
