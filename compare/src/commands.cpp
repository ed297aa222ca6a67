#include "commands.hpp"

#include <algorithm>
#include <stdexcept>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene_json.hpp"

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

bool Args::has_flag(const std::string& f) const { return std::find(flags.begin(), flags.end(), f) != flags.end(); }

std::string Args::get(const std::string& name, const std::string& fallback) const {
  for (auto it = options.rbegin(); it != options.rend(); ++it)
    if (it->first == name) return it->second;
  return fallback;
}

long long Args::get_int(const std::string& name, long long fallback, long long lo, long long hi) const {
  const std::string s = get(name, "");
  if (s.empty()) return fallback;
  std::size_t pos = 0;
  long long v = 0;
  try { v = std::stoll(s, &pos); } catch (const std::exception&) { pos = 0; }
  if (pos != s.size() || v < lo || v > hi)
    throw std::invalid_argument(name + ": '" + s + "' must be an integer in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "]");
  return v;
}

Args parse_args(const std::vector<std::string>& args, const std::vector<std::string>& value_options,
                const std::vector<std::string>& flag_options) {
  Args out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0 || a == "--") { out.positional.push_back(a); continue; }
    std::string key = a, value;
    const bool inline_value = a.find('=') != std::string::npos;
    if (inline_value) { key = a.substr(0, a.find('=')); value = a.substr(a.find('=') + 1); }
    if (std::find(value_options.begin(), value_options.end(), key) != value_options.end()) {
      if (!inline_value) {
        if (i + 1 >= args.size()) throw std::invalid_argument(key + ": needs a value");
        value = args[++i];
      }
      out.options.emplace_back(key, value);
    } else if (std::find(flag_options.begin(), flag_options.end(), key) != flag_options.end()) {
      out.flags.push_back(key);
    } else {
      std::string known;
      for (const auto& o : value_options) known += " " + o;
      for (const auto& o : flag_options) known += " " + o;
      throw std::invalid_argument("unknown option '" + key + "'; known:" + known);
    }
  }
  return out;
}

}  // namespace lockstep::cli
