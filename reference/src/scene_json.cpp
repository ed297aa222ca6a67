// JSON scene loader, validator, writer and comparison (docs/SCENES.md).
//
// Loading is two steps: nlohmann's SAX parser builds the document through
// DomBuilder (which also rejects duplicate keys, limits nesting and turns
// syntax errors into messages with line:column and the path being parsed),
// then SceneReader walks the document, checking the type and range of every
// value as it is read. Everything is checked before anything is returned.
#include "lockstep/scene_json.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "lockstep/sdf_generators.hpp"

namespace lockstep {
namespace {

using json = nlohmann::json;

// ---------------------------------------------------------------------------
// Number text
// ---------------------------------------------------------------------------

// Shortest decimal that reads back to exactly v (std::to_chars); integral
// values below 1e15 in plain integer form. For messages and range bounds.
std::string plain_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  if (v == std::trunc(v) && std::fabs(v) < 1e15) {
    const auto i = static_cast<long long>(v);
    auto r = std::to_chars(buf, buf + sizeof buf, i);
    std::string s(buf, r.ptr);
    if (i == 0 && std::signbit(v)) s = "-0";
    return s;
  }
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// As plain_number, but always readable as a JSON float (so -0.0 keeps its
// sign and 2.0 stays 2.0): the writer's form. Finite v only.
std::string json_number(double v) {
  std::string s = plain_number(v);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

// ---------------------------------------------------------------------------
// Paths and errors
// ---------------------------------------------------------------------------

std::string child(const std::string& path, std::string_view key) {
  if (path.empty()) return std::string(key);
  std::string s = path;
  s += '.';
  s += key;
  return s;
}

std::string index_path(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string with_article(const char* type_name) {
  const std::string t = type_name;
  if (t == "null") return "null";
  if (t == "object" || t == "array") return "an " + t;
  return "a " + t;
}

// A key or string as JSON writes it: quoted, with control characters escaped.
std::string json_quoted(const std::string& s) { return json(s).dump(-1, ' ', false, json::error_handler_t::replace); }

// The value as the document wrote it (truncated for long arrays/strings).
std::string shown(const json& j) {
  std::string s = j.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      const std::size_t sub = diag + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, sub});
      diag = up;
    }
  }
  return row[b.size()];
}

// Line and column (both 1-based, column in bytes) of the byte at `offset`.
std::pair<std::size_t, std::size_t> line_column(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return {line, offset - line_start + 1};
}

std::string prefix(std::string_view source) {
  return source.empty() ? std::string() : std::string(source) + ": ";
}

// ---------------------------------------------------------------------------
// Ranges
// ---------------------------------------------------------------------------

struct Range {
  double lo, hi;
  bool lo_open, hi_open;
  const char* unit;  // "" for dimensionless
  const char* hint;  // how to fix; nullptr for the generic hint
};

constexpr double kQ16Limit = 32768.0;
constexpr double kCoordLimit = 30000.0;

std::string range_text(const Range& r) {
  std::string s = r.lo_open ? "(" : "[";
  s += plain_number(r.lo) + ", " + plain_number(r.hi);
  s += r.hi_open ? ")" : "]";
  if (*r.unit != '\0') {
    s += ' ';
    s += r.unit;
  }
  return s;
}

bool in_range(double v, const Range& r) {
  const bool lo_ok = r.lo_open ? v > r.lo : v >= r.lo;
  const bool hi_ok = r.hi_open ? v < r.hi : v <= r.hi;
  return lo_ok && hi_ok;
}

// Body and ground.
constexpr Range kHalfExtent{1.0 / 256.0, 1024.0, false, false, "m",
                            "each half extent is half the box's size along that axis"};
constexpr Range kMass{0.0, 10000.0, true, false, "kg",
                      "use \"static\": true for an immovable body"};
constexpr Range kStaticMass{0.0, 10000.0, false, false, "kg",
                            "a static body's mass is ignored; omit it or give 0"};
constexpr Range kPosition{-kCoordLimit, kCoordLimit, false, false, "m",
                          "move it closer to the origin: positions must keep a margin inside "
                          "the Q16.16 range |x| < 32768 m"};
constexpr Range kQuatComponent{-2.0, 2.0, false, false, "",
                               "the quaternion [w, x, y, z] must have norm in [0.5, 2]; "
                               "[1, 0, 0, 0] is no rotation"};
constexpr Range kVelocity{-1000.0, 1000.0, false, false, "m/s", "each component is limited"};
constexpr Range kAngularVelocity{-1000.0, 1000.0, false, false, "rad/s",
                                 "each component is limited"};
constexpr Range kRestitution{0.0, 1.0, false, false, "",
                             "0 is perfectly inelastic, 1 perfectly elastic"};
constexpr Range kFriction{0.0, 4.0, false, false, "", "0 is frictionless; 0.5 is typical"};
constexpr Range kHeight{-kCoordLimit, kCoordLimit, false, false, "m",
                        "heights must keep a margin inside the Q16.16 range |x| < 32768 m"};
// SDF.
constexpr Range kSdfBound{-kCoordLimit, kCoordLimit, false, false, "m",
                          "the volume must lie inside the Q16.16 range with a margin"};
constexpr Range kSdfValue{-kCoordLimit, kCoordLimit, false, false, "m",
                          "SDF values are distances: positive in free space, negative in the "
                          "solid; clamp far values"};
constexpr Range kGenRadius{1.0 / 256.0, kCoordLimit, false, false, "m", "give a positive radius"};
constexpr Range kGenCoord{-kCoordLimit, kCoordLimit, false, false, "m",
                          "keep it inside the Q16.16 range with a margin"};
constexpr double kMinSdfSpacing = 1.0 / 256.0;
constexpr std::size_t kMaxSdfs = 256;
constexpr int kMaxDepth = 20;

// Every Constants field, in declaration order (the writer's order).
struct ConstSpec {
  const char* name;
  double Constants::*real = nullptr;
  int Constants::*integer = nullptr;
  Vec3d Constants::*vec = nullptr;
  Range range{};  // for real and vec; for integer: lo, hi used as integers
};

