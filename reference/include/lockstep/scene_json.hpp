// JSON scenes: loading (with full validation), writing and comparing.
//
// The format ("lockstep-scene", version 1) and every range are documented in
// docs/SCENES.md. Loading is all or nothing: parse_scene either returns a
// Scene in which every field is within its documented range, or throws a
// SceneError naming the offending field, its value, what is allowed and how to
// fix it. Nothing partial is ever returned.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "lockstep/scene.hpp"

namespace lockstep {

// A scene that cannot be loaded (syntax, type or range error, unreadable file).
// what() is the full message, prefixed by the source name ("file.json: ...");
// field is the path of the offending value inside the document, e.g.
// "bodies[3].mass" or "constants.dt", empty when the error concerns no single
// field (a syntax error at top level, an unreadable file).
struct SceneError : std::runtime_error {
  std::string field;
  using std::runtime_error::runtime_error;
  SceneError(const std::string& message, std::string field_path)
      : std::runtime_error(message), field(std::move(field_path)) {}
};

inline constexpr const char* kSceneFormat = "lockstep-scene";
inline constexpr int kSceneVersion = 1;
inline constexpr int kMaxSceneFrames = 10'000'000;
inline constexpr std::size_t kMaxSceneBodies = 1'000'000;
inline constexpr int kMaxSdfResolution = 256;
inline constexpr std::int64_t kMaxSdfValues = std::int64_t{1} << 24;
inline constexpr std::size_t kMaxTerrainBumps = 1024;

// Parses and validates a scene. source_name (a file name, "<builtin drop>",
// ...) prefixes every error message. Throws SceneError.
Scene parse_scene(std::string_view json_text, std::string_view source_name);

// Reads the file and parses it (source name = path). Throws SceneError, also
// when the file cannot be read.
Scene load_scene_file(const std::string& path);

// Writes every field of the scene (defaults included, so the file pins every
// constant) as "lockstep-scene" version 1 JSON. Doubles are written as the
// shortest decimal that reads back to the same double, so
// parse_scene(scene_to_json(s)) is bit for bit s for every valid scene.
// SDFs are always written with explicit "values" (a generator is expanded on
// load). Throws SceneError only for a value JSON cannot hold (NaN or infinity),
// naming its field; other out-of-range values are written as they are (and
// are then rejected by parse_scene).
std::string scene_to_json(const Scene& scene);

// Throws SceneError if the scene (e.g. one built in code) would not load:
// exactly the checks of parse_scene, with source name "<scene NAME>".
void validate_scene(const Scene& scene);

// Field-by-field comparison; doubles compare bit for bit (so -0.0 != 0.0).
bool scenes_equal(const Scene& a, const Scene& b);
// The path of the first field that differs ("bodies[2].position[1]: 0.5 vs
// 0.75"), or "" when scenes_equal(a, b). For test diagnostics.
std::string scene_difference(const Scene& a, const Scene& b);

}  // namespace lockstep
