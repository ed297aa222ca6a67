// Run-time inputs (issue 32, docs/SPEC.md "Run-time inputs"): what a game
// does to a world between two frames. Values are doubles, converted to the
// engine's number type T exactly as the scene loader converts a scene's values
// (a value given as raw Q16.16 is the exact double R / 2^16), so that every
// engine, and the fixed engine bit for bit, sees the same input. An input with
// frame f is applied before the step that computes frame f, in the order the
// inputs were given.
#pragma once
#include <cstdint>
#include <string>

#include "lockstep/scene.hpp"

namespace lockstep {

// A body's stable name across creations and removals: the slot it occupies
// and how many times that slot has been reused. An id whose generation is not
// the slot's current one names a body that no longer exists.
struct BodyId {
  std::uint32_t slot = 0;
  std::uint32_t generation = 0;
  friend bool operator==(const BodyId&, const BodyId&) = default;
};

enum class InputKind : std::uint8_t {
  create,        // adds `body` (its shape, material and initial state)
  destroy,       // removes body `id`
  impulse,       // J = `a` (N s) applied at the world point `b` (m) of body `id`
  force,         // F = `a` (N) at the centre of mass and torque `b` (N m) for the next step
  set_pose,      // p = `a` (m), q = `q` (normalised as the loader does) of body `id`
  set_velocity,  // v = `a` (m/s), omega = `b` (rad/s, world) of body `id`
  wake,          // 5.1 on body `id`
};

struct Input {
  int frame = 1;          // applied before the step that computes this frame (>= 1)
  InputKind kind = InputKind::wake;
  BodyId id;              // the body acted on (not used by create)
  BodyDesc body;          // create only
  Vec3d a, b;             // see InputKind
  Quatd q;                // set_pose only
};

// "create", "destroy", ...: the names the recording format and the command
// line use.
inline const char* input_kind_name(InputKind kind) {
  switch (kind) {
    case InputKind::create: return "create";
    case InputKind::destroy: return "destroy";
    case InputKind::impulse: return "impulse";
    case InputKind::force: return "force";
    case InputKind::set_pose: return "set_pose";
    case InputKind::set_velocity: return "set_velocity";
    case InputKind::wake: return "wake";
  }
  return "unknown";
}

}  // namespace lockstep
