// The replay page (`lockstep view`, `lockstep compare --report`): one
// self-contained HTML file that replays runs of one scene in 3D (three.js),
// with charts (Chart.js) linked to a frame slider; docs/COMPARE.md "The
// replay page". This header holds the data the page shows, how it is
// collected from engines (ViewRecorder) or read back from `lockstep run`'s
// files (load_run), and the page writer.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lockstep/compare/engine.hpp"
#include "lockstep/compare/tolerances.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::compare {

// Floats stored per body and kept frame: p (3), q (w, x, y, z), v (3), w (3).
inline constexpr int kViewFloats = 13;

struct ViewContact {
  int a = 0, b = -1;  // b = -1: the ground; -2 - k: SDF volume k
  float point[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
  float penetration = 0;  // (m), > 0: overlap
};

// One engine's run of the scene as the page shows it.
struct ViewRun {
  std::string label;   // shown in the page, e.g. "fixed" or "stack5-double.csv"
  std::string engine;  // "fixed", "double", ...
  int bodies = 0;
  std::vector<int> frames;            // the frames whose state is kept, ascending
  std::vector<float> state;           // frames.size() x bodies x kViewFloats
  std::vector<std::uint8_t> asleep;   // frames.size() x bodies: 1 asleep
  // Per frame 0..last (index = frame; empty when unknown):
  std::vector<std::string> hashes;    // eq 92, 16 hex digits
  std::vector<double> energy;         // (J)
  std::vector<int> contact_count;     // contacts the narrow phase found
  std::vector<double> penetration;    // deepest contact penetration (m), 0 when none
  std::vector<int> asleep_count;
  bool has_contacts = false;          // contact_count / penetration are known
  std::map<int, std::vector<ViewContact>> contacts;  // per kept frame, when recorded
  int last_frame() const { return frames.empty() ? 0 : frames.back(); }
};

// Collects a ViewRun from an engine, one frame at a time.
class ViewRecorder {
 public:
  // keep_states false: add() keeps only the contacts of kept frames (the
  // states are in `lockstep run`'s CSV).
  ViewRecorder(std::string label, std::string engine, bool record_contacts, bool keep_states = true);
  // Adds the engine's current frame; its body states (and contacts, when
  // recorded) are kept when keep_state is set.
  void add(const EngineRun& e, bool keep_state);
  const ViewRun& run() const { return run_; }
  ViewRun take() { return std::move(run_); }
  // The first frame after frame 0 where every body is asleep, the scene's
  // static bodies (never asleep: they never move) aside; -1: none.
  int all_asleep_frame() const { return all_asleep_frame_; }
  // How many of the scene's bodies are static (0 unless set).
  void set_static_bodies(int count) { static_bodies_ = count; }
  // The deepest penetration over every frame added (m); 0 when none.
  double worst_penetration() const { return worst_penetration_; }

 private:
  ViewRun run_;
  bool record_contacts_, keep_states_;
  int all_asleep_frame_ = -1;
  int static_bodies_ = 0;
  double worst_penetration_ = 0;
};

// The kept-frame stride that keeps the page's trajectory data (runs x bodies
// x kept frames x bytes) under max_bytes: 1, 2, 3, ...
int view_stride(int frames, int bodies, int runs, std::size_t max_bytes);

// The run record `lockstep run` writes beside a CSV trajectory (FILE + this
// suffix): the scene, the engine, and the per-frame hashes, energy, contact
// counts and (with --contacts) contacts. JSON, "format": "lockstep-run".
inline constexpr const char* kRunRecordSuffix = ".run.json";
std::string run_record_json(const Scene& scene, const ViewRun& run, int every, bool raw);

// Reads a trajectory CSV written by `lockstep run` and the run record beside
// it; keeps every stride-th written frame (and the last). Throws
// std::runtime_error naming the file, the line and the fix.
struct LoadedRun {
  Scene scene;
  ViewRun run;
};
LoadedRun load_run(const std::string& csv_path, int stride = 1);
// The number of frames and bodies a CSV trajectory holds, from a first pass
// (to choose a stride before loading).
struct RunShape {
  int written_frames = 0, bodies = 0;
};
RunShape run_shape(const std::string& csv_path);

// Two or more runs of one scene: the divergence of each from the first (the
// baseline) and where they part.
struct ViewComparison {
  int baseline = 0;
  double position_tolerance = 0, orientation_tolerance = 0;  // (m), (rad)
  std::vector<std::vector<double>> divergence;  // per run, per kept frame of the baseline: max |p - p_base| (m)
  std::vector<int> parted_frame;                // per run: the first kept frame beyond a tolerance; -1: never
  std::vector<int> parted_body;                 // the body that parted first; -1
  // The first frame where the per-frame hashes of two runs of one engine
  // (two fixed runs first) differ; -1 when equal or when no two runs share an engine.
  int hash_run_a = -1, hash_run_b = -1, first_hash_difference = -1;
  int hash_frames_compared = 0;
  std::string note;                             // one line for the page
  // The tolerance the divergence is judged against, named as `lockstep
  // compare` names it (its trajectory check uses the same position and
  // orientation tolerances), and one sentence for the page.
  std::string tolerance_name = "trajectory tolerance";
  std::string tolerance_note;
  // The final pose (compare's rest check, tolerance rest_position): per run,
  // max |p - p_base| over bodies at the last frame both runs hold when that
  // is both runs' last frame; -1 when not compared. The body; -1.
  double rest_position_tolerance = 0;
  std::vector<double> final_distance;
  std::vector<int> final_body;
  // Per run, the kept frames of the baseline it shares (runs written with
  // different --every are compared on their common frames only).
  std::vector<int> common_frames;
};
ViewComparison compare_runs(const std::vector<ViewRun>& runs, const CompareTolerances& tolerances);

// A recording replayed (`lockstep view FILE.rec.json`, docs/RECORDINGS.md):
// the inputs' frames (marked on the slider) and the first frame whose
// replayed hash differs from the recorded one (the page's "DIVERGED at frame
// N" overlay from that frame on).
struct ViewRecording {
  std::string recorded_engine, engine;
  std::vector<std::pair<int, std::string>> inputs;  // (frame, kind)
  int diverged_frame = -1;                          // -1: the replay agrees on every frame
  std::string note;                                 // one line: what was replayed and how it compares
};

struct ViewPage {
  std::string title;
  std::optional<ViewRecording> recording;
  Scene scene;
  std::vector<ViewRun> runs;
  std::optional<ViewComparison> comparison;
  int stride = 1;  // kept-frame stride (1: every frame)
};

// The JavaScript libraries the page inlines, read from the Debian packages
// found when lockstep was configured (libjs-three, libjs-chart.js).
struct ViewLibraries {
  std::string three, orbit_controls, chart;
};
// Throws std::runtime_error naming the missing file and the package to install.
ViewLibraries load_view_libraries();

// The page: HTML with the libraries, the page's own script and the data
// (trajectories as base64 float32) inlined.
std::string view_html(const ViewPage& page, const ViewLibraries& libraries);
// The size in bytes of the page's trajectory data before base64.
std::size_t view_data_bytes(const ViewPage& page);

std::string hash_hex(std::uint64_t h);

}  // namespace lockstep::compare
