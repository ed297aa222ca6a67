// The comparison harness: runs engines side by side on one scene, frame by
// frame (record), then judges their agreement with a baseline engine (judge)
// on trajectories, resting states and sleep times, or, for chaotic scenes, on
// statistics. docs/COMPARE.md describes every check.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/tolerances.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::compare {

// One engine at one frame, against the baseline engine at the same frame.
struct FrameStats {
  int frame = 0;
  double pos_max = 0;  // max over bodies of |p_e - p_base| (m)
  double pos_rms = 0;  // RMS over bodies of |p_e - p_base| (m)
  int pos_body = -1;   // the body of pos_max
  double ori_max = 0;  // max over bodies of the angle between q_e and q_base (rad)
  double ori_rms = 0;  // (rad)
  int ori_body = -1;
  double energy = 0;   // kinetic + potential (J)
  int asleep = 0;      // bodies asleep
};

// A run that stopped (RunError): where and why; or, refused, an engine that
// cannot run the scene at all (make_engine threw SceneError: its number type
// cannot hold a body, lockstep/scene_limits.hpp): frame 0, quantity the
// field's path ("bodies[0].mass"), message the SceneError's.
struct RunFailure {
  int frame = -1, body = -1;
  std::string quantity, message;
  bool refused = false;
};

struct EngineTrack {
  std::string name, description;
  std::vector<FrameStats> frames;          // frames[f] is frame f; frames[0] is the loaded scene
  std::vector<BodySnapshot> final_bodies;  // at the last frame run
  // Per body, the frames asleep: [first, end) intervals (end = frames_run + 1 while still asleep).
  std::vector<std::vector<std::pair<int, int>>> asleep_intervals;
  int frames_run = 0;
  double step_seconds = 0;  // total wall time inside step() (s)
  bool failed = false;
  RunFailure failure;
};

struct Recording {
  Scene scene;
  int frames = 0;    // frames asked for
  int baseline = 0;  // index into engines
  std::vector<EngineTrack> engines;
};

struct RecordOptions {
  int frames = -1;  // -1: scene.frames
  // Called after each frame with (frames done, frames total).
  std::function<void(int, int)> progress;
  // Called for every engine still running at frame 0 and after each frame,
  // with the engine's index and the engine (e.g. a ViewRecorder, view.hpp).
  std::function<void(int, const EngineRun&)> observe;
};

// Steps every engine one frame at a time; after each frame compares each
// engine's bodies with the baseline's. An engine that throws RunError stops
// (its failure is recorded); the others go on.
Recording record(const Scene& scene, std::vector<std::unique_ptr<EngineRun>> engines, int baseline,
                 const RecordOptions& options = {});
// The same, making the engines by name (make_engine). An engine that refuses
// the scene (SceneError) is recorded as failed at frame 0 with no frames
// (failure.refused); the others run and are judged as usual.
Recording record(const Scene& scene, const std::vector<std::string>& engine_names, const std::string& baseline,
                 const RecordOptions& options = {});

// One check of one engine against the baseline.
struct Finding {
  std::string engine;     // the engine compared with the baseline
  std::string check;      // "trajectory", "rest", "sleep", "statistics", "run"
  std::string quantity;   // e.g. "position", "face up", "sleep frame", "height histogram"
  int body = -1;          // -1: not about one body
  int frame = -1;         // the frame it is about (-1: none)
  std::string value;      // the engine's value, as text with its unit
  std::string baseline_value;
  std::string tolerance;  // as text, e.g. "<= 0.05 m", "+-10 frames", "equal"
  bool pass = true;
  std::string message(const std::string& baseline_name) const;  // one line naming body, frame and quantity
};

struct EngineVerdict {
  std::string engine;
  bool is_baseline = false;
  // Trajectory divergence from the baseline over all frames run by both.
  double pos_max = 0, pos_rms = 0;  // (m): max and RMS over frames and bodies
  double ori_max = 0, ori_rms = 0;  // (rad)
  // The first frame a body exceeds a trajectory tolerance ("trajectories
  // part"); -1 if never.
  int parted_frame = -1, parted_body = -1;
  std::string parted_quantity;
  int checks = 0, failures = 0;
  std::vector<Finding> findings;  // every check, passed or not
};

struct Verdict {
  CompareTolerances tolerances;
  std::string baseline;
  std::vector<EngineVerdict> engines;
  bool agree() const;
  std::vector<Finding> failures() const;
};

Verdict judge(const Recording& recording, const CompareTolerances& tolerances);

}  // namespace lockstep::compare
