// The hard-case catalogue (tests/data/hard/*.json, docs/HARD_CASES.md) on
// every engine: each scene runs for its own "frames" and must meet the
// criteria every case shares (hard_case.hpp) and its own resting state.
// HardCatalogue/Case.Stable/<scene>_<engine>. mp runs every scene but
// crowd_cell (2048 bodies: minutes in mp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "hard_case.hpp"

namespace lockstep::hard {
namespace {

using Check = void (*)(const MonitoredRun&);

// A stack of unit cubes on the ground stays standing: every cube within
// 0.05 m horizontally of its start (Appendix C "stack"), and no lower than
// its start by more than one resting depth (the Monitor's bound: slop plus
// what it may move in the frame it falls asleep) per contact below it (the
// ground and the cubes under it: level + 1 contacts, level = y0 - 0.5 m).
void check_stays_standing(const MonitoredRun& r) {
  expect_all_asleep(r);
  for (std::size_t i = 0; i < r.scene.bodies.size(); ++i) {
    const Vec3d& p = r.scene.bodies[i].position;
    const double contacts = std::round(p.y - 0.5) + 1.0;
    expect_rests_at(r, static_cast<int>(i), p.x, p.y, p.z, 0.05, contacts * resting_depth_bound(r.scene, static_cast<int>(i)));
  }
}

void check_spin200(const MonitoredRun& r) {
  expect_all_asleep(r);
  for (int i = 0; i < 3; ++i) expect_flat_on_ground(r, i, 0.01);
  // The upright top spins in place: its four ground corners are symmetric.
  const Vec3d& p = r.scene.bodies[0].position;
  expect_rests_at(r, 0, p.x, p.y, p.z, 0.05, 0.01);
}

void check_impact50(const MonitoredRun& r) {
  const Constants& c = r.scene.constants;
  expect_all_asleep(r);
  for (std::size_t i = 0; i < r.scene.bodies.size(); ++i) expect_flat_on_ground(r, static_cast<int>(i), 0.01);
  // No tunnelling: a body is never deeper in the ground than one frame of
  // its approach (the frame it arrives: at most its launch speed plus what
  // gravity adds on the way down) plus slop; the next frame's correction
  // (eq 89, baumgarte 1) lifts it out.
  double approach = 0.0;
  for (const BodyDesc& b : r.scene.bodies) {
    const double drop = b.position.y - b.half_extents.y - r.scene.ground.height;
    approach = std::max(approach, std::sqrt(b.velocity.y * b.velocity.y - 2.0 * c.gravity.y * drop));
  }
  const double bound = approach * c.dt + c.slop;
  EXPECT_LE(r.stats().max_depth, bound) << "deeper than one frame of approach: body " << r.stats().max_depth_body
                                        << " at frame " << r.stats().max_depth_frame << "\n" << r.summary();
}

void check_overlap_spawn(const MonitoredRun& r) {
  const Scene& s = r.scene;
  expect_all_asleep(r);
  // No explosion: the correction moves positions only (eq 89), so a speed
  // can only come from falling: at most from the highest spawn height plus
  // one lift out of the deepest possible overlap (a body's full size).
  double fall = 0.0;
  for (const BodyDesc& b : s.bodies)
    fall = std::max(fall, b.position.y - s.ground.height - b.half_extents.y + 2.0 * b.half_extents.y);
  const double v_bound = std::sqrt(2.0 * -s.constants.gravity.y * fall);
  EXPECT_LE(r.stats().max_speed, v_bound) << r.summary();
  // Bounded separation: 4 unit cubes at one point need 1.5 m to lie side by
  // side; nobody travels more than 2 m.
  for (std::size_t i = 0; i < s.bodies.size(); ++i)
    EXPECT_LE(r.stats().max_distance[i], 2.0) << "body " << i << "\n" << r.summary();
  // Separated at the end: no body more than 1 cm inside another.
  EXPECT_LE(r.stats().final_pair_overlap, 0.01) << r.summary();
}

void check_thin(const MonitoredRun& r) {
  expect_all_asleep(r);
  for (std::size_t i = 0; i < r.scene.bodies.size(); ++i) expect_flat_on_ground(r, static_cast<int>(i), 0.005);
  const Vec3d& p = r.scene.bodies[0].position;
  expect_rests_at(r, 0, p.x, 0.01, p.z, 0.05, 0.005);
}

void check_large(const MonitoredRun& r) {
  expect_all_asleep(r);
  const Vec3d& big = r.scene.bodies[0].position;
  expect_rests_at(r, 0, big.x, big.y, big.z, 0.01, 0.01);
  const Vec3d& small = r.scene.bodies[1].position;
  expect_rests_at(r, 1, small.x, big.y + 50.0 + 0.5, small.z, 0.05, 0.01);
}

void check_q16_edge(const MonitoredRun& r) {
  expect_all_asleep(r);
  const double rest_y[3] = {0.5, 1.5, 0.5};
  for (int i = 0; i < 3; ++i) {
    const Vec3d& p = r.scene.bodies[static_cast<std::size_t>(i)].position;
    expect_rests_at(r, i, p.x, rest_y[i], p.z, 0.05, 0.01);
  }
}

void check_crowd_cell(const MonitoredRun& r) {
  expect_all_asleep(r);
  for (std::size_t i = 0; i < r.scene.bodies.size(); ++i) {
    const Vec3d& p = r.scene.bodies[i].position;
    const double rest_y = i < 1024 ? 0.05 : 0.15;  // lower layer, upper layer (1 cm drop)
    expect_rests_at(r, static_cast<int>(i), p.x, rest_y, p.z, 0.02, 0.01);
    if (::testing::Test::HasFailure()) return;  // one body's report is enough
  }
}

// The sleeper wakes when the heavy cube lands on it; both come to rest, the
// cube on top of the box, where it landed.
void check_heavy_on_sleeper(const MonitoredRun& r) {
  const int woke = r.stats().first_awake_frame[0];
  EXPECT_GT(woke, 0) << "the sleeper never woke\n" << r.summary();
  expect_all_asleep(r);
  const Vec3d& box = r.scene.bodies[0].position;
  const Vec3d& cube = r.scene.bodies[1].position;
  expect_rests_at(r, 0, box.x, box.y, box.z, 0.05, 0.01);
  expect_rests_at(r, 1, cube.x, 2.0 * r.scene.bodies[0].half_extents.y + r.scene.bodies[1].half_extents.y, cube.z,
                  0.05, 0.01);
}

// An inelastic impact with nothing else acting: the energy check of every
// case is the criterion; at the end the plate no longer approaches the ground.
void check_plate_impact(const MonitoredRun& r) {
  EXPECT_GE(r.monitor->state()[0].v[1], -1e-3) << r.summary();
  EXPECT_LE(r.stats().e_last, r.stats().e0) << r.summary();
}

// A bouncing, spinning impact with nothing else acting: the energy check of
// every frame is the criterion; at the end the plate has left the ground
// with less energy than it came with.
void check_spin_bounce(const MonitoredRun& r) {
  EXPECT_LE(r.stats().e_last, r.stats().e0) << r.summary();
  EXPECT_GT(r.monitor->state()[0].p[1], 1.0) << "the plate did not leave the ground\n" << r.summary();
}

struct CatalogueCase {
  const char* scene;
  bool mp;
  Check check;
};

const CatalogueCase kCases[] = {
    {"stack20", true, check_stays_standing},
    {"pyramid21", true, check_stays_standing},
    {"mass_ratio", true, check_stays_standing},
    {"spin200", true, check_spin200},
    {"impact50", true, check_impact50},
    {"overlap_spawn", true, check_overlap_spawn},
    {"thin", true, check_thin},
    {"large", true, check_large},
    {"q16_edge", true, check_q16_edge},
    {"heavy_on_sleeper", true, check_heavy_on_sleeper},
    {"plate_impact", true, check_plate_impact},
    {"spin_bounce", true, check_spin_bounce},
    {"crowd_cell", false, check_crowd_cell},
};

struct Param {
  const CatalogueCase* c;
  std::string engine;
};

std::vector<Param> params() {
  std::vector<Param> out;
  for (const CatalogueCase& c : kCases)
    for (const std::string& e : engines_for(c.mp)) out.push_back({&c, e});
  return out;
}

// GoogleTest prints the parameter as "scene/engine".
void PrintTo(const Param& p, std::ostream* os) { *os << p.c->scene << "/" << p.engine; }

class Case : public ::testing::TestWithParam<Param> {};

TEST_P(Case, Stable) {
  const Param& p = GetParam();
  MonitoredRun r(load_hard_scene(p.c->scene), p.engine);
  const int frames = r.scene.frames;
  r.run_to(frames);
  RecordProperty("summary", r.summary());
  expect_every_case_criteria(r, frames);
  if (r.error.empty() && r.stats().nonfinite_frame < 0) p.c->check(r);
}

INSTANTIATE_TEST_SUITE_P(HardCatalogue, Case, ::testing::ValuesIn(params()),
                         [](const ::testing::TestParamInfo<Param>& p) {
                           return std::string(p.param.c->scene) + "_" + p.param.engine;
                         });

}  // namespace
}  // namespace lockstep::hard
