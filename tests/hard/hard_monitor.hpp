// Monitor: steps an engine frame by frame and records, from the body
// snapshots alone (so it works for every engine, the GPU one included), the
// quantities the hard-case criteria of docs/HARD_CASES.md are stated in:
//  - non-finite values (NaN, infinity) in any body's state;
//  - the energy E (kinetic + gravitational potential, the latter only with the
//    gravity effect on; recomputed in double from the state) against the
//    allowance of docs/HARD_CASES.md:
//      E(n) <= E(0) + C(n) + S(n) + W(n) + tol
//    C(n): per body, m |g| max(0, D - slop) * baumgarte, D the deepest
//          penetration of a contact whose correction (eqs 63, 89, 110) lifts
//          it (the ground; a body-body contact along y, for the upper body;
//          with the oriented-box model, eqs 100-106, the pair manifold's
//          deepest point times |n_y|, for the side n points to, plus the
//          lift of its lower side carried up eq 110's chain, speculative
//          pairs within eq 107's reach included) in frames 1..n, measured
//          on the state each frame starts from (what its narrow phase
//          sees): one lift out of the deepest penetration;
//    S(n): per body, 1/2 I_max w_d^2, w_d = kp * max(speed_factor_min,
//          speed_factor_max) * the largest misalignment (1 - eq 66, against
//          y and against its support normals) the body has had while
//          touching something (within contact_tolerance: a speculative
//          contact, eq 97): the most spin the righting torque
//          (eqs 67-71) can set up;
//    W(n): the engine keeps w constant while a body turns (eq 11 with
//          alpha = 0: no gyroscopic term), so the rotational energy
//          1/2 w . I_world w of a non-cubic body changes as it turns: summed
//          over frames 1..n and bodies, 1/2 w(k).(I_world(k) - I_world(k-1))
//          w(k) from the states (0 for a cube), and W = max(0, that sum);
//    tol:  the rounding of the state (docs/HARD_CASES.md, "Tolerance");
//  - the resting depth: a body asleep (that has been awake) lies at most
//      slop + (sleep_linear + sleep_angular |h|) dt + L + kPositionRounding
//    below the ground, L the y-overlap of a body resting on it (the share of
//    eq 89 that pushes it down);
//  - speeds, spins, ground depths, quaternion norms, displacements, body-body
//    overlaps, and asleep bodies whose state changes while they sleep.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "body_geometry.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::hard {

inline constexpr double kNegInf = -std::numeric_limits<double>::infinity();
// The rounding allowed on a position or height (m): 16 ulps of Q16.16 (each
// frame floors positions and the rotation matrix's entries), far above the
// roundings of float and double at the scale of the scenes.
inline constexpr double kPositionRounding = 0x1p-12;

struct MonitorStats {
  int frames = 0;                 // frames stepped
  // Non-finite state (first occurrence).
  int nonfinite_frame = -1;
  int nonfinite_body = -1;
  // Energy (J).
  double e0 = 0.0;                // E(0)
  double e_last = 0.0;            // E(frames)
  double worst_excess = kNegInf;  // max_n E(n) - (E(0) + C(n) + S(n) + W(n) + tol); > 0 breaks the bound
  int worst_excess_frame = 0;
  double worst_energy = 0.0;      // E(n) at that frame
  double worst_allowance = 0.0;   // C(n) + S(n) + W(n) + tol at that frame
  double correction_allowance = 0.0;  // C(frames)
  double righting_allowance = 0.0;    // S(frames)
  double spin_allowance = 0.0;        // W(frames)
  double tolerance = 0.0;             // tol
  // Kinematics over every frame and dynamic body.
  double max_speed = 0.0;         // |v| (m/s)
  double max_spin = 0.0;          // |w| (rad/s)
  double max_depth = 0.0;         // deepest corner below the ground after a frame (m)
  int max_depth_frame = 0;
  int max_depth_body = -1;
  double min_centre_height = std::numeric_limits<double>::infinity();  // min p.y - ground height (m)
  double max_q_dev = 0.0;         // max | |q| - 1 |
  int max_q_dev_frame = 0;
  double max_pair_overlap = 0.0;  // deepest body-body AABB overlap after a frame (m)
  double final_pair_overlap = 0.0;  // the same in the last state (m)
  std::vector<double> max_horizontal;  // per body: max horizontal distance from its start (m)
  std::vector<double> max_distance;    // per body: max 3-D distance from its start (m)
  // Rest and sleep.
  double resting_excess = kNegInf;  // max over asleep bodies of depth - its resting bound (m); > 0 breaks it
  int resting_excess_frame = 0;
  int resting_excess_body = -1;
  double resting_excess_depth = 0.0;  // the depth there (m)
  int asleep_moved = 0;           // (body, frame) cases where an asleep body changed state or had v, w != 0
  int first_asleep_moved_frame = -1;
  int first_asleep_moved_body = -1;
  int all_asleep_frame = -1;      // first frame after which every dynamic body was asleep
  std::vector<int> first_awake_frame;  // per body: first frame after which it was awake (0: awake at the start, -1: never)
};

class Monitor {
 public:
  // The run must be at frame 0 of `scene`; both must outlive the monitor.
  Monitor(const Scene& scene, EngineRun& run);
  // One frame: run.step() (a RunError propagates), then the checks.
  void step();
  // Steps until `frames` frames are done, or the first non-finite state.
  void run_to(int frames);
  const MonitorStats& stats() const { return stats_; }
  // The state after the last frame, and at frame 0.
  const std::vector<BodySnapshot>& state() const { return prev_; }
  const std::vector<BodySnapshot>& start() const { return start_; }
  const std::vector<BodyGeometry>& geometry() const { return prev_geom_; }
  double energy() const { return stats_.e_last; }
  bool all_asleep() const;
  int awake_count() const;
  // One line with the numbers, for failure messages and reports.
  std::string summary() const;

 private:
  // What the narrow phase finds in a state (per body): the deepest
  // penetration of a contact whose correction lifts it (lift), the deepest
  // y-overlap of a body resting on it (load), whether it touches anything;
  // and the deepest body-body overlap.
  struct ContactView {
    std::vector<double> lift, load;
    std::vector<char> touching;
    std::vector<double> misalign;  // 1 - eq 66 against its support normals (0: none)
    double deepest_pair = 0.0;
  };
  ContactView contacts_of(const std::vector<BodySnapshot>& s, const std::vector<BodyGeometry>& g) const;
  std::vector<BodySnapshot> snapshot() const;
  std::vector<BodyGeometry> geometries(const std::vector<BodySnapshot>& s) const;
  double energy_of(const std::vector<BodySnapshot>& s, const std::vector<BodyGeometry>& g) const;

  const Scene& scene_;
  EngineRun& run_;
  double g_up_ = 0.0;  // -g.y (m/s^2); 0 with the gravity effect off
  std::vector<BodySnapshot> start_, prev_;
  std::vector<BodyGeometry> prev_geom_;
  std::vector<double> max_misalign_;  // per body, while touching
  std::vector<double> max_lift_;      // per body (m)
  double spin_sum_ = 0.0;             // the sum of W(n) (J)
  std::vector<char> was_awake_;       // per body: awake at some frame
  MonitorStats stats_;
};

}  // namespace lockstep::hard