const std::vector<ConstSpec>& constant_specs() {
  using C = Constants;
  auto R = [](const char* n, double C::*m, Range r) { return ConstSpec{n, m, nullptr, nullptr, r}; };
  auto I = [](const char* n, int C::*m, double lo, double hi, const char* hint) {
    return ConstSpec{n, nullptr, m, nullptr, Range{lo, hi, false, false, "", hint}};
  };
  static const std::vector<ConstSpec> specs = {
      R("dt", &C::dt,
        {1.0 / 65536.0, 0.1, false, false, "s",
         "60 Hz is 0.016666666666666666; a step below 2^-16 s is 0 in Q16.16"}),
      ConstSpec{"gravity", nullptr, nullptr, &C::gravity,
                {-1000.0, 1000.0, false, false, "m/s^2", "Earth's gravity is [0, -9.81, 0]"}},
      R("linear_damping", &C::linear_damping,
        {0.0, 1000.0, false, false, "1/s", "the default is 0.005; 0 disables it"}),
      R("angular_damping", &C::angular_damping,
        {0.0, 1000.0, false, false, "1/s", "the default is 0.02; 0 disables it"}),
      R("cell_size", &C::cell_size,
        {0.25, 1024.0, false, false, "m", "use about twice the largest body's size"}),
      R("slop", &C::slop, {0.0, 1.0, false, false, "m", "the default is 0.001"}),
      R("baumgarte", &C::baumgarte, {0.0, 1.0, false, false, "", "the default is 1"}),
      I("solver_iterations", &C::solver_iterations, 1, 64, "the default is 8"),
      R("contact_tolerance", &C::contact_tolerance,
        {0.0, 1.0, false, false, "m", "the default is 0.01"}),
      R("converged_speed", &C::converged_speed,
        {0.0, 100.0, false, false, "m/s", "the default is 0 (every solver pass in full); 0.03125 skips converged visits"}),
      R("kp", &C::kp, {0.0, 1000.0, false, false, "rad/s", "the default is 30"}),
      R("kd", &C::kd, {0.0, 1000.0, false, false, "1/s", "the default is 10"}),
      R("speed_factor_min", &C::speed_factor_min, {0.0, 100.0, false, false, "", "the default is 0.5"}),
      R("speed_factor_max", &C::speed_factor_max, {0.0, 100.0, false, false, "", "the default is 2"}),
      R("support_normal_min", &C::support_normal_min, {0.0, 1.0, false, false, "", "the default is 0.7"}),
      R("align_fine", &C::align_fine, {0.0, 1.0, true, false, "", "the default is 0.998"}),
      R("align_good", &C::align_good, {0.0, 1.0, true, false, "", "the default is 0.99"}),
      R("align_fair", &C::align_fair, {0.0, 1.0, true, false, "", "the default is 0.95"}),
      R("damp_fine", &C::damp_fine, {0.0, 1.0, false, false, "", "the default is 0.4"}),
      R("damp_good", &C::damp_good, {0.0, 1.0, false, false, "", "the default is 0.7"}),
      R("damp_fair", &C::damp_fair, {0.0, 1.0, false, false, "", "the default is 0.85"}),
      R("rest_speed", &C::rest_speed, {0.0, 100.0, false, false, "m/s", "the default is 0.2"}),
      R("restitution_min_speed", &C::restitution_min_speed,
        {0.0, 100.0, false, false, "m/s", "the default is 0.5"}),
      R("settle_speed", &C::settle_speed, {0.0, 100.0, false, false, "m/s", "the default is 0.3"}),
      R("settle_damping", &C::settle_damping, {0.0, 1.0, false, false, "", "the default is 0.1"}),
      R("sleep_linear", &C::sleep_linear, {0.0, 100.0, false, false, "m/s", "the default is 0.05"}),
      R("sleep_angular", &C::sleep_angular, {0.0, 100.0, false, false, "rad/s", "the default is 0.05"}),
      R("sleep_alignment", &C::sleep_alignment, {0.0, 1.0, true, false, "", "the default is 0.99"}),
      I("drowsy_frames", &C::drowsy_frames, 1, 100000, "the default is 10"),
      R("drowsy_damping", &C::drowsy_damping, {0.0, 1.0, false, false, "", "the default is 0.5"}),
      I("sleep_frames", &C::sleep_frames, 1, 100000, "the default is 30"),
      R("wake_speed", &C::wake_speed, {0.0, 100.0, false, false, "m/s", "the default is 0.1"}),
      R("wake_penetration", &C::wake_penetration, {0.0, 10.0, false, false, "m", "the default is 0.02"}),
      R("wake_support_distance", &C::wake_support_distance, {0.0, 10.0, false, false, "m", "the default is 0.005"}),
  };
  return specs;
}

// The "pair_contacts" names, in PairModel order.
constexpr const char* kPairModelNames[] = {"oriented_box", "aabb"};
const char* pair_model_name(PairModel m) { return kPairModelNames[m == PairModel::kOrientedBox ? 0 : 1]; }

constexpr const char* kEffectNames[] = {"gravity", "damping", "ground", "contacts", "friction",
                                        "restitution", "settling", "sleep", "sdf"};
bool Effects::*const kEffectMembers[] = {&Effects::gravity,  &Effects::damping,     &Effects::ground,
                                         &Effects::contacts, &Effects::friction,    &Effects::restitution,
                                         &Effects::settling, &Effects::sleep,       &Effects::sdf};

// ---------------------------------------------------------------------------
// DomBuilder: nlohmann SAX -> json, with duplicate-key, depth and error handling
// ---------------------------------------------------------------------------

