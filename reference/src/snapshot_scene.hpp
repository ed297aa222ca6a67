// The number-type-free parts of a snapshot (docs/SNAPSHOTS.md): the scene
// section (everything of the Scene but the bodies' initial state), the
// constants hash and the header. snapshot_scene.cpp; World<T>'s parts are in
// snapshot.hpp.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lockstep/scene.hpp"
#include "lockstep/snapshot.hpp"
#include "snapshot_bytes.hpp"

namespace lockstep::snap {

namespace detail {
// The longest name a snapshot may hold (bytes).
inline constexpr std::size_t kMaxNameBytes = 1u << 20;

// Every field of Constants, in declaration order. A field added to Constants
// changes its size: the static_assert asks for it to be added here (and the
// format version raised).
template <class C, class D, class I>
inline void each_constant(C& c, D&& dbl, I&& integer) {
  dbl(c.dt);
  dbl(c.gravity.x); dbl(c.gravity.y); dbl(c.gravity.z);
  dbl(c.linear_damping); dbl(c.angular_damping); dbl(c.cell_size); dbl(c.slop); dbl(c.baumgarte);
  integer(c.solver_iterations);
  dbl(c.contact_tolerance); dbl(c.converged_speed); dbl(c.kp); dbl(c.kd); dbl(c.speed_factor_min);
  dbl(c.speed_factor_max); dbl(c.support_normal_min); dbl(c.align_fine); dbl(c.align_good); dbl(c.align_fair);
  dbl(c.damp_fine); dbl(c.damp_good); dbl(c.damp_fair); dbl(c.rest_speed); dbl(c.restitution_min_speed);
  dbl(c.settle_speed); dbl(c.settle_damping); dbl(c.sleep_linear); dbl(c.sleep_angular); dbl(c.sleep_alignment);
  integer(c.drowsy_frames);
  dbl(c.drowsy_damping);
  integer(c.sleep_frames);
  dbl(c.wake_speed); dbl(c.wake_penetration); dbl(c.wake_support_distance);
}
static_assert(sizeof(Constants) == 33 * sizeof(double) + 3 * alignof(double) || sizeof(Constants) == 33 * sizeof(double) + 3 * sizeof(int), "a constant was added: add it to each_constant and raise kSnapshotVersion");


inline Effects effects_of(std::uint16_t v) {
  Effects fx;
  bool* bits[] = {&fx.gravity, &fx.damping, &fx.ground, &fx.contacts, &fx.friction, &fx.restitution, &fx.settling, &fx.sleep, &fx.sdf};
  for (int i = 0; i < 9; ++i) *bits[i] = (v >> i) & 1u;
  return fx;
}

}  // namespace detail


// The scene section of `scene`'s snapshots: name, frames, pair model,
// effects, constants, ground, SDF volumes, the table of distinct body shapes
// (half extents, mass, material, static) and each body's shape, as runs.
std::vector<std::uint8_t> encode_scene_section(const Scene& scene);

// FNV-1a 64 over the constants block (Constants in declaration order: doubles
// as IEEE binary64 bits, ints as int32, little-endian).
std::uint64_t constants_hash(const Constants& c);

// Reads a scene section: the Scene with every body's shape, its pose the
// origin and at rest (the caller sets the state). Checks it as the scene
// loader does (validate_scene) and that it holds body_count bodies; throws
// SnapshotError.
Scene read_scene_section(Reader& r, std::uint32_t body_count);

// Reads the scene section of a snapshot whose header is `info` and checks it
// against the header's constants hash and the engine's number type
// (validate_scene_for; `engine` names it in the message: "this engine",
// "the gpu engine"); throws SnapshotError.
Scene read_checked_scene(Reader& r, const SnapshotInfo& info, const char* number_type, const char* engine);

// Writes the 40-byte header; the size and checksum are patched by finish().
void write_header(Writer& w, SnapshotNumber number, std::uint32_t body_count, std::uint64_t constants_hash,
                  std::uint32_t frame);
// Patches the total size into the header and appends the checksum.
void finish(std::vector<std::uint8_t>& out);

}  // namespace lockstep::snap
