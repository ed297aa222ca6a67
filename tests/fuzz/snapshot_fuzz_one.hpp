// One fuzz input through the snapshot loaders (World<T>::load_state, and
// GpuWorld::load_state for the GPU engine's snapshots, number type 5), shared
// by the libFuzzer target (snapshot_fuzz.cpp) and the replay driver
// (snapshot_replay.cpp). docs/FUZZING.md "Snapshots".
//
// The contract it checks (any breach is a FuzzFinding):
//  - the input as it is, and a copy whose header size and checksum are made
//    to match it (so that mutations reach the parser behind the checksum),
//    either load or throw SnapshotError with a non-empty message; no other
//    exception, no crash, no sanitizer report;
//  - a snapshot that loads saves again to bytes that load and save to the
//    same bytes (save(load(save(load(x)))) == save(load(x)));
//  - a fixed-engine snapshot that loads with at most kMaxFuzzBodies bodies is
//    stepped kMaxSnapshotFuzzFrames frames; a RunError is a clean stop.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene_fuzz_one.hpp"

namespace lockstep::fuzz {

inline constexpr int kMaxSnapshotFuzzFrames = 4;

// kRejected: both copies refused; kLoaded / kRan / kStopped: one loaded
// (and the fixed engine's ran or stopped).
Outcome fuzz_one_snapshot(const std::uint8_t* data, std::size_t size);

// The repository's seeds: snapshots of small built-in scenes on every engine.
std::vector<std::pair<std::string, std::vector<std::uint8_t>>> snapshot_seeds();

}  // namespace lockstep::fuzz
