// One fuzz input through the scene loader and, when it loads, a few frames of
// the engine: the function shared by the libFuzzer target (scene_fuzz.cpp)
// and the plain replay driver (scene_replay.cpp). docs/FUZZING.md.
//
// The contract it checks (any breach is a finding):
//  - parse_scene either returns a scene or throws SceneError whose message is
//    non-empty and starts with the source name; no other exception, no crash;
//  - a scene that loads with at most kMaxFuzzSdfValues SDF samples is written
//    back by scene_to_json and reads back equal (scenes_equal): the
//    writer/reader round trip of scene_json.hpp;
//  - if it also has at most kMaxFuzzBodies bodies, World<Q16> and
//    World<double> are built and stepped
//    min(frames, kMaxFuzzFrames) frames; a RunError (Q16 overflow, non-finite
//    value) is a clean stop and must name a frame in [0, frames stepped + 1]
//    and a body in [-1, bodies).
// Breaches throw FuzzFinding (the replay driver reports it; the fuzz target
// lets it escape, which libFuzzer reports as a crash with the input saved).
#pragma once
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lockstep::fuzz {

inline constexpr std::size_t kMaxFuzzBodies = 64;
inline constexpr int kMaxFuzzFrames = 8;
inline constexpr std::size_t kMaxFuzzSdfValues = std::size_t{1} << 16;
// The source name given to parse_scene.
inline constexpr const char* kFuzzSource = "<fuzz>";

struct FuzzFinding : std::logic_error {
  using std::logic_error::logic_error;
};

enum class Outcome {
  kRejected,  // SceneError: a clean refusal
  kLoaded,    // loaded, but too large for the round trip or the engines under the caps
  kRan,       // loaded and stepped without error
  kStopped,   // loaded and stopped by a RunError (in either engine)
};

const char* outcome_name(Outcome o);

// Runs one input. Throws FuzzFinding on a breach of the contract above; any
// other exception escaping is a finding too.
Outcome fuzz_one_scene(std::string_view input);

}  // namespace lockstep::fuzz
