// The number-type-free parts of a snapshot (docs/SNAPSHOTS.md): the scene
// section (everything of the Scene but the bodies' initial state), the
// constants hash and the header. snapshot_scene.cpp; World<T>'s parts are in
// snapshot.hpp.
#pragma once
#include <cstdint>
#include <vector>

#include "lockstep/scene.hpp"
#include "lockstep/snapshot.hpp"
#include "snapshot_bytes.hpp"

namespace lockstep::snap {

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

// Writes the 40-byte header; the size and checksum are patched by finish().
void write_header(Writer& w, SnapshotNumber number, std::uint32_t body_count, std::uint64_t constants_hash,
                  std::uint32_t frame);
// Patches the total size into the header and appends the checksum.
void finish(std::vector<std::uint8_t>& out);

}  // namespace lockstep::snap
