// The GPU engine's snapshot body (docs/SNAPSHOTS.md "The GPU engine"): after
// the header (number type 5) and the scene section that World<T>'s snapshots
// share, the engine's state (gpu_state.hpp) as little-endian bytes. Reading
// checks every count against the bytes left before allocating, every index
// against the body count and every value against the engine's ranges, and
// throws SnapshotError naming the field: never undefined behaviour.
#pragma once
#include <cstdint>
#include <vector>

#include "gpu_state.hpp"
#include "initial_state.hpp"

namespace lockstep::gpu {

// The options byte: how the saved engine solved body pairs.
inline constexpr std::uint8_t kSnapshotJacobi = 1;

// Appends the state (after the scene section) to `out`.
// For float ("gpu", number type 5) and Q16 ("gpu-fixed", number type 6):
// the same fields, each value's 4 bytes (IEEE bits, or the raw Q16.16).
template <class T>
void write_gpu_state(std::vector<std::uint8_t>& out, const GpuState<T>& s, std::uint8_t options, bool oriented,
                     int imm_stride);

// Reads the state after the scene section; `init` is the scene's initial state
// (static flags, the inverse masses pos.w). The options byte is returned in `options`.
template <class T>
GpuState<T> read_gpu_state(const std::uint8_t* data, std::size_t size, const InitialState<T>& init, int imm_stride,
                           std::uint32_t frame, std::uint8_t& options);

}  // namespace lockstep::gpu
