// Shared by the hard-case tests: loading the catalogue, the engines to run,
// a monitored run, and the criteria every hard case shares
// (docs/HARD_CASES.md, "Every case").
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "hard_monitor.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/scene_json.hpp"

namespace lockstep::hard {

// tests/data/hard/<name>.json.
inline Scene load_hard_scene(const std::string& name) {
  return load_scene_file(std::string(LOCKSTEP_HARD_SCENE_DIR) + "/" + name + ".json");
}

// fixed, float, double, then mp when asked (it is ~100x slower), then gpu
// when the GPU engine is built (engine_names() lists it).
inline std::vector<std::string> engines_for(bool with_mp) {
  std::vector<std::string> out{"fixed", "float", "double"};
  if (with_mp) out.emplace_back("mp");
  for (const std::string& e : engine_names())
    if (e == "gpu") out.push_back(e);
  return out;
}

// One engine running one scene under a Monitor.
struct MonitoredRun {
  Scene scene;
  std::unique_ptr<EngineRun> run;
  std::unique_ptr<Monitor> monitor;
  std::string error;  // the RunError that stopped it ("" if none): "frame F, body B, quantity Q: what"

  // Every engine runs the case's scene as it is, its pair model included.
  MonitoredRun(Scene s, const std::string& engine) : scene(std::move(s)) {
    run = make_engine(engine, scene);
    monitor = std::make_unique<Monitor>(scene, *run);
  }
  // Runs to `frames` frames; stops at a RunError (recorded in error) or at
  // the first non-finite state.
  void run_to(int frames) {
    try {
      monitor->run_to(frames);
    } catch (const RunError& e) {
      error = "frame " + std::to_string(e.frame) + ", body " + std::to_string(e.body) + ", quantity '" + e.quantity +
              "': " + e.what();
    }
  }
  const MonitorStats& stats() const { return monitor->stats(); }
  std::string summary() const { return monitor->summary(); }
};

// Every hard case, every engine (docs/HARD_CASES.md "Every case"): ran every
// frame without a run error (no overflow, not silent either), no non-finite
// value, the energy within its allowance, no asleep body moved, no resting
// body deeper in the ground than its bound.
inline void expect_every_case_criteria(const MonitoredRun& r, int frames) {
  const MonitorStats& s = r.stats();
  EXPECT_EQ(r.error, "") << "run error\n" << r.summary();
  EXPECT_EQ(s.frames, frames) << r.summary();
  EXPECT_EQ(s.nonfinite_frame, -1) << "non-finite state at frame " << s.nonfinite_frame << ", body "
                                   << s.nonfinite_body << "\n" << r.summary();
  EXPECT_LE(s.worst_excess, 0.0) << "energy above E(0) + allowance at frame " << s.worst_excess_frame << ": E = "
                                 << s.worst_energy << " J, E(0) = " << s.e0 << " J, allowance = "
                                 << s.worst_allowance << " J\n" << r.summary();
  EXPECT_EQ(s.asleep_moved, 0) << "an asleep body moved: first at frame " << s.first_asleep_moved_frame << ", body "
                               << s.first_asleep_moved_body << "\n" << r.summary();
  EXPECT_LE(s.resting_excess, 0.0) << "a resting body is deeper in the ground than its bound: body "
                                   << s.resting_excess_body << " at frame " << s.resting_excess_frame << ", depth "
                                   << s.resting_excess_depth << " m, " << s.resting_excess << " m over\n"
                                   << r.summary();
}

// How deep below the ground a body resting alone may lie (m): slop, plus what
// it can move in the frame it falls asleep (|v| < sleep_linear, |w| <
// sleep_angular, corners at |h| from the centre), plus rounding. The Monitor
// applies the same bound (plus the load of a body resting on it) to every
// asleep body.
inline double resting_depth_bound(const Scene& s, int i) {
  const Constants& c = s.constants;
  const Vec3d& h = s.bodies[static_cast<std::size_t>(i)].half_extents;
  return c.slop + (c.sleep_linear + c.sleep_angular * std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z)) * c.dt +
         kPositionRounding;
}

// Every dynamic body asleep at the end.
inline void expect_all_asleep(const MonitoredRun& r) {
  EXPECT_TRUE(r.monitor->all_asleep()) << r.monitor->awake_count() << " bodies still awake after "
                                       << r.stats().frames << " frames\n" << r.summary();
}

// Body i ended within `horizontal` (m) of its start in x and z, and within
// `vertical` (m) of y_expected.
inline void expect_rests_at(const MonitoredRun& r, int i, double x, double y, double z, double horizontal,
                            double vertical) {
  const BodySnapshot& b = r.monitor->state()[static_cast<std::size_t>(i)];
  const double dh = std::hypot(b.p[0] - x, b.p[2] - z);
  EXPECT_LE(dh, horizontal) << "body " << i << " ends at (" << b.p[0] << ", " << b.p[1] << ", " << b.p[2]
                            << "), " << dh << " m horizontally from (" << x << ", " << z << ")";
  EXPECT_LE(std::fabs(b.p[1] - y), vertical) << "body " << i << " ends at y = " << b.p[1] << ", expected " << y
                                             << " +- " << vertical;
}

// Body i ended flat on the ground: the body axis closest to vertical within
// acos(sleep_alignment) and the centre at that axis' half extent above the
// ground, within `vertical` (m).
inline void expect_flat_on_ground(const MonitoredRun& r, int i, double vertical) {
  const BodySnapshot& b = r.monitor->state()[static_cast<std::size_t>(i)];
  const BodyGeometry& g = r.monitor->geometry()[static_cast<std::size_t>(i)];
  const Vec3d& h = r.scene.bodies[static_cast<std::size_t>(i)].half_extents;
  const double hs[3] = {h.x, h.y, h.z};
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(g.R[1][a]) > std::fabs(g.R[1][axis])) axis = a;
  EXPECT_GE(g.alignment, r.scene.constants.sleep_alignment) << "body " << i << " is not flat: alignment "
                                                            << g.alignment;
  const double expected = r.scene.ground.height + hs[axis];
  EXPECT_LE(std::fabs(b.p[1] - expected), vertical) << "body " << i << " ends at y = " << b.p[1]
                                                    << ", flat on its axis " << axis << " it rests at " << expected;
}

}  // namespace lockstep::hard