class DomBuilder {
 public:
  DomBuilder(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  json root;

  bool null() { add(json(nullptr)); return true; }
  bool boolean(bool b) { add(json(b)); return true; }
  bool number_integer(json::number_integer_t v) { add(json(v)); return true; }
  bool number_unsigned(json::number_unsigned_t v) { add(json(v)); return true; }
  bool number_float(json::number_float_t v, const json::string_t& /*text*/) { add(json(v)); return true; }
  bool string(json::string_t& s) { add(json(std::move(s))); return true; }
  bool binary(json::binary_t& /*b*/) { add(json(nullptr)); return true; }  // not produced by the JSON reader
  bool start_object(std::size_t /*n*/) { push(add(json::object())); return true; }
  bool key(json::string_t& k) {
    Frame& f = stack_.back();
    if (f.container->contains(k)) {
      const std::string path = child(current_path_of_container(), k);
      throw SceneError(prefix(source_) + path + ": duplicate key " + json_quoted(k) +
                           ": each key may appear once per object (remove one of them)",
                       path);
    }
    f.key = std::move(k);
    f.has_key = true;
    return true;
  }
  bool end_object() { stack_.pop_back(); return true; }
  bool start_array(std::size_t /*n*/) { push(add(json::array())); return true; }
  bool end_array() { stack_.pop_back(); return true; }

  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& ex) {
    // position counts the bytes read, the offending one included. A number
    // that overflows is reported at its first character.
    std::size_t offset = position > 0 ? position - 1 : 0;
    if (ex.id == 406 && last_token.size() <= position) offset = position - last_token.size();
    const auto [line, col] = line_column(text_, offset);
    const std::string where = prefix(source_).empty()
                                  ? "line " + std::to_string(line) + ", column " + std::to_string(col) + ": "
                                  : std::string(source_) + ":" + std::to_string(line) + ":" +
                                        std::to_string(col) + ": ";
    const std::string path = current_path();
    if (ex.id == 406) {  // number overflow: a literal beyond the double range
      throw SceneError(where + (path.empty() ? std::string() : path + ": ") + "the number " + last_token +
                           " is not finite (it overflows a double): must be a finite number in the "
                           "field's range (see docs/SCENES.md)",
                       path);
    }
    std::string detail = ex.what();
    // A bare NaN or Infinity (JSON has neither): say so rather than "syntax error".
    {
      // The word around the offending byte (last_token may hold text before it).
      std::size_t start = std::min(offset, text_.size());
      while (start > 0 && (std::isalpha(static_cast<unsigned char>(text_[start - 1])) || text_[start - 1] == '-' ||
                           text_[start - 1] == '+'))
        --start;
      std::size_t end = start;
      while (end < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[end])) || text_[end] == '-' ||
                                    text_[end] == '+'))
        ++end;
      std::string word(text_.substr(start, end - start));
      std::string lower = word;
      for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      const std::string bare = lower.empty() || (lower[0] != '-' && lower[0] != '+') ? lower : lower.substr(1);
      if (bare == "nan" || bare == "inf" || bare == "infinity") {
        const auto [wl, wc] = line_column(text_, start);
        const std::string at = prefix(source_).empty()
                                   ? "line " + std::to_string(wl) + ", column " + std::to_string(wc) + ": "
                                   : std::string(source_) + ":" + std::to_string(wl) + ":" + std::to_string(wc) + ": ";
        throw SceneError(at + (path.empty() ? std::string() : path + ": ") + word +
                             " is not allowed: NaN and infinities are not numbers in JSON, and every number in a "
                             "scene must be finite; write a finite number in the field's range (docs/SCENES.md)",
                         path);
      }
    }
    // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..."
    if (auto p = detail.find("syntax error"); p != std::string::npos) {
      detail = detail.substr(p);
    } else if (auto q = detail.find("] "); q != std::string::npos) {
      detail = detail.substr(q + 2);
    }
    if (text_.find_first_not_of(" \t\r\n") == std::string_view::npos) {
      detail = "the document is empty: a scene is a JSON object {\"format\": \"lockstep-scene\", ...}";
    }
    throw SceneError(where + "JSON syntax error" + (path.empty() ? std::string() : " near " + path) +
                         ": " + detail + " (fix the JSON syntax at this line and column)",
                     path);
  }

 private:
  struct Frame {
    json* container;
    std::string key;
    bool has_key = false;
  };

  json* add(json&& v) {
    if (stack_.empty()) {
      root = std::move(v);
      return &root;
    }
    Frame& f = stack_.back();
    if (f.container->is_array()) {
      f.container->push_back(std::move(v));
      return &f.container->back();
    }
    json& slot = (*f.container)[f.key];
    slot = std::move(v);
    return &slot;
  }

  void push(json* container) {
    if (stack_.size() >= static_cast<std::size_t>(kMaxDepth)) {
      const std::string path = current_path(/*last_has_open_child=*/true);
      throw SceneError(prefix(source_) + (path.empty() ? std::string() : path + ": ") +
                           "nested more than " + std::to_string(kMaxDepth) +
                           " levels deep: a scene never needs that (check the brackets)",
                       path);
    }
    stack_.push_back(Frame{container, {}, false});
  }

  // Path of the innermost open container.
  std::string current_path_of_container() const {
    std::string p;
    for (std::size_t i = 0; i + 1 < stack_.size(); ++i) p = step(p, stack_[i], true);
    return p;
  }
  // Path of the value being read (or just read).
  std::string current_path(bool last_has_open_child = false) const {
    std::string p;
    for (std::size_t i = 0; i < stack_.size(); ++i) {
      p = step(p, stack_[i], last_has_open_child || i + 1 < stack_.size());
    }
    return p;
  }
  // One step down from frame f: to its open child container (the last
  // element of an array) or to the value being read (the next element).
  static std::string step(const std::string& p, const Frame& f, bool open_child) {
    if (f.container->is_array()) {
      const std::size_t n = f.container->size();
      return index_path(p, open_child && n > 0 ? n - 1 : n);
    }
    if (f.has_key) return child(p, f.key);
    return p;
  }

  std::string_view text_;
  std::string_view source_;
  std::vector<Frame> stack_;
};

// ---------------------------------------------------------------------------
// SceneReader: the document -> Scene, every value checked
// ---------------------------------------------------------------------------

class SceneReader {
 public:
  explicit SceneReader(std::string_view source) : source_(source) {}

  Scene read(const json& root) {
    Scene s;
    if (!root.is_object()) {
      fail("", "the scene must be a JSON object {\"format\": \"lockstep-scene\", \"version\": 1, ...}, got " +
                   with_article(root.type_name()) + " (wrap the scene in { })");
    }
    check_keys(root, "", {"format", "version", "name", "frames", "pair_contacts", "effects", "constants", "ground",
                          "bodies", "sdfs"});
    const json* format = find(root, "format");
    if (format == nullptr) {
      fail("format", "missing required key \"format\": a scene file starts with \"format\": \"lockstep-scene\", "
                     "\"version\": 1");
    }
    if (!format->is_string() || format->get_ref<const std::string&>() != kSceneFormat) {
      fail("format", shown(*format) + " is not a lockstep scene: must be \"lockstep-scene\" (set \"format\": "
                     "\"lockstep-scene\")");
    }
    const json* version = find(root, "version");
    if (version == nullptr) {
      fail("version", "missing required key \"version\": add \"version\": 1");
    }
    if (!version->is_number_integer() || version->get<std::int64_t>() != kSceneVersion) {
      fail("version", shown(*version) + " is not supported: must be 1 (this build reads lockstep-scene "
                      "version 1 only; set \"version\": 1)");
    }
    if (const json* j = find(root, "name")) s.name = string(*j, "name");
    if (const json* j = find(root, "frames")) {
      s.frames = static_cast<int>(integer(*j, "frames", 1, kMaxSceneFrames, "", "the number of steps to run"));
    }
    if (const json* j = find(root, "pair_contacts")) s.pair_contacts = pair_model(*j, "pair_contacts");
    if (const json* j = find(root, "effects")) read_effects(*j, "effects", s.effects);
    if (const json* j = find(root, "constants")) read_constants(*j, "constants", s.constants);
    if (const json* j = find(root, "ground")) read_ground(*j, "ground", s.ground);
    if (const json* j = find(root, "bodies")) {
      const json& arr = expect_array(*j, "bodies", "an array of bodies [{\"position\": [x, y, z], ...}, ...]");
      if (arr.size() > kMaxSceneBodies) {
        fail("bodies", std::to_string(arr.size()) + " bodies given: at most 1000000 are allowed (split the scene)");
      }
      s.bodies.resize(arr.size());
      for (std::size_t i = 0; i < arr.size(); ++i) read_body(arr[i], index_path("bodies", i), s.bodies[i]);
    }
    if (const json* j = find(root, "sdfs")) {
      const json& arr = expect_array(*j, "sdfs", "an array of SDF volumes");
      if (arr.size() > kMaxSdfs) {
        fail("sdfs", std::to_string(arr.size()) + " SDF volumes given: at most " + std::to_string(kMaxSdfs) +
                         " are allowed (merge volumes)");
      }
      s.sdfs.resize(arr.size());
      for (std::size_t i = 0; i < arr.size(); ++i) read_sdf(arr[i], index_path("sdfs", i), s.sdfs[i]);
    }
    return s;
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw SceneError(prefix(source_) + (path.empty() ? std::string() : path + ": ") + message, path);
  }

