// Recording a run and replaying it (docs/RECORDINGS.md): `lockstep run
// --record` and `lockstep replay`. A replay re-simulates the recording's
// scene and inputs on an engine and names the first frame whose state hash
// (eq 92) differs from the recorded one, then the body and field at that
// frame, then the stage of the frame (docs/SPEC.md 7.2) where the two runs
// part, re-running the frame stage by stage on both sides.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/recording.hpp"

namespace lockstep::compare {

// Applies a run-time input to an engine (its frame is the engine's next).
// Throws std::invalid_argument for an input the engine cannot take.
void apply_input(EngineRun& engine, const Input& input);

// Makes an engine by name for a scene (make_engine, or a test's own engines).
using EngineFactory = std::function<std::unique_ptr<EngineRun>(const std::string& name, const Scene& scene)>;

struct RecordRunOptions {
  int snapshot_every = 0;  // a snapshot every K frames besides the last (0: the last only); engines with snapshots
  std::string build;       // build_description(...)
  // Called after frame 0 and after each frame (e.g. the trajectory writer of `lockstep run`).
  std::function<void(const EngineRun&)> after_frame;
};

// What `lockstep run --record` does around its own loop: before_step applies
// the inputs of the frame about to be computed, after_step keeps the hash
// (and the snapshot every K frames and at the last).
class RunRecorder {
 public:
  // Checks the inputs against the scene (validate_inputs, source "--inputs").
  RunRecorder(const std::string& engine_name, const Scene& scene, std::vector<Input> inputs, int frames,
              const RecordRunOptions& options);
  void before_step(EngineRun& engine);
  void after_step(const EngineRun& engine);
  const RunRecording& recording() const { return rec_; }

 private:
  RunRecording rec_;
  std::size_t next_ = 0;
};

// Runs `engine` (at frame 0 of `scene`) for `frames` frames, applying each
// input before the step that computes its frame, and returns the recording.
// Throws RunError as the engine does, std::invalid_argument for an input it
// cannot take.
RunRecording record_run(EngineRun& engine, const std::string& engine_name, const Scene& scene,
                        const std::vector<Input>& inputs, int frames, const RecordRunOptions& options);

// A difference between two sets of bodies: the first body (index order) and
// field (p.x, p.y, p.z, q.w, ..., w.z, asleep, sleep_frame) that differ.
struct BodyDifference {
  int body = -1;  // -1: none (or the body counts differ: field "body count")
  std::string field;
  double recorded = 0, replayed = 0;
  int bodies_differing = 0;
};
BodyDifference first_body_difference(const std::vector<BodySnapshot>& recorded, const std::vector<BodySnapshot>& replayed);

struct ReplayReport {
  std::string recorded_engine, engine, recorded_build;
  int frames = 0;                 // frames compared (all of the recording's when they agree)
  int first_frame = -1;           // the first frame whose hash differs; -1: none
  std::string replay_stopped;     // the replay's engine stopped at first_frame (RunError), why
  std::uint64_t recorded_hash = 0, replayed_hash = 0;
  // The body and field, at diff_frame (first_frame, or the first recorded
  // snapshot after it when the recorder's state at first_frame is out of reach).
  int diff_frame = -1;
  BodyDifference body;
  std::string recorder_state;     // how the recorder's state was obtained
  // The stage of first_frame where the two runs part ("5 solve", docs/SPEC.md
  // 7.2), or "before frame N: ..." when the states differ before it; empty
  // when not found, then stage_note says why.
  std::string stage;
  BodyDifference stage_body;
  std::string stage_note;
  std::string note;               // e.g. the engines' number types differ
  bool same() const { return first_frame < 0; }
};

// Replays `rec` on `engine` (engines made by `make`; the recorder's engine is
// made too, to re-run the recorder's side). Throws std::invalid_argument for
// an engine `make` refuses or inputs it cannot take.
ReplayReport replay(const RunRecording& rec, const std::string& engine, const EngineFactory& make);

// The report as `lockstep replay` prints it.
std::string replay_text(const ReplayReport& r);

}  // namespace lockstep::compare
