// What the comparison harness accepts as agreement between two engines.
//
// A scene's tolerances come from (first match): the sidecar JSON given to
// `lockstep compare --tolerances FILE` (fields it names override the rest),
// the table of built-in scenes (builtin_tolerances), or the documented
// defaults (default_tolerances). docs/COMPARE.md documents every field and
// the sidecar format ("lockstep-tolerances", version 1).
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "lockstep/scene.hpp"

namespace lockstep::compare {

// What must agree once trajectories have parted.
enum class Judge {
  bodies,      // simple scenes: every body's trajectory, resting state and sleep frame
  statistics,  // chaotic scenes (piles): trajectories are reported, not judged;
               // resting heights, faces up and sleep are judged as statistics
};

struct CompareTolerances {
  Judge judge = Judge::bodies;

  // Trajectories: per frame and body, the divergence from the baseline engine.
  // Judge::bodies fails above these; Judge::statistics reports the first frame
  // above them as "trajectories part".
  double position = 0.05;     // |p_e - p_base| (m)
  double orientation = 0.10;  // angle of q_base^-1 q_e (rad)

  // Resting states (the final frame).
  double rest_position = 0.02;  // |p_e - p_base| of the final pose (m)
  double support_gap = 0.02;    // a support's surface lies within this of the body's lowest point (m)
  double flat_alignment = 0.99; // alignment (eq 66) above which a face is up (1); below it the
                                // body rests on an edge or corner and "face up" is "none"

  // Sleep times: the frame each body last fell asleep (eq 80).
  int sleep_frames = 10;  // +- k (frames)

  // Statistics (Judge::statistics), over the dynamic bodies at the final frame.
  double height_distance = 0.10;   // earth mover's distance between the resting-height
                                   // distributions: mean |h_e(k) - h_base(k)| over the
                                   // sorted heights (m); free of histogram bin edges
  double height_bin = 0.25;        // bin width of the height histogram in the report (m)
  double face_fraction = 0.10;     // per face label (+x .. -z, none): |count_e - count_base| / N
  double asleep_fraction = 0.10;   // |asleep_e - asleep_base| / N
  int median_sleep_frames = 60;    // |median sleep frame_e - median_base| (frames)
};

// A tolerances file that cannot be used: names the field and the fix.
struct ToleranceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The documented defaults: the values above, with Judge::statistics for a
// scene of more than kBodiesJudgeMax dynamic bodies.
inline constexpr int kBodiesJudgeMax = 10;
CompareTolerances default_tolerances(const Scene& scene);

// The tolerances of a built-in scene (by name), or nullopt.
std::optional<CompareTolerances> builtin_tolerances(std::string_view scene_name);

// builtin_tolerances(scene.name) when the scene is a built-in one (same name
// and same body count), else default_tolerances(scene).
CompareTolerances tolerances_for(const Scene& scene);

// Reads a sidecar ("lockstep-tolerances" version 1): every field is optional
// and overrides `base`. Throws ToleranceError (unknown field, wrong type, out
// of range, unreadable file), naming the source and the field.
CompareTolerances parse_tolerances(std::string_view json_text, std::string_view source_name, CompareTolerances base);
CompareTolerances load_tolerances_file(const std::string& path, CompareTolerances base);
// Every field, as a sidecar that parse_tolerances reads back to the same values.
std::string tolerances_to_json(const CompareTolerances& t);

const char* judge_name(Judge j);

}  // namespace lockstep::compare
