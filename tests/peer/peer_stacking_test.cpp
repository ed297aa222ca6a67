// As good as Bullet (issue 12): the same seeded harder columns (columns.hpp:
// 2-10 cubes of 0.25-1 m, tilted up to 2 degrees, shifted up to 10 %, dropped
// up to 0.3 m) run through Bullet (btDiscreteDynamicsWorld, 10 iterations,
// bullet_run.hpp) and through each of lockstep's engines. Each engine must
// stand at least as many columns as Bullet, never let a cube sleep over a
// gap, and never gain energy: a column starts at rest with no two cubes
// touching, so with restitution 0.2 and friction every contact can only take
// energy away, and the total kinetic + rotational + gravitational energy must
// never rise above its value at frame 0 (kEnergyTolerance: the rounding of the
// energy sum itself, not a physical allowance). It may rise above an earlier
// frame's: that is restitution's bounce, the energy a contact took in while
// approaching (here, stored in the penetration of an impact) given back, so a
// frame-to-frame bound would be wrong; the test prints the largest such rise.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "box_pair.hpp"
#include "bullet_run.hpp"
#include "columns.hpp"

namespace lockstep::peer {
namespace {

constexpr int kColumns = 100;
constexpr std::uint64_t kSeed = kPeerColumnSeed;
// J: the energy is summed in double over at most 10 cubes of at most 2 kg
// with |m g y| < 700 J; 1e-6 J is far above that sum's rounding (1e-13 J) and
// far below any physical gain (a 1 kg cube raised 0.1 mm is 1e-3 J).
constexpr double kEnergyTolerance = 1e-6;

const std::vector<Column>& columns() {
  static const std::vector<Column> c = harder_columns(kColumns, kSeed);
  return c;
}

struct Tally {
  std::string engine;
  int count = 0;
  int standing = 0;
  std::vector<ColumnResult> results;
};

Tally run_engine(const std::string& engine, int count) {
  Tally t;
  t.engine = engine;
  t.count = count;
  for (int c = 0; c < count; ++c) {
    const Column& col = columns()[static_cast<std::size_t>(c)];
    std::unique_ptr<EngineRun> e;
    if (engine == "bullet") e = std::make_unique<BulletRun>(col.scene);
    else e = make_engine(engine, col.scene);  // throws, naming the limitation, where the engine cannot run the scene
    t.results.push_back(run_column(*e, col));
    t.standing += t.results.back().stands;
  }
  return t;
}

const Tally& bullet(int count) {
  static std::map<int, Tally> cache;
  auto it = cache.find(count);
  if (it == cache.end()) it = cache.emplace(count, run_engine("bullet", count)).first;
  return it->second;
}

BodySnapshot snapshot_of_desc(const BodyDesc& b) {
  const Quatd& q = b.orientation;
  return {{b.position.x, b.position.y, b.position.z}, {q.w, q.x, q.y, q.z}, {}, {}, false, -1};
}

std::string describe(const Column& c) {
  std::ostringstream s;
  s << "column " << c.index << " (" << c.scene.bodies.size() << " cubes of " << c.size << " m)";
  return s.str();
}

void expect_as_good_as_bullet(const std::string& engine, int count) {
  const Tally& b = bullet(count);
  Tally t;
  try {
    t = run_engine(engine, count);
  } catch (const std::exception& e) {
    FAIL() << engine << " cannot run the columns: " << e.what();
  }
  int sleepers_over_gaps = 0, gained = 0, latest_sleep = 0;
  double worst_gain = -INFINITY, rebound = 0;
  std::ostringstream fallen, gaps, gains;
  for (int c = 0; c < count; ++c) {
    const Column& col = columns()[static_cast<std::size_t>(c)];
    const ColumnResult& r = t.results[static_cast<std::size_t>(c)];
    const ColumnResult& rb = b.results[static_cast<std::size_t>(c)];
    if (!r.stands && rb.stands) fallen << "\n  " << describe(col) << " stands on Bullet, not on " << engine << ": " << r.why;
    if (r.gap_frame >= 0) {
      ++sleepers_over_gaps;
      gaps << "\n  " << describe(col) << ": a sleeper " << r.worst_sleeping_gap << " m over its support, first at frame " << r.gap_frame;
    }
    if (r.energy_gain > kEnergyTolerance) {
      ++gained;
      gains << "\n  " << describe(col) << ": E rose " << r.energy_gain << " J above its start " << r.energy_start << " J at frame "
            << r.gain_frame;
    }
    worst_gain = std::max(worst_gain, r.energy_gain);
    rebound = std::max(rebound, r.rebound);
    if (r.stands) latest_sleep = std::max(latest_sleep, r.all_asleep_frame);
  }
  double bullet_gain = -INFINITY, bullet_rebound = 0;
  for (const ColumnResult& r : b.results) {
    bullet_gain = std::max(bullet_gain, r.energy_gain);
    bullet_rebound = std::max(bullet_rebound, r.rebound);
  }
  std::printf("[peer] %d harder columns: Bullet stands %d (largest energy change from frame 0 %+.3g J, largest bounce %.3g J); "
              "%s stands %d, %d with a sleeper over a gap, largest energy change from frame 0 %+.3g J, largest bounce %.3g J, "
              "standing columns asleep by frame %d\n",
              count, b.standing, bullet_gain, bullet_rebound, engine.c_str(), t.standing, sleepers_over_gaps, worst_gain, rebound,
              latest_sleep);
  EXPECT_GE(t.standing, b.standing) << engine << " stands fewer columns than " << bullet_version() << fallen.str();
  EXPECT_EQ(sleepers_over_gaps, 0) << gaps.str();
  EXPECT_EQ(gained, 0) << "energy gained (tolerance " << kEnergyTolerance << " J):" << gains.str();
}

TEST(PeerColumns, FixedStandsAsManyAsBullet) { expect_as_good_as_bullet("fixed", kColumns); }
TEST(PeerColumns, FloatStandsAsManyAsBullet) { expect_as_good_as_bullet("float", kColumns); }
TEST(PeerColumns, DoubleStandsAsManyAsBullet) { expect_as_good_as_bullet("double", kColumns); }
// mp (113-bit) takes about 25 s of CPU for the 100 columns: all of them.
TEST(PeerColumns, MpStandsAsManyAsBullet) { expect_as_good_as_bullet("mp", kColumns); }
// The GPU engine: its host build where there is no CUDA device, as in CI (the
// same pipeline and per-element functions as its CUDA kernels). On this main
// it refuses oriented-box scenes (engine_limitation), so this test fails,
// naming that limitation, until the GPU engine's oriented-box port lands.
TEST(PeerColumnsGpu, GpuStandsAsManyAsBullet) { expect_as_good_as_bullet("gpu", kColumns); }

// The family is what it claims: seeded (the same columns twice), 2-10 cubes
// of 0.25-1 m, no two cubes (or a cube and the ground) touching at the start.
TEST(PeerColumns, TheFamilyIsSeededAndStartsApart) {
  const std::vector<Column> again = harder_columns(kColumns, kSeed);
  int tallest = 0, shortest = 100;
  for (int c = 0; c < kColumns; ++c) {
    const Column& col = columns()[static_cast<std::size_t>(c)];
    ASSERT_EQ(col.scene.bodies.size(), again[static_cast<std::size_t>(c)].scene.bodies.size());
    for (std::size_t i = 0; i < col.scene.bodies.size(); ++i)
      EXPECT_EQ(col.scene.bodies[i].position.y, again[static_cast<std::size_t>(c)].scene.bodies[i].position.y);
    const int n = static_cast<int>(col.scene.bodies.size());
    tallest = std::max(tallest, n);
    shortest = std::min(shortest, n);
    EXPECT_GE(col.size, 0.25);
    EXPECT_LE(col.size, 1.0);
    for (int i = 0; i < n; ++i) {
      const BodyDesc& a = col.scene.bodies[static_cast<std::size_t>(i)];
      const BodySnapshot sa = snapshot_of_desc(a);
      const hard::BodyGeometry ga = hard::geometry_of(sa, a.half_extents);
      EXPECT_GT(ga.lowest_y, 0.0) << describe(col) << ", cube " << i;
      for (int j = 0; j < i; ++j) {
        const BodyDesc& b = col.scene.bodies[static_cast<std::size_t>(j)];
        const BodySnapshot sb = snapshot_of_desc(b);
        EXPECT_GT(box_pair_separation(sa, ga, a.half_extents, sb, hard::geometry_of(sb, b.half_extents), b.half_extents), 0.0)
            << describe(col) << ", cubes " << j << " and " << i;
      }
    }
  }
  EXPECT_EQ(shortest, 2);
  EXPECT_EQ(tallest, 10);
}

}  // namespace
}  // namespace lockstep::peer
