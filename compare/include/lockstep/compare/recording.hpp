// Recordings (docs/RECORDINGS.md): a run's scene, its inputs with their
// frames, the engine and build that made it, the per-frame state hashes
// (eq 92) and snapshots every K frames, as one JSON document
// ("lockstep-recording", version 1); and the inputs file that `lockstep run
// --inputs` reads ("lockstep-inputs", version 1). Reading is all or nothing:
// a RecordingError names the field, the value and the fix. This file needs
// the reference library only (no engine interface), so that a small replay
// tool for another architecture can read recordings (tests/compare/cross).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lockstep/input.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::compare {

// A recording or inputs file that cannot be read: what() names the source,
// the field ("inputs[3].frame"), the value and the fix; field is the path.
struct RecordingError : std::runtime_error {
  std::string field;
  RecordingError(const std::string& message, std::string field_path)
      : std::runtime_error(message), field(std::move(field_path)) {}
};

inline constexpr const char* kRecordingFormat = "lockstep-recording";
inline constexpr const char* kInputsFormat = "lockstep-inputs";
inline constexpr int kRecordingVersion = 1;
inline constexpr int kMaxRecordedFrames = 10'000'000;
inline constexpr std::size_t kMaxInputs = 1'000'000;

struct RecordedSnapshot {
  int frame = 0;                    // the state after this frame
  std::vector<std::uint8_t> bytes;  // the engine's snapshot (docs/SNAPSHOTS.md)
};

struct RunRecording {
  std::string engine;                 // the engine that recorded: "fixed", "double", "gpu", ...
  std::string build;                  // the build that recorded (information: version, commit, compiler, architecture)
  Scene scene;                        // scene.frames: the frames recorded
  std::vector<Input> inputs;          // frame ascending; inputs of one frame in the order they were applied
  std::vector<std::uint64_t> hashes;  // hashes[f - 1]: eq 92 after frame f, f = 1 .. frames
  int snapshot_every = 0;             // a snapshot every K frames (0: none but the last)
  std::vector<RecordedSnapshot> snapshots;  // frame ascending
  int frames() const { return static_cast<int>(hashes.size()); }
  // The snapshot of frame f, or null.
  const RecordedSnapshot* snapshot_at(int f) const;
};

// The inputs file: {"format": "lockstep-inputs", "version": 1, "inputs": [...]}
// (docs/RECORDINGS.md "Inputs"). source prefixes every error message.
std::vector<Input> parse_inputs(std::string_view json_text, std::string_view source);
std::vector<Input> load_inputs_file(const std::string& path);
// Checks the inputs against the scene they drive: frames in [1, frames] and
// ascending, bodies that exist when the input applies (creations and
// destructions counted as they come). Throws RecordingError naming
// "inputs[k].field".
void validate_inputs(const std::vector<Input>& inputs, const Scene& scene, int frames, std::string_view source);
// The inputs file for `inputs` (what parse_inputs reads back, bit for bit).
std::string inputs_to_json(const std::vector<Input>& inputs);

std::string recording_to_json(const RunRecording& r);
RunRecording parse_recording(std::string_view json_text, std::string_view source);
RunRecording load_recording_file(const std::string& path);

// This build, in words: "lockstep 0.1.0, g++ 12.2.0, x86_64, little-endian".
std::string build_description(const std::string& version);

// 16 lower-case hex digits; parse_hash throws RecordingError.
std::string hash_to_hex(std::uint64_t h);

}  // namespace lockstep::compare
