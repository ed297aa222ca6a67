// The checks of run-time inputs (docs/SPEC.md "Run-time inputs"): a body
// description is checked by the scene loader's own validation, values by
// their documented ranges. Every failure is a std::invalid_argument whose
// message names the input, the field, the value and a fix.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "lockstep/scene.hpp"

namespace lockstep::input_check {

// Ranges of an input's values (docs/SPEC.md "Run-time inputs").
inline constexpr double kMaxImpulse = 1e6;     // N s, each component
inline constexpr double kMaxForce = 1e7;       // N and N m, each component
inline constexpr double kMaxPoint = 32000.0;   // m, each component (the scene format's positions)

// Throws when the scene loader (validate_scene) or the engine's number type
// (validate_scene_for) would refuse `desc` as a body of `scene`. `what`
// prefixes the message ("create_body", "set_pose of body 3 (slot 3, generation 0)"),
// `field` replaces the loader's "bodies[0]" ("desc", "pose").
void body(const Scene& scene, const BodyDesc& desc, std::string_view number_type, const std::string& what,
          const std::string& field);

// Throws when a component of v is not finite or |v_i| > limit.
void vector(const Vec3d& v, double limit, const char* unit, const std::string& what, const char* field,
            const char* fix);

// Throws unless an input of frame `input_frame` is applied now, to a world at
// frame `world_frame` (an input of frame f is applied before the step that
// computes frame f).
void frame(int input_frame, int world_frame);

// "slot 3, generation 0".
std::string id_text(std::uint32_t slot, std::uint32_t generation);

}  // namespace lockstep::input_check