  static const json* find(const json& obj, std::string_view key) {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  const json& require(const json& obj, const std::string& path, const char* key, const std::string& how) const {
    const json* j = find(obj, key);
    if (j == nullptr) fail(child(path, key), "missing required key \"" + std::string(key) + "\": " + how);
    return *j;
  }

  void check_keys(const json& obj, const std::string& path, std::initializer_list<std::string_view> allowed) const {
    check_keys_in(obj, path, allowed, nullptr);
  }

  // Rejects the first key of obj not in allowed, suggesting the nearest one.
  // what_list: how to name the allowed keys (nullptr: list them).
  template <class Names>
  void check_keys_in(const json& obj, const std::string& path, const Names& allowed, const char* what_list) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      const std::string& k = it.key();
      if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
      std::string list, best;
      std::size_t best_d = std::numeric_limits<std::size_t>::max();
      for (std::string_view a : allowed) {
        if (!list.empty()) list += ", ";
        list += a;
        const std::size_t d = edit_distance(k, a);
        if (d < best_d) {
          best_d = d;
          best = std::string(a);
        }
      }
      std::string msg = "unknown key " + json_quoted(k) + ": " + (what_list ? std::string(what_list) : "allowed keys here are " + list);
      if (best_d <= std::max<std::size_t>(2, k.size() / 3)) {
        msg += " (did you mean \"" + best + "\"? keys are case-sensitive)";
      } else {
        msg += " (remove it or fix its spelling)";
      }
      fail(child(path, k), msg);
    }
  }

  const json& expect_object(const json& j, const std::string& path, const std::string& what) const {
    if (!j.is_object()) fail(path, shown(j) + " must be " + what + ", got " + with_article(j.type_name()));
    return j;
  }
  const json& expect_array(const json& j, const std::string& path, const std::string& what) const {
    if (!j.is_array()) fail(path, shown(j) + " must be " + what + ", got " + with_article(j.type_name()));
    return j;
  }

  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, shown(j) + " must be a string, got " + with_article(j.type_name()));
    return j.get<std::string>();
  }

  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) {
      fail(path, shown(j) + " must be true or false, got " + with_article(j.type_name()) +
                     " (write true or false without quotes)");
    }
    return j.get<bool>();
  }

  std::int64_t integer(const json& j, const std::string& path, std::int64_t lo, std::int64_t hi, const char* unit,
                       const char* hint) const {
    const std::string allowed = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" +
                                (*unit ? std::string(" ") + unit : std::string());
    const std::string fix = std::string(" (") + hint + ")";
    bool ok = false;
    std::int64_t v = 0;
    if (j.is_number_unsigned()) {
      const auto u = j.get<std::uint64_t>();
      ok = u <= static_cast<std::uint64_t>(hi) && static_cast<std::int64_t>(u) >= lo;
      v = ok ? static_cast<std::int64_t>(u) : 0;
    } else if (j.is_number_integer()) {
      v = j.get<std::int64_t>();
      ok = v >= lo && v <= hi;
    } else if (j.is_number_float()) {
      const double d = j.get<double>();
      if (!(std::isfinite(d) && d == std::trunc(d))) fail(path, shown(j) + " must be " + allowed + fix);
      ok = d >= static_cast<double>(lo) && d <= static_cast<double>(hi);
      v = ok ? static_cast<std::int64_t>(d) : 0;
    } else {
      fail(path, shown(j) + " must be " + allowed + ", got " + with_article(j.type_name()) + fix);
    }
    if (!ok) fail(path, shown(j) + " is out of range: must be " + allowed + fix);
    return v;
  }

  // A real value: a JSON number or {"raw": R}.
  double real(const json& j, const std::string& path, const Range& r) const {
    double v = 0.0;
    std::string text;
    if (j.is_object()) {
      check_keys(j, path, {"raw"});
      const json* raw = find(j, "raw");
      if (raw == nullptr) {
        fail(child(path, "raw"), "missing key \"raw\": an exact value is written {\"raw\": R} with R an int32, "
                                 "meaning R/65536");
      }
      const std::string int32_range = "an integer in [-2147483648, 2147483647] (the raw Q16.16 value R means R/65536)";
      if (!raw->is_number_integer()) {
        fail(path, "{\"raw\":" + shown(*raw) + "}: the raw value must be " + int32_range);
      }
      std::int64_t R = 0;
      if (raw->is_number_unsigned() &&
          raw->get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max())) {
        fail(path, "{\"raw\":" + shown(*raw) + "}: the raw value is out of range: must be " + int32_range);
      }
      R = raw->get<std::int64_t>();
      if (R < std::numeric_limits<std::int32_t>::min() || R > std::numeric_limits<std::int32_t>::max()) {
        fail(path, "{\"raw\":" + shown(*raw) + "}: the raw value is out of range: must be " + int32_range);
      }
      v = static_cast<double>(R) / 65536.0;
      if (!in_range(v, r)) text = "{\"raw\":" + std::to_string(R) + "} (= " + plain_number(v) + ")";
    } else if (j.is_number()) {
      v = j.get<double>();
      if (!in_range(v, r)) text = shown(j);
    } else {
      fail(path, shown(j) + " must be a number in " + range_text(r) +
                     " (or {\"raw\": R} for exactly R/65536), got " + with_article(j.type_name()));
    }
    check_range(path, v, text, r);
    return v;
  }

  // text: the value as written (only needed, and only computed, when v is out of range).
  void check_range(const std::string& path, double v, const std::string& text, const Range& r) const {
    if (in_range(v, r)) return;  // false for NaN
    if (!std::isfinite(v)) fail(path, text + " is not a finite number: must be in " + range_text(r));
    std::string msg = text;
    if (std::fabs(v) >= kQ16Limit) {
      msg += " is outside the Q16.16 range |x| < 32768";
      if (*r.unit) msg += std::string(" ") + r.unit;
      msg += ": must be in " + range_text(r);
    } else {
      msg += " is out of range: must be in " + range_text(r);
    }
    msg += " (";
    msg += r.hint ? r.hint : "change it to a value in that range";
    msg += ")";
    fail(path, msg);
  }

  void reals(const json& j, const std::string& path, double* out, std::size_t n, const Range& r,
             const char* shape) const {
    if (!j.is_array() || j.size() != n) {
      const std::string got = j.is_array() ? std::to_string(j.size()) + " element" + (j.size() == 1 ? "" : "s")
                                           : with_article(j.type_name());
      fail(path, "expected an array of " + std::to_string(n) + " numbers " + shape + ", got " + got);
    }
    for (std::size_t i = 0; i < n; ++i) out[i] = real(j[i], index_path(path, i), r);
  }

  Vec3d vec3(const json& j, const std::string& path, const Range& r) const {
    double v[3];
    reals(j, path, v, 3, r, "[x, y, z]");
    return {v[0], v[1], v[2]};
  }

  void read_material(const json& j, const std::string& path, Material& m) const {
    expect_object(j, path, "an object {\"restitution\": e, \"friction\": mu}");
    check_keys(j, path, {"restitution", "friction"});
    if (const json* v = find(j, "restitution")) m.restitution = real(*v, child(path, "restitution"), kRestitution);
    if (const json* v = find(j, "friction")) m.friction = real(*v, child(path, "friction"), kFriction);
  }

  // "pair_contacts": how body pairs touch (docs/SPEC.md 2.2, 2.4).
  PairModel pair_model(const json& j, const std::string& path) const {
    const std::string v = string(j, path);
    if (v == kPairModelNames[0]) return PairModel::kOrientedBox;
    if (v == kPairModelNames[1]) return PairModel::kAabb;
    fail(path, shown(j) + " is not a pair contact model: must be \"oriented_box\" (eqs 100-106, the default) or "
               "\"aabb\" (the source's single AABB point, eqs 38-43, 85)");
  }

  void read_effects(const json& j, const std::string& path, Effects& e) const {
    expect_object(j, path, "an object of booleans {\"gravity\": true, ...}");
    check_keys(j, path, {"gravity", "damping", "ground", "contacts", "friction", "restitution", "settling",
                         "sleep", "sdf"});
    for (std::size_t i = 0; i < std::size(kEffectNames); ++i) {
      if (const json* v = find(j, kEffectNames[i])) e.*kEffectMembers[i] = boolean(*v, child(path, kEffectNames[i]));
    }
  }

  void read_constants(const json& j, const std::string& path, Constants& c) const {
    expect_object(j, path, "an object {\"dt\": 0.016666666666666666, ...} of constants to override");
    static const std::vector<std::string_view> names = [] {
      std::vector<std::string_view> n;
      for (const ConstSpec& spec : constant_specs()) n.emplace_back(spec.name);
      return n;
    }();
    check_keys_in(j, path, names, "not a constant: keys are the C++ names of lockstep::Constants, listed in "
                                  "docs/SCENES.md");
    for (const ConstSpec& s : constant_specs()) {
      const json* v = find(j, s.name);
      if (v == nullptr) continue;
      const std::string p = child(path, s.name);
      if (s.real) {
        c.*s.real = real(*v, p, s.range);
      } else if (s.integer) {
        c.*s.integer = static_cast<int>(integer(*v, p, static_cast<std::int64_t>(s.range.lo),
                                                static_cast<std::int64_t>(s.range.hi), "", s.range.hint));
      } else {
        c.*s.vec = vec3(*v, p, s.range);
      }
    }
    // Rules between constants, checked once each is in range (the error names
    // the first field of its rule).
    for (auto [name, member] : {std::pair{"linear_damping", &Constants::linear_damping},
                                std::pair{"angular_damping", &Constants::angular_damping}}) {
      if (!(c.*member < 1.0 / c.dt)) {
        fail(child(path, name), plain_number(c.*member) + " is out of range: must be in [0, 1/dt) = [0, " +
                                    plain_number(1.0 / c.dt) + ") 1/s for dt = " + plain_number(c.dt) +
                                    " s (lower the damping or the time step)");
      }
    }
    if (c.speed_factor_min > c.speed_factor_max) {
      fail(child(path, "speed_factor_min"),
           plain_number(c.speed_factor_min) + " is greater than speed_factor_max = " +
               plain_number(c.speed_factor_max) + ": must be <= speed_factor_max (swap or adjust them)");
    }
    if (c.drowsy_frames > c.sleep_frames) {
      fail(child(path, "drowsy_frames"),
           std::to_string(c.drowsy_frames) + " is greater than sleep_frames = " + std::to_string(c.sleep_frames) +
               ": must be <= sleep_frames (a body is drowsy before it sleeps; lower drowsy_frames or raise "
               "sleep_frames)");
    }
  }

  void read_ground(const json& j, const std::string& path, GroundDesc& g) const {
    expect_object(j, path, "an object {\"present\": true, \"height\": 0, \"material\": {...}}");
    check_keys(j, path, {"present", "height", "material"});
    if (const json* v = find(j, "present")) g.present = boolean(*v, child(path, "present"));
    if (const json* v = find(j, "height")) g.height = real(*v, child(path, "height"), kHeight);
    if (const json* v = find(j, "material")) read_material(*v, child(path, "material"), g.material);
  }

  void read_body(const json& j, const std::string& path, BodyDesc& b) const {
    expect_object(j, path, "an object {\"position\": [x, y, z], ...}");
    check_keys(j, path, {"half_extents", "mass", "position", "orientation", "velocity", "angular_velocity",
                         "material", "static", "asleep"});
    if (const json* v = find(j, "static")) b.is_static = boolean(*v, child(path, "static"));
    if (const json* v = find(j, "asleep")) b.asleep = boolean(*v, child(path, "asleep"));
    if (const json* v = find(j, "half_extents")) b.half_extents = vec3(*v, child(path, "half_extents"), kHalfExtent);
    if (const json* v = find(j, "mass")) b.mass = real(*v, child(path, "mass"), b.is_static ? kStaticMass : kMass);
    b.position = vec3(require(j, path, "position", "give the centre as \"position\": [x, y, z] in m"),
                      child(path, "position"), kPosition);
    if (const json* v = find(j, "orientation")) {
      const std::string p = child(path, "orientation");
      double q[4];
      reals(*v, p, q, 4, kQuatComponent, "[w, x, y, z]");
      const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      if (!(n >= 0.5 && n <= 2.0)) {
        fail(p, shown(*v) + " has norm " + plain_number(n) +
                    ": the norm must be in [0.5, 2] (give a unit quaternion [w, x, y, z]; [1, 0, 0, 0] is "
                    "no rotation)");
      }
      b.orientation = {q[0], q[1], q[2], q[3]};
    }
    if (const json* v = find(j, "velocity")) b.velocity = vec3(*v, child(path, "velocity"), kVelocity);
    if (const json* v = find(j, "angular_velocity")) {
      b.angular_velocity = vec3(*v, child(path, "angular_velocity"), kAngularVelocity);
    }
    if (const json* v = find(j, "material")) read_material(*v, child(path, "material"), b.material);
  }

  void read_sdf(const json& j, const std::string& path, SdfDesc& s) const {
    expect_object(j, path, "an object {\"name\", \"min\", \"max\", \"resolution\", \"values\" or \"generator\"}");
    check_keys(j, path, {"name", "min", "max", "resolution", "values", "generator", "material"});
    if (const json* v = find(j, "name")) s.name = string(*v, child(path, "name"));
    s.min = vec3(require(j, path, "min", "give the box's low corner \"min\": [x, y, z] in m"), child(path, "min"),
                 kSdfBound);
    s.max = vec3(require(j, path, "max", "give the box's high corner \"max\": [x, y, z] in m"), child(path, "max"),
                 kSdfBound);
    const double lo[3] = {s.min.x, s.min.y, s.min.z};
    const double hi[3] = {s.max.x, s.max.y, s.max.z};
    for (std::size_t a = 0; a < 3; ++a) {
      if (!(hi[a] > lo[a])) {
        fail(index_path(child(path, "max"), a),
             plain_number(hi[a]) + " must be greater than min[" + std::to_string(a) + "] = " + plain_number(lo[a]) +
                 " (the box [min, max] must have positive size on every axis)");
      }
    }
    const std::string rpath = child(path, "resolution");
    const json& res = require(j, path, "resolution", "give the sample counts \"resolution\": [nx, ny, nz]");
    if (!res.is_array() || res.size() != 3) {
      const std::string got = res.is_array() ? std::to_string(res.size()) + " elements" : with_article(res.type_name());
      fail(rpath, "expected an array of 3 integers [nx, ny, nz], got " + got);
    }
    int n[3];
    for (std::size_t a = 0; a < 3; ++a) {
      n[a] = static_cast<int>(integer(res[a], index_path(rpath, a), 2, kMaxSdfResolution, "samples",
                                      "each axis needs 2 to 256 samples"));
    }
    for (std::size_t a = 0; a < 3; ++a) {
      const double spacing = (hi[a] - lo[a]) / static_cast<double>(n[a] - 1);
      if (!(spacing >= kMinSdfSpacing)) {
        fail(index_path(rpath, a), std::to_string(n[a]) + " samples over " + plain_number(hi[a] - lo[a]) +
                                       " m give a spacing of " + plain_number(spacing) +
                                       " m: the spacing (max - min) / (n - 1) must be at least 0.00390625 m "
                                       "(lower the resolution or enlarge the box)");
      }
    }
    s.nx = n[0];
    s.ny = n[1];
    s.nz = n[2];
    const std::int64_t count = std::int64_t{n[0]} * n[1] * n[2];
    if (count > kMaxSdfValues) {  // cannot happen with n <= 256, kept as the documented rule
      fail(rpath, std::to_string(count) + " samples: at most 16777216 (2^24) are allowed (lower the resolution)");
    }
    if (const json* v = find(j, "material")) read_material(*v, child(path, "material"), s.material);
    const json* values = find(j, "values");
    const json* gen = find(j, "generator");
    if (values != nullptr && gen != nullptr) {
      fail(child(path, "generator"), "give either \"values\" or \"generator\", not both (remove one)");
    }
    if (values == nullptr && gen == nullptr) {
      fail(child(path, "values"), "missing required key \"values\": give nx*ny*nz = " + std::to_string(count) +
                                      " sample values, or a \"generator\"");
    }
    const SdfGrid grid{s.min, s.max, s.nx, s.ny, s.nz};
    if (values != nullptr) {
      const std::string vpath = child(path, "values");
      expect_array(*values, vpath, "an array of nx*ny*nz numbers");
      if (static_cast<std::int64_t>(values->size()) != count) {
        fail(vpath, std::to_string(values->size()) + " values given, resolution " + std::to_string(n[0]) + "x" +
                        std::to_string(n[1]) + "x" + std::to_string(n[2]) + " needs " + std::to_string(count) +
                        " (index i + nx*(j + ny*k); fix the resolution or the values)");
      }
      s.values.resize(values->size());
      for (std::size_t i = 0; i < values->size(); ++i) s.values[i] = real((*values)[i], index_path(vpath, i), kSdfValue);
    } else {
      const std::string gpath = child(path, "generator");
      expect_object(*gen, gpath, "an object {\"type\": \"bowl\" or \"terrain\", ...}");
      const json& type = require(*gen, gpath, "type", "give \"type\": \"bowl\" or \"type\": \"terrain\"");
      const std::string tpath = child(gpath, "type");
      if (!type.is_string()) fail(tpath, shown(type) + " must be \"bowl\" or \"terrain\", got " + with_article(type.type_name()));
      const std::string& t = type.get_ref<const std::string&>();
      std::string name = s.name;
      if (t == "bowl") {
        check_keys(*gen, gpath, {"type", "center", "radius"});
        BowlParams bowl;
        bowl.center = vec3(require(*gen, gpath, "center", "give the sphere's centre (the middle of the rim) "
                                                          "\"center\": [x, y, z] in m"),
                           child(gpath, "center"), kGenCoord);
        bowl.radius = real(require(*gen, gpath, "radius", "give the bowl's radius in m"), child(gpath, "radius"),
                           kGenRadius);
        s = make_bowl_sdf(grid, bowl, std::move(name), s.material);
      } else if (t == "terrain") {
        check_keys(*gen, gpath, {"type", "base_height", "bumps"});
        TerrainParams terrain;
        if (const json* v = find(*gen, "base_height")) {
          terrain.base_height = real(*v, child(gpath, "base_height"), kGenCoord);
        }
        if (const json* v = find(*gen, "bumps")) {
          const std::string bpath = child(gpath, "bumps");
          expect_array(*v, bpath, "an array of bumps {\"center\": [x, z], \"radius\": r, \"height\": h}");
          if (v->size() > kMaxTerrainBumps) {
            fail(bpath, std::to_string(v->size()) + " bumps given: at most 1024 are allowed");
          }
          for (std::size_t i = 0; i < v->size(); ++i) {
            const std::string p = index_path(bpath, i);
            const json& bj = expect_object((*v)[i], p, "an object {\"center\": [x, z], \"radius\": r, \"height\": h}");
            check_keys(bj, p, {"center", "radius", "height"});
            TerrainBump bump;
            double c[2];
            reals(require(bj, p, "center", "give the bump's centre \"center\": [x, z] in m"), child(p, "center"), c, 2,
                  kGenCoord, "[x, z]");
            bump.x = c[0];
            bump.z = c[1];
            bump.radius = real(require(bj, p, "radius", "give the bump's radius in m"), child(p, "radius"), kGenRadius);
            bump.height = real(require(bj, p, "height", "give the bump's height in m (negative for a dip)"),
                               child(p, "height"), kGenCoord);
            terrain.bumps.push_back(bump);
          }
        }
        s = make_terrain_sdf(grid, terrain, std::move(name), s.material);
      } else {
        fail(tpath, shown(type) + " is not a generator: must be \"bowl\" or \"terrain\" (or give explicit "
                                  "\"values\" instead)");
      }
    }
  }

  std::string source_;
};

