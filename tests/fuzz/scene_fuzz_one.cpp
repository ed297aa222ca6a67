#include "scene_fuzz_one.hpp"

#include <algorithm>
#include <string>

#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/world.hpp"

namespace lockstep::fuzz {

namespace {

// Steps a World<T> of the scene; returns true if it ran every frame, false if
// a RunError stopped it (after checking what the error names).
template <class T>
bool step_world(const Scene& scene, int frames) {
  try {
    World<T> world(scene);
    for (int f = 0; f < frames; ++f) world.step();
    return true;
  } catch (const RunError& e) {
    const int bodies = static_cast<int>(scene.bodies.size());
    if (e.frame < 0 || e.frame > frames || e.body < -1 || e.body >= bodies || e.quantity.empty() ||
        std::string(e.what()).empty()) {
      throw FuzzFinding(std::string("RunError names an impossible frame/body/quantity: frame ") +
                        std::to_string(e.frame) + ", body " + std::to_string(e.body) + " of " +
                        std::to_string(bodies) + ", quantity '" + e.quantity + "': " + e.what());
    }
    return false;
  }
}

}  // namespace

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::kRejected: return "rejected";
    case Outcome::kLoaded: return "loaded";
    case Outcome::kRan: return "ran";
    case Outcome::kStopped: return "stopped";
  }
  return "?";
}

Outcome fuzz_one_scene(std::string_view input) {
  Scene scene;
  try {
    scene = parse_scene(input, kFuzzSource);
  } catch (const SceneError& e) {
    const std::string message = e.what();
    const std::string prefix = kFuzzSource;
    if (message.size() <= prefix.size() || message.compare(0, prefix.size(), prefix) != 0) {
      throw FuzzFinding("SceneError message does not start with the source name: '" + message + "'");
    }
    return Outcome::kRejected;
  }
  std::size_t sdf_values = 0;
  for (const SdfDesc& s : scene.sdfs) sdf_values += s.values.size();
  if (sdf_values > kMaxFuzzSdfValues) return Outcome::kLoaded;
  // The writer/reader round trip (scene_json.hpp: parse(write(s)) == s).
  std::string written;
  try {
    written = scene_to_json(scene);
  } catch (const SceneError& e) {
    throw FuzzFinding(std::string("scene_to_json refused a scene that parse_scene accepted: ") + e.what());
  }
  Scene again;
  try {
    again = parse_scene(written, "<fuzz round trip>");
  } catch (const SceneError& e) {
    throw FuzzFinding(std::string("parse_scene refused what scene_to_json wrote: ") + e.what());
  }
  if (!scenes_equal(scene, again)) {
    throw FuzzFinding("round trip changed the scene: " + scene_difference(scene, again));
  }
  if (scene.bodies.size() > kMaxFuzzBodies) return Outcome::kLoaded;
  const int frames = std::min(scene.frames, kMaxFuzzFrames);
  const bool fixed_ran = step_world<Q16>(scene, frames);
  const bool double_ran = step_world<double>(scene, frames);
  return fixed_ran && double_ran ? Outcome::kRan : Outcome::kStopped;
}

}  // namespace lockstep::fuzz
