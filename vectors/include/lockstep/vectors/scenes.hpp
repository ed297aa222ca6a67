// Level 3 vectors: whole scenes on the fixed engine. Per scene: the scene
// itself (lockstep-scene JSON), its setup in raw Q16.16 (derived constants,
// per-body properties, SDF samples), the state hash (eq 92) after every frame,
// the full raw state at chosen frames, the sleep and wake events and each
// body's sleep frame. File: scenes/<name>.json.
#pragma once
#include <string>
#include <vector>

#include "lockstep/scene.hpp"
#include "lockstep/vectors/common.hpp"
#include "lockstep/world.hpp"

namespace lockstep::vectors {

// The 15 per-body state fields of "states", in order.
const std::vector<std::string>& state_fields();
// One body's row of "states": the 15 state_fields() as raw integers (the
// first 13 and asleep are what eq 92 hashes).
Json body_state(const Body<Q16>& body);

struct SceneVectorOptions {
  // Scenes with at most this many bodies get the full state at every frame;
  // larger ones only at sparse_frames (and the last frame).
  int full_state_max_bodies = 32;
  std::vector<int> sparse_frames = {0, 1, 2, 10, 60, 120, 300};
};

// The scene's vector document (runs scene.frames frames on World<Q16>).
Json generate_scene_vectors(const Scene& scene, const SceneVectorOptions& options = {});

struct SceneVerifyOptions {
  int max_frames = -1;  // verify frames 0..max_frames only (-1: all)
};

// Runs the scene of the document on World<Q16> and compares, frame by frame,
// the state at stored frames and the hash at every frame; then the sleep
// frames, events and counters. The first difference names frame, body and
// field (a hash difference at a frame without a stored state is located at
// the next stored frame).
Verdict verify_scene_vectors(const Json& doc, const std::string& file_name, const SceneVerifyOptions& options = {});

}  // namespace lockstep::vectors