// ---------------------------------------------------------------------------
// Writer
// ---------------------------------------------------------------------------

class Writer {
 public:
  std::string out;

  // The value at base.name[index] (index < 0: base.name). Paths are only
  // built for the error.
  void real(double v, const std::string& base, std::string_view name, long index = -1) {
    if (!std::isfinite(v)) {
      std::string path = name.empty() ? base : child(base, name);
      if (index >= 0) path = index_path(path, static_cast<std::size_t>(index));
      throw SceneError(path + ": " + plain_number(v) + " cannot be written to JSON: must be a finite number", path);
    }
    out += json_number(v);
  }
  void reals(const double* v, std::size_t n, const std::string& base, std::string_view name) {
    out += '[';
    for (std::size_t i = 0; i < n; ++i) {
      if (i) out += ", ";
      real(v[i], base, name, static_cast<long>(i));
    }
    out += ']';
  }
  void vec3(const Vec3d& v, const std::string& base, std::string_view name) {
    const double a[3] = {v.x, v.y, v.z};
    reals(a, 3, base, name);
  }
  void str(const std::string& s) { out += json(s).dump(-1, ' ', false, json::error_handler_t::replace); }
  void boolean(bool b) { out += b ? "true" : "false"; }
  void key(const char* k) {
    out += '"';
    out += k;
    out += "\": ";
  }
  void material(const Material& m, const std::string& base, std::string_view name) {
    const std::string path = child(base, name);
    out += "{\"restitution\": ";
    real(m.restitution, path, "restitution");
    out += ", \"friction\": ";
    real(m.friction, path, "friction");
    out += '}';
  }
};

