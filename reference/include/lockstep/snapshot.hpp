// Snapshots of a World<T>: the byte format's constants, its error and a
// reader of the header. World<T>::save_state / load_state / restore_state
// (lockstep/world.hpp) write and read the whole format; docs/SNAPSHOTS.md
// documents it byte by byte.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace lockstep {

// A snapshot that cannot be loaded: truncated, corrupt (checksum, a value out
// of range, an index past the body count), foreign (another number type,
// another format version) or not a snapshot at all. what() names what is
// wrong and where ("snapshot: body 12: position x = 40000 m is outside ...");
// field names the part ("header.version", "bodies[12].p", "warm[3].a"), empty
// when no single field is at fault.
struct SnapshotError : std::runtime_error {
  std::string field;
  SnapshotError(const std::string& message, std::string field_path)
      : std::runtime_error("snapshot: " + message), field(std::move(field_path)) {}
};

inline constexpr char kSnapshotMagic[8] = {'L', 'K', 'S', 'T', 'S', 'N', 'A', 'P'};
inline constexpr std::uint16_t kSnapshotVersion = 2;
inline constexpr std::size_t kSnapshotHeaderSize = 40;
inline constexpr std::size_t kSnapshotChecksumSize = 8;

// The number type byte of the header; 5: the GPU engine's snapshots (float,
// its own body of the format: docs/SNAPSHOTS.md "The GPU engine").
enum class SnapshotNumber : std::uint8_t { kFixed = 1, kFloat = 2, kDouble = 3, kMp = 4, kGpu = 5, kGpuFixed = 6 };
// "fixed", "float", "double", "mp" (Num<T>::kName, the engine's name), "gpu", or "?".
const char* snapshot_number_name(SnapshotNumber n);

// The header of a snapshot, checked (magic, version, declared size, checksum)
// but not its body: what a tool needs to pick the engine (`lockstep run
// --load-state` reads the number type here).
struct SnapshotInfo {
  std::uint16_t version = 0;
  SnapshotNumber number = SnapshotNumber::kFixed;
  std::uint32_t body_count = 0;
  std::uint64_t constants_hash = 0;  // FNV-1a 64 of the scene section's constants block
  std::uint32_t frame = 0;
  std::uint64_t size = 0;            // bytes, header and checksum included
};

// Throws SnapshotError when the bytes are not a whole, intact snapshot of a
// version this build reads.
SnapshotInfo read_snapshot_info(const std::uint8_t* data, std::size_t size);

}  // namespace lockstep
