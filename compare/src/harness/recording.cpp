// Recordings and inputs files (docs/RECORDINGS.md): JSON in, JSON out. Every
// value is checked as it is read; an error names the source, the field, the
// value and the fix. Needs the reference library only (recording.hpp).
#include "lockstep/compare/recording.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "lockstep/scene_json.hpp"
#include "lockstep/snapshot.hpp"

namespace lockstep::compare {

namespace {

using nlohmann::json;

inline constexpr double kMaxValue = 32768.0;  // inputs' values: the Q16.16 range |x| < 32768

std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

class Reader {
 public:
  explicit Reader(std::string_view source) : source_(source) {}
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw RecordingError(source_ + ": " + field + ": " + what, field);
  }
  static std::string shown(const json& j) {
    std::string s = j.dump();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
  }
  const json& member(const json& obj, const std::string& path, const char* key) const {
    auto it = obj.find(key);
    if (it == obj.end()) fail(join(path, key), "missing; add it (docs/RECORDINGS.md)");
    return *it;
  }
  void only_keys(const json& obj, const std::string& path, std::initializer_list<const char*> keys) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool known = false;
      std::string list;
      for (const char* k : keys) {
        known = known || it.key() == k;
        list += (list.empty() ? "" : ", ") + std::string(k);
      }
      if (!known) fail(join(path, it.key()), "unknown field; the fields here are " + list + " (remove it or fix its name)");
    }
  }
  const json& object(const json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, shown(j) + " is not a JSON object");
    return j;
  }
  long long integer(const json& j, const std::string& path, long long lo, long long hi) const {
    if (!j.is_number_integer()) fail(path, shown(j) + " is not an integer; give an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    const long long v = j.is_number_unsigned() && j.get<unsigned long long>() > static_cast<unsigned long long>(hi) ? hi + 1 : j.get<long long>();
    if (v < lo || v > hi) fail(path, shown(j) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, shown(j) + " is not a string");
    return j.get<std::string>();
  }
  // A number, or {"raw": R}: exactly R / 65536 (as in scenes, docs/SCENES.md).
  double value(const json& j, const std::string& path) const {
    double v = 0;
    if (j.is_object()) {
      only_keys(j, path, {"raw"});
      v = static_cast<double>(integer(member(j, path, "raw"), path + ".raw", INT32_MIN, INT32_MAX)) / 65536.0;
    } else if (j.is_number()) {
      v = j.get<double>();
    } else {
      fail(path, shown(j) + " is not a number or {\"raw\": R}");
    }
    if (!std::isfinite(v) || std::fabs(v) >= kMaxValue)
      fail(path, shown(j) + " is outside the Q16.16 range |x| < 32768; give a smaller value");
    return v;
  }
  Vec3d vec(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, shown(j) + " is not an array of 3 numbers [x, y, z]");
    return {value(j[0], path + "[0]"), value(j[1], path + "[1]"), value(j[2], path + "[2]")};
  }
  Quatd quat(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 4) fail(path, shown(j) + " is not an array of 4 numbers [w, x, y, z]");
    const Quatd q{value(j[0], path + "[0]"), value(j[1], path + "[1]"), value(j[2], path + "[2]"), value(j[3], path + "[3]")};
    if (q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z < 1e-12)
      fail(path, shown(j) + " is (nearly) the zero quaternion; give a rotation, e.g. [1, 0, 0, 0]");
    return q;
  }
  BodyId id(const json& j, const std::string& path) const {
    if (j.is_object()) {
      only_keys(j, path, {"slot", "generation"});
      return {static_cast<std::uint32_t>(integer(member(j, path, "slot"), path + ".slot", 0, 999'999)),
              static_cast<std::uint32_t>(integer(member(j, path, "generation"), path + ".generation", 0, INT32_MAX))};
    }
    if (!j.is_number_integer()) fail(path, shown(j) + " is not a body: give its index (an integer) or {\"slot\": S, \"generation\": G}");
    return {static_cast<std::uint32_t>(integer(j, path, 0, 999'999)), 0};
  }
  // A scene body object (docs/SCENES.md "bodies"), checked by the scene loader.
  BodyDesc body(const json& j, const std::string& path) const {
    object(j, path);
    const json scene = {{"format", kSceneFormat}, {"version", kSceneVersion}, {"name", "input"}, {"bodies", json::array({j})}};
    try {
      return parse_scene(scene.dump(), "").bodies.at(0);
    } catch (const SceneError& e) {
      std::string what = e.what(), field = e.field;
      const std::string prefix = "bodies[0]";
      if (field.rfind(prefix, 0) == 0) field = path + field.substr(prefix.size());
      if (const auto at = what.find(prefix); at != std::string::npos) what.replace(at, prefix.size(), path);
      if (what.rfind(": ", 0) == 0) what = what.substr(2);
      throw RecordingError(source_ + ": " + what, field);
    }
  }
  Input input(const json& j, const std::string& path) const {
    object(j, path);
    Input in;
    in.frame = static_cast<int>(integer(member(j, path, "frame"), path + ".frame", 1, kMaxRecordedFrames));
    const std::string kind = string(member(j, path, "kind"), path + ".kind");
    const InputKind kinds[] = {InputKind::create, InputKind::destroy, InputKind::impulse, InputKind::force,
                               InputKind::set_pose, InputKind::set_velocity, InputKind::wake};
    bool found = false;
    std::string names;
    for (InputKind k : kinds) {
      names += (names.empty() ? "" : ", ") + std::string(input_kind_name(k));
      if (kind == input_kind_name(k)) { in.kind = k; found = true; }
    }
    if (!found) fail(path + ".kind", "\"" + kind + "\" is not an input kind; use one of " + names);
    switch (in.kind) {
      case InputKind::create:
        only_keys(j, path, {"frame", "kind", "body"});
        in.body = body(member(j, path, "body"), path + ".body");
        break;
      case InputKind::destroy:
      case InputKind::wake:
        only_keys(j, path, {"frame", "kind", "id"});
        break;
      case InputKind::impulse:
        only_keys(j, path, {"frame", "kind", "id", "impulse", "point"});
        in.a = vec(member(j, path, "impulse"), path + ".impulse");
        in.b = vec(member(j, path, "point"), path + ".point");
        break;
      case InputKind::force:
        only_keys(j, path, {"frame", "kind", "id", "force", "torque"});
        in.a = vec(member(j, path, "force"), path + ".force");
        if (j.contains("torque")) in.b = vec(j["torque"], path + ".torque");
        break;
      case InputKind::set_pose:
        only_keys(j, path, {"frame", "kind", "id", "position", "orientation"});
        in.a = vec(member(j, path, "position"), path + ".position");
        in.q = quat(member(j, path, "orientation"), path + ".orientation");
        break;
      case InputKind::set_velocity:
        only_keys(j, path, {"frame", "kind", "id", "velocity", "angular_velocity"});
        in.a = vec(member(j, path, "velocity"), path + ".velocity");
        if (j.contains("angular_velocity")) in.b = vec(j["angular_velocity"], path + ".angular_velocity");
        break;
    }
    if (in.kind != InputKind::create) in.id = id(member(j, path, "id"), path + ".id");
    return in;
  }
  std::vector<Input> inputs(const json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, shown(j) + " is not an array of inputs");
    if (j.size() > kMaxInputs) fail(path, std::to_string(j.size()) + " inputs: at most " + std::to_string(kMaxInputs));
    std::vector<Input> out;
    out.reserve(j.size());
    for (std::size_t k = 0; k < j.size(); ++k) out.push_back(input(j[k], path + "[" + std::to_string(k) + "]"));
    return out;
  }
  void header(const json& doc, const char* format) const {
    object(doc, "(document)");
    const std::string f = string(member(doc, "", "format"), "format");
    if (f != format)
      fail("format", "\"" + f + "\" is not \"" + format + "\"" +
                         (f == kRecordingFormat || f == kInputsFormat ? " (a recording and an inputs file are different documents)" : ""));
    integer(member(doc, "", "version"), "version", kRecordingVersion, kRecordingVersion);
  }
  json parse(std::string_view text) const {
    try {
      return json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
      throw RecordingError(source_ + ": not valid JSON: " + e.what(), "");
    }
  }

 private:
  std::string source_;
};

std::string read_file(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RecordingError(path + ": cannot read this " + std::string(what) + " file (check the path)", "");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

json vec_json(const Vec3d& v) { return json::array({v.x, v.y, v.z}); }

json id_json(const BodyId& id) {
  if (id.generation == 0) return id.slot;
  return {{"slot", id.slot}, {"generation", id.generation}};
}

json input_json(const Input& in) {
  json j = {{"frame", in.frame}, {"kind", input_kind_name(in.kind)}};
  switch (in.kind) {
    case InputKind::create: {
      Scene s;
      s.name = "input";
      s.bodies = {in.body};
      j["body"] = json::parse(scene_to_json(s))["bodies"][0];
      return j;
    }
    case InputKind::destroy:
    case InputKind::wake: break;
    case InputKind::impulse: j["impulse"] = vec_json(in.a); j["point"] = vec_json(in.b); break;
    case InputKind::force: j["force"] = vec_json(in.a); j["torque"] = vec_json(in.b); break;
    case InputKind::set_pose: j["position"] = vec_json(in.a); j["orientation"] = json::array({in.q.w, in.q.x, in.q.y, in.q.z}); break;
    case InputKind::set_velocity: j["velocity"] = vec_json(in.a); j["angular_velocity"] = vec_json(in.b); break;
  }
  j["id"] = id_json(in.id);
  return j;
}

json inputs_json(const std::vector<Input>& inputs) {
  json a = json::array();
  for (const Input& in : inputs) a.push_back(input_json(in));
  return a;
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64(const std::vector<std::uint8_t>& b) {
  std::string out;
  out.reserve((b.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < b.size(); i += 3) {
    const std::uint32_t n = (std::uint32_t{b[i]} << 16) | (i + 1 < b.size() ? std::uint32_t{b[i + 1]} << 8 : 0) |
                            (i + 2 < b.size() ? std::uint32_t{b[i + 2]} : 0);
    out += kBase64[(n >> 18) & 63];
    out += kBase64[(n >> 12) & 63];
    out += i + 1 < b.size() ? kBase64[(n >> 6) & 63] : '=';
    out += i + 2 < b.size() ? kBase64[n & 63] : '=';
  }
  return out;
}

std::vector<std::uint8_t> unbase64(const std::string& s, const Reader& r, const std::string& path) {
  if (s.size() % 4 != 0) r.fail(path, "base64 text of " + std::to_string(s.size()) + " characters, not a multiple of 4");
  std::vector<std::uint8_t> out;
  out.reserve(s.size() / 4 * 3);
  for (std::size_t i = 0; i < s.size(); i += 4) {
    std::uint32_t n = 0;
    int pad = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = s[i + k];
      int v = -1;
      if (c == '=' && i + 4 == s.size() && k >= 2) { ++pad; v = 0; }
      else if (pad == 0) for (int d = 0; d < 64; ++d) if (kBase64[d] == c) v = d;
      if (v < 0) r.fail(path, "character " + std::to_string(i + k) + " is not base64");
      n = (n << 6) | static_cast<std::uint32_t>(v);
    }
    out.push_back(static_cast<std::uint8_t>(n >> 16));
    if (pad < 2) out.push_back(static_cast<std::uint8_t>(n >> 8));
    if (pad < 1) out.push_back(static_cast<std::uint8_t>(n));
  }
  return out;
}

std::uint64_t parse_hash(const json& j, const Reader& r, const std::string& path) {
  const std::string s = r.string(j, path);
  if (s.size() != 16) r.fail(path, "\"" + s + "\" is not 16 hex digits");
  std::uint64_t h = 0;
  for (char c : s) {
    int v = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    if (v < 0) r.fail(path, "\"" + s + "\" is not 16 lower-case hex digits");
    h = (h << 4) | static_cast<std::uint64_t>(v);
  }
  return h;
}

}  // namespace

const RecordedSnapshot* RunRecording::snapshot_at(int f) const {
  for (const RecordedSnapshot& s : snapshots)
    if (s.frame == f) return &s;
  return nullptr;
}

std::string hash_to_hex(std::uint64_t h) {
  char buf[17];
  for (int i = 15; i >= 0; --i, h >>= 4) buf[i] = "0123456789abcdef"[h & 15];
  buf[16] = 0;
  return buf;
}

std::vector<Input> parse_inputs(std::string_view text, std::string_view source) {
  const Reader r(source);
  const json doc = r.parse(text);
  r.header(doc, kInputsFormat);
  r.only_keys(doc, "", {"format", "version", "inputs"});
  return r.inputs(r.member(doc, "", "inputs"), "inputs");
}

std::vector<Input> load_inputs_file(const std::string& path) { return parse_inputs(read_file(path, "inputs"), path); }

void validate_inputs(const std::vector<Input>& inputs, const Scene& scene, int frames, std::string_view source) {
  const Reader r(source);
  std::size_t slots = scene.bodies.size();
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const Input& in = inputs[k];
    const std::string path = "inputs[" + std::to_string(k) + "]";
    if (in.frame < 1 || in.frame > frames)
      r.fail(path + ".frame", std::to_string(in.frame) + " is outside the run's frames [1, " + std::to_string(frames) +
                                  "]; an input with frame f applies before the step that computes frame f");
    if (k > 0 && in.frame < inputs[k - 1].frame)
      r.fail(path + ".frame", std::to_string(in.frame) + " comes after an input of frame " + std::to_string(inputs[k - 1].frame) +
                                  "; list the inputs in frame order");
    if (in.kind == InputKind::create) {
      ++slots;
    } else if (in.id.slot >= slots) {
      r.fail(path + ".id", "body " + std::to_string(in.id.slot) + " does not exist at frame " + std::to_string(in.frame) +
                               ": the scene has " + std::to_string(scene.bodies.size()) + " bodies" +
                               (slots > scene.bodies.size() ? " and " + std::to_string(slots - scene.bodies.size()) + " created before" : "") +
                               " (slots 0.." + std::to_string(slots == 0 ? 0 : slots - 1) + ")");
    }
  }
}

std::string inputs_to_json(const std::vector<Input>& inputs) {
  json doc = {{"format", kInputsFormat}, {"version", kRecordingVersion}, {"inputs", inputs_json(inputs)}};
  return doc.dump(2) + "\n";
}

std::string recording_to_json(const RunRecording& rec) {
  json hashes = json::array();
  for (std::uint64_t h : rec.hashes) hashes.push_back(hash_to_hex(h));
  json snaps = json::array();
  for (const RecordedSnapshot& s : rec.snapshots) snaps.push_back({{"frame", s.frame}, {"state", base64(s.bytes)}});
  Scene scene = rec.scene;
  scene.frames = rec.frames();
  json doc = {{"format", kRecordingFormat},   {"version", kRecordingVersion}, {"engine", rec.engine},
              {"build", rec.build},           {"frames", rec.frames()},       {"snapshot_every", rec.snapshot_every},
              {"scene", json::parse(scene_to_json(scene))}, {"inputs", inputs_json(rec.inputs)},
              {"hashes", std::move(hashes)},  {"snapshots", std::move(snaps)}};
  // One input, hash or snapshot per line: diffable, and the scene as scene files are.
  std::ostringstream out;
  out << "{\n";
  const char* keys[] = {"format", "version", "engine", "build", "frames", "snapshot_every", "scene", "inputs", "hashes", "snapshots"};
  for (std::size_t k = 0; k < std::size(keys); ++k) {
    const json& v = doc[keys[k]];
    out << "  \"" << keys[k] << "\": ";
    if (v.is_array() && !v.empty()) {
      out << "[\n";
      for (std::size_t i = 0; i < v.size(); ++i) out << "    " << v[i].dump() << (i + 1 < v.size() ? ",\n" : "\n");
      out << "  ]";
    } else {
      out << v.dump();
    }
    out << (k + 1 < std::size(keys) ? ",\n" : "\n");
  }
  out << "}\n";
  return out.str();
}

RunRecording parse_recording(std::string_view text, std::string_view source) {
  const Reader r(source);
  const json doc = r.parse(text);
  r.header(doc, kRecordingFormat);
  r.only_keys(doc, "", {"format", "version", "engine", "build", "frames", "snapshot_every", "scene", "inputs", "hashes", "snapshots"});
  RunRecording rec;
  rec.engine = r.string(r.member(doc, "", "engine"), "engine");
  if (rec.engine.empty() || rec.engine.size() > 64) r.fail("engine", "\"" + rec.engine + "\" is not an engine name");
  rec.build = r.string(r.member(doc, "", "build"), "build");
  const int frames = static_cast<int>(r.integer(r.member(doc, "", "frames"), "frames", 0, kMaxRecordedFrames));
  rec.snapshot_every = static_cast<int>(r.integer(r.member(doc, "", "snapshot_every"), "snapshot_every", 0, kMaxRecordedFrames));
  const json& scene = r.object(r.member(doc, "", "scene"), "scene");
  try {
    rec.scene = parse_scene(scene.dump(), std::string(source) + ": scene");
  } catch (const SceneError& e) {
    throw RecordingError(e.what(), "scene." + e.field);
  }
  if (rec.scene.frames != frames)
    r.fail("scene.frames", std::to_string(rec.scene.frames) + " is not the recording's frames " + std::to_string(frames));
  rec.inputs = r.inputs(r.member(doc, "", "inputs"), "inputs");
  validate_inputs(rec.inputs, rec.scene, frames, source);
  const json& hashes = r.member(doc, "", "hashes");
  if (!hashes.is_array() || hashes.size() != static_cast<std::size_t>(frames))
    r.fail("hashes", "must be an array of " + std::to_string(frames) + " hashes (one per frame 1.." + std::to_string(frames) +
                         "), not " + Reader::shown(hashes).substr(0, 20));
  rec.hashes.reserve(hashes.size());
  for (std::size_t f = 0; f < hashes.size(); ++f) rec.hashes.push_back(parse_hash(hashes[f], r, "hashes[" + std::to_string(f) + "]"));
  const json& snaps = r.member(doc, "", "snapshots");
  if (!snaps.is_array()) r.fail("snapshots", Reader::shown(snaps) + " is not an array");
  for (std::size_t k = 0; k < snaps.size(); ++k) {
    const std::string path = "snapshots[" + std::to_string(k) + "]";
    const json& s = r.object(snaps[k], path);
    r.only_keys(s, path, {"frame", "state"});
    RecordedSnapshot snap;
    snap.frame = static_cast<int>(r.integer(r.member(s, path, "frame"), path + ".frame", 0, frames));
    if (!rec.snapshots.empty() && snap.frame <= rec.snapshots.back().frame)
      r.fail(path + ".frame", std::to_string(snap.frame) + " is not after the snapshot before it (frame " +
                                  std::to_string(rec.snapshots.back().frame) + "); list them in frame order");
    snap.bytes = unbase64(r.string(r.member(s, path, "state"), path + ".state"), r, path + ".state");
    try {
      const SnapshotInfo info = read_snapshot_info(snap.bytes.data(), snap.bytes.size());
      if (static_cast<int>(info.frame) != snap.frame)
        r.fail(path + ".state", "a snapshot of frame " + std::to_string(info.frame) + ", not of frame " + std::to_string(snap.frame));
    } catch (const SnapshotError& e) {
      r.fail(path + ".state", e.what());
    }
    rec.snapshots.push_back(std::move(snap));
  }
  return rec;
}

RunRecording load_recording_file(const std::string& path) { return parse_recording(read_file(path, "recording"), path); }

std::string build_description(const std::string& version) {
  std::string s = "lockstep " + version;
#if defined(__clang__)
  s += ", clang++ " __clang_version__;
#elif defined(__GNUC__)
  s += ", g++ " __VERSION__;
#else
  s += ", an unknown compiler";
#endif
#if defined(__x86_64__)
  s += ", x86_64";
#elif defined(__aarch64__)
  s += ", aarch64";
#elif defined(__i386__)
  s += ", i686";
#elif defined(__arm__)
  s += ", arm";
#elif defined(__s390x__)
  s += ", s390x";
#else
  s += ", another architecture";
#endif
#if defined(NDEBUG)
  s += ", optimised";
#else
  s += ", debug";
#endif
  return s;
}

}  // namespace lockstep::compare