// ---------------------------------------------------------------------------
// Comparison
// ---------------------------------------------------------------------------

class Comparer {
 public:
  std::string diff;

  bool real(double a, double b, const std::string& path) {
    if (std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b)) return true;
    diff = path + ": " + plain_number(a) + " vs " + plain_number(b);
    return false;
  }
  bool integer(std::int64_t a, std::int64_t b, const std::string& path) {
    if (a == b) return true;
    diff = path + ": " + std::to_string(a) + " vs " + std::to_string(b);
    return false;
  }
  bool boolean(bool a, bool b, const std::string& path) {
    if (a == b) return true;
    diff = path + ": " + (a ? "true" : "false") + " vs " + (b ? "true" : "false");
    return false;
  }
  bool str(const std::string& a, const std::string& b, const std::string& path) {
    if (a == b) return true;
    diff = path + ": \"" + a + "\" vs \"" + b + "\"";
    return false;
  }
  bool vec3(const Vec3d& a, const Vec3d& b, const std::string& path) {
    return real(a.x, b.x, index_path(path, 0)) && real(a.y, b.y, index_path(path, 1)) &&
           real(a.z, b.z, index_path(path, 2));
  }
  bool material(const Material& a, const Material& b, const std::string& path) {
    return real(a.restitution, b.restitution, child(path, "restitution")) &&
           real(a.friction, b.friction, child(path, "friction"));
  }

  bool scene(const Scene& a, const Scene& b) {
    if (!str(a.name, b.name, "name") || !integer(a.frames, b.frames, "frames")) return false;
    if (!str(pair_model_name(a.pair_contacts), pair_model_name(b.pair_contacts), "pair_contacts")) return false;
    for (std::size_t i = 0; i < std::size(kEffectNames); ++i) {
      if (!boolean(a.effects.*kEffectMembers[i], b.effects.*kEffectMembers[i], child("effects", kEffectNames[i]))) {
        return false;
      }
    }
    for (const ConstSpec& s : constant_specs()) {
      const std::string p = child("constants", s.name);
      const bool same = s.real      ? real(a.constants.*s.real, b.constants.*s.real, p)
                        : s.integer ? integer(a.constants.*s.integer, b.constants.*s.integer, p)
                                    : vec3(a.constants.*s.vec, b.constants.*s.vec, p);
      if (!same) return false;
    }
    if (!boolean(a.ground.present, b.ground.present, "ground.present") ||
        !real(a.ground.height, b.ground.height, "ground.height") ||
        !material(a.ground.material, b.ground.material, "ground.material")) {
      return false;
    }
    if (!integer(static_cast<std::int64_t>(a.bodies.size()), static_cast<std::int64_t>(b.bodies.size()),
                 "bodies (count)")) {
      return false;
    }
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
      const BodyDesc& x = a.bodies[i];
      const BodyDesc& y = b.bodies[i];
      const std::string p = index_path("bodies", i);
      const std::string q = child(p, "orientation");
      if (!vec3(x.half_extents, y.half_extents, child(p, "half_extents")) ||
          !real(x.mass, y.mass, child(p, "mass")) || !vec3(x.position, y.position, child(p, "position")) ||
          !real(x.orientation.w, y.orientation.w, index_path(q, 0)) ||
          !real(x.orientation.x, y.orientation.x, index_path(q, 1)) ||
          !real(x.orientation.y, y.orientation.y, index_path(q, 2)) ||
          !real(x.orientation.z, y.orientation.z, index_path(q, 3)) ||
          !vec3(x.velocity, y.velocity, child(p, "velocity")) ||
          !vec3(x.angular_velocity, y.angular_velocity, child(p, "angular_velocity")) ||
          !material(x.material, y.material, child(p, "material")) ||
          !boolean(x.is_static, y.is_static, child(p, "static")) || !boolean(x.asleep, y.asleep, child(p, "asleep"))) {
        return false;
      }
    }
    if (!integer(static_cast<std::int64_t>(a.sdfs.size()), static_cast<std::int64_t>(b.sdfs.size()), "sdfs (count)")) {
      return false;
    }
    for (std::size_t i = 0; i < a.sdfs.size(); ++i) {
      const SdfDesc& x = a.sdfs[i];
      const SdfDesc& y = b.sdfs[i];
      const std::string p = index_path("sdfs", i);
      const std::string r = child(p, "resolution");
      if (!str(x.name, y.name, child(p, "name")) || !vec3(x.min, y.min, child(p, "min")) ||
          !vec3(x.max, y.max, child(p, "max")) || !integer(x.nx, y.nx, index_path(r, 0)) ||
          !integer(x.ny, y.ny, index_path(r, 1)) || !integer(x.nz, y.nz, index_path(r, 2)) ||
          !material(x.material, y.material, child(p, "material")) ||
          !integer(static_cast<std::int64_t>(x.values.size()), static_cast<std::int64_t>(y.values.size()),
                   child(p, "values (count)"))) {
        return false;
      }
      for (std::size_t k = 0; k < x.values.size(); ++k) {
        if (std::bit_cast<std::uint64_t>(x.values[k]) != std::bit_cast<std::uint64_t>(y.values[k])) {
          return real(x.values[k], y.values[k], index_path(child(p, "values"), k));
        }
      }
    }
    return true;
  }
};

}  // namespace

