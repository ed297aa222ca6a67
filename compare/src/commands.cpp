#include "commands.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>
#include <stdexcept>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/recording.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/world.hpp"

const char* lockstep_build_commit();  // commit.cpp, written by compare/commit.cmake

namespace lockstep::cli {

std::string count_of(long long n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string significant(double v, int digits) {
  if (!std::isfinite(v)) return std::to_string(v);
  if (v == 0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::fabs(v))));
  const int decimals = std::max(0, digits - 1 - magnitude);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

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

std::string build_text() {
  return compare::build_description(LOCKSTEP_VERSION) + ", commit " + lockstep_build_commit();
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
  std::printf("usage: lockstep COMMAND [options]   (lockstep COMMAND --help: its options, defaults and an example)\n"
              "       lockstep --version\n\n"
              "commands:\n");
  for (const auto& c : commands()) std::printf("  %-10s %s\n", c.name.c_str(), c.summary.c_str());
  std::printf("\nWith no command, `lockstep run` runs the default scene on the fixed engine.\n\n%s.\n", kExitCodes);
}

void print_version() {
  std::printf("lockstep %s\ncommit %s\nengines %s (also: %s)\ngpu engine: %s\n", LOCKSTEP_VERSION,
              lockstep_build_commit(), join(engine_names(), ", ").c_str(), join(engine_variants(), ", ").c_str(),
              gpu_build_description().c_str());
}

// Levenshtein distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// The option of `app` nearest to `given` ("--engin" -> "--engine"), or "".
std::string nearest_option(const CLI::App& app, const std::string& given) {
  std::string key = given.substr(0, given.find('='));
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const CLI::Option* o : app.get_options())
    for (const std::string& l : o->get_lnames()) {
      const std::string name = "--" + l;
      std::size_t d = edit_distance(key, name);
      if (name.rfind(key, 0) == 0 || key.rfind(name, 0) == 0) d = std::min<std::size_t>(d, 1);  // a prefix
      if (d < best_d) { best_d = d; best = name; }
    }
  return best_d <= std::max<std::size_t>(2, key.size() / 3) ? best : "";
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
    // CLI11 took the arguments last first: put them back in command-line order.
    std::vector<std::string> words = split_list([&] {
      std::string s = extra;
      std::replace(s.begin(), s.end(), ' ', ',');
      return s;
    }());
    std::reverse(words.begin(), words.end());
    extra = join(words, " ");
    const auto first_option = std::find_if(words.begin(), words.end(), [](const std::string& w) { return w.size() > 1 && w[0] == '-'; });
    if (first_option != words.end()) {
      const std::string near = nearest_option(app, *first_option);
      return "unknown option " + *first_option + (near.empty() ? "" : "; did you mean " + near + "?") +
             " (options: " + option_names(app) + ")";
    }
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
  if (name == "--version" || name == "-V" || name == "version") {
    print_version();
    return 0;
  }
  const auto& all = commands();
  const auto it = std::find_if(all.begin(), all.end(), [&](const Command& c) { return c.name == name; });
  if (it == all.end()) {
    std::vector<std::string> names;
    for (const auto& c : all) names.push_back(c.name);
    std::string near;
    for (const std::string& n : names)
      if (edit_distance(name, n) <= 2) near = n;
    if (!name.empty() && name[0] == '-' && name != "--version") {
      // An option before any command belongs to `run` (the default command).
      const auto run_it = std::find_if(all.begin(), all.end(), [](const Command& c) { return c.name == "run"; });
      if (run_it != all.end()) {
        std::vector<std::string> with_run{"run"};
        with_run.insert(with_run.end(), args.begin(), args.end());
        return run_command_line(with_run);
      }
    }
    std::fprintf(stderr, "lockstep: unknown command '%s'%s; commands: %s (lockstep --help)\n", name.c_str(),
                 near.empty() ? "" : ("; did you mean " + near + "?").c_str(), join(names, ", ").c_str());
    return 2;
  }
  CLI::App app(it->summary, "lockstep " + it->name);
  app.footer("Example:\n" + it->example + "\n" + kExitCodes + ".");
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
