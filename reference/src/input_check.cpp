#include "lockstep/input_check.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "lockstep/scene_json.hpp"
#include "lockstep/scene_limits.hpp"

namespace lockstep::input_check {

namespace {
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace

void body(const Scene& scene, const BodyDesc& desc, std::string_view number_type, const std::string& what,
          const std::string& field) {
  Scene probe;  // the scene's rules without its bodies and volumes: the body alone
  probe.name = scene.name;
  probe.frames = 1;  // a snapshot's scene may have run out of frames (0); the body is what is checked
  probe.pair_contacts = scene.pair_contacts;
  probe.effects = scene.effects;
  probe.constants = scene.constants;
  probe.ground = scene.ground;
  probe.bodies = {desc};
  try {
    validate_scene(probe);
    validate_scene_for(number_type, probe);
  } catch (const SceneError& e) {
    std::string message = e.what();
    const std::string prefix = "<scene " + scene.name + ">: ";
    if (message.compare(0, prefix.size(), prefix) == 0) message.erase(0, prefix.size());
    for (std::size_t at; (at = message.find("bodies[0]")) != std::string::npos;) message.replace(at, 9, field);
    throw std::invalid_argument(what + ": " + message);
  }
}

void vector(const Vec3d& v, double limit, const char* unit, const std::string& what, const char* field,
            const char* fix) {
  const double c[3] = {v.x, v.y, v.z};
  for (int a = 0; a < 3; ++a) {
    if (std::isfinite(c[a]) && std::fabs(c[a]) <= limit) continue;
    throw std::invalid_argument(what + ": " + field + " = [" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "] " +
                                unit + ": component " + std::to_string(a) + " is " +
                                (std::isfinite(c[a]) ? "outside [-" + num(limit) + ", " + num(limit) + "]" : "not finite") +
                                "; " + fix);
  }
}

void frame(int input_frame, int world_frame) {
  if (input_frame != world_frame + 1)
    throw std::invalid_argument("apply: input.frame = " + std::to_string(input_frame) + " but the world is at frame " +
                                std::to_string(world_frame) + ": an input of frame f is applied before the step that "
                                "computes frame f; apply it when frame() == " + std::to_string(static_cast<long long>(input_frame) - 1));
}

std::string id_text(std::uint32_t slot, std::uint32_t generation) {
  return "slot " + std::to_string(slot) + ", generation " + std::to_string(generation);
}

}  // namespace lockstep::input_check