// ---------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------

Scene parse_scene(std::string_view json_text, std::string_view source_name) {
  DomBuilder dom(json_text, source_name);
  try {
    json::sax_parse(json_text.begin(), json_text.end(), &dom, json::input_format_t::json, /*strict=*/true,
                    /*ignore_comments=*/false);
  } catch (const json::exception& e) {  // not expected: the SAX handler reports every parse error
    throw SceneError(prefix(source_name) + "cannot parse the JSON: " + e.what(), "");
  }
  return SceneReader(source_name).read(dom.root);
}

Scene load_scene_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw SceneError(path + ": cannot read the scene file: it is a directory (give the path of a .json file)", "");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw SceneError(path + ": cannot open the scene file: " + std::strerror(errno) +
                         " (check the path; built-in scenes are chosen by name, not by file)",
                     "");
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read the scene file", "");
  const std::string text = std::move(ss).str();
  return parse_scene(text, path);
}

std::string scene_to_json(const Scene& s) {
  Writer w;
  std::string& o = w.out;
  o += "{\n  \"format\": \"lockstep-scene\",\n  \"version\": 1,\n  \"name\": ";
  w.str(s.name);
  o += ",\n  \"frames\": " + std::to_string(s.frames) + ",\n  \"pair_contacts\": ";
  w.str(pair_model_name(s.pair_contacts));
  o += ",\n  \"effects\": {";
  for (std::size_t i = 0; i < std::size(kEffectNames); ++i) {
    if (i) o += ", ";
    w.key(kEffectNames[i]);
    w.boolean(s.effects.*kEffectMembers[i]);
  }
  o += "},\n  \"constants\": {\n";
  bool first = true;
  for (const ConstSpec& c : constant_specs()) {
    if (!first) o += ",\n";
    first = false;
    o += "    ";
    w.key(c.name);
    if (c.real) {
      w.real(s.constants.*c.real, "constants", c.name);
    } else if (c.integer) {
      o += std::to_string(s.constants.*c.integer);
    } else {
      w.vec3(s.constants.*c.vec, "constants", c.name);
    }
  }
  o += "\n  },\n  \"ground\": {\"present\": ";
  w.boolean(s.ground.present);
  o += ", \"height\": ";
  w.real(s.ground.height, "ground", "height");
  o += ", \"material\": ";
  w.material(s.ground.material, "ground", "material");
  o += "},\n  \"bodies\": [";
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const BodyDesc& b = s.bodies[i];
    const std::string p = index_path("bodies", i);
    o += i ? ",\n    {" : "\n    {";
    w.key("half_extents");
    w.vec3(b.half_extents, p, "half_extents");
    o += ", ";
    w.key("mass");
    w.real(b.mass, p, "mass");
    o += ", ";
    w.key("position");
    w.vec3(b.position, p, "position");
    o += ", ";
    w.key("orientation");
    const double q[4] = {b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z};
    w.reals(q, 4, p, "orientation");
    o += ", ";
    w.key("velocity");
    w.vec3(b.velocity, p, "velocity");
    o += ", ";
    w.key("angular_velocity");
    w.vec3(b.angular_velocity, p, "angular_velocity");
    o += ", ";
    w.key("material");
    w.material(b.material, p, "material");
    o += ", ";
    w.key("static");
    w.boolean(b.is_static);
    o += ", ";
    w.key("asleep");
    w.boolean(b.asleep);
    o += '}';
  }
  o += s.bodies.empty() ? "],\n" : "\n  ],\n";
  o += "  \"sdfs\": [";
  for (std::size_t i = 0; i < s.sdfs.size(); ++i) {
    const SdfDesc& d = s.sdfs[i];
    const std::string p = index_path("sdfs", i);
    o += i ? ",\n    {\n      " : "\n    {\n      ";
    w.key("name");
    w.str(d.name);
    o += ",\n      ";
    w.key("min");
    w.vec3(d.min, p, "min");
    o += ",\n      ";
    w.key("max");
    w.vec3(d.max, p, "max");
    o += ",\n      \"resolution\": [" + std::to_string(d.nx) + ", " + std::to_string(d.ny) + ", " +
         std::to_string(d.nz) + "],\n      ";
    w.key("material");
    w.material(d.material, p, "material");
    o += ",\n      \"values\": [";
    const std::size_t per_line = d.nx > 0 ? static_cast<std::size_t>(d.nx) : 1;
    for (std::size_t k = 0; k < d.values.size(); ++k) {
      if (k) o += ',';
      o += (k % per_line == 0) ? "\n        " : " ";
      w.real(d.values[k], p, "values", static_cast<long>(k));
    }
    o += d.values.empty() ? "]\n    }" : "\n      ]\n    }";
  }
  o += s.sdfs.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return std::move(w.out);
}

void validate_scene(const Scene& scene) {
  const std::string source = "<scene " + scene.name + ">";
  std::string text;
  try {
    text = scene_to_json(scene);
  } catch (const SceneError& e) {
    throw SceneError(source + ": " + e.what(), e.field);
  }
  const Scene back = parse_scene(text, source);
  // Values written from a valid scene read back exactly; a difference means
  // the scene holds something the format cannot express.
  Comparer c;
  if (!c.scene(scene, back)) {
    const std::string field = c.diff.substr(0, c.diff.find(':'));
    throw SceneError(source + ": " + c.diff + ": the value does not survive a JSON round trip", field);
  }
}

bool scenes_equal(const Scene& a, const Scene& b) { return Comparer().scene(a, b); }

std::string scene_difference(const Scene& a, const Scene& b) {
  Comparer c;
  c.scene(a, b);
  return c.diff;
}

}  // namespace lockstep
