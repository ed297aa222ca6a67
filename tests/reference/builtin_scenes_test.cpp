// Tests of the built-in scenes (reference/src/builtin_scenes.cpp) and the SDF
// generators (reference/src/sdf_generators.cpp): names and order, validity
// and exact JSON round trip, the geometry each scene promises (resting,
// touching, clearances, no initial overlaps), and pinned fingerprints so any
// change of a scene's bits, on any platform, is noticed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene_json.hpp"
#include "lockstep/sdf_generators.hpp"

namespace lockstep {
namespace {

const std::vector<std::string> kExpectedNames = {"drop",     "bounce",   "slide",    "tip_edge", "tip_corner",
                                                 "stack5",   "pyramid",  "pile1000", "bowl",     "terrain"};

Scene get(const std::string& name) {
  auto s = builtin_scene(name);
  if (!s) throw std::runtime_error("no built-in scene " + name);
  return *s;
}

// ---------------------------------------------------------------------------
// Geometry helpers (double precision, test only)
// ---------------------------------------------------------------------------

struct Box {
  std::array<double, 3> c;
  std::array<std::array<double, 3>, 3> axis;  // world directions of the body's x, y, z
  std::array<double, 3> h;
};

Box box_of(const BodyDesc& b) {
  const Quatd& q0 = b.orientation;
  const double n = std::sqrt(q0.w * q0.w + q0.x * q0.x + q0.y * q0.y + q0.z * q0.z);
  const double w = q0.w / n, x = q0.x / n, y = q0.y / n, z = q0.z / n;
  Box box;
  box.c = {b.position.x, b.position.y, b.position.z};
  box.h = {b.half_extents.x, b.half_extents.y, b.half_extents.z};
  // Columns of the rotation matrix.
  box.axis[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
  box.axis[1] = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
  box.axis[2] = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
  return box;
}

std::vector<std::array<double, 3>> corners(const Box& b) {
  std::vector<std::array<double, 3>> out;
  for (int sx = -1; sx <= 1; sx += 2) {
    for (int sy = -1; sy <= 1; sy += 2) {
      for (int sz = -1; sz <= 1; sz += 2) {
        std::array<double, 3> p = b.c;
        for (int k = 0; k < 3; ++k) {
          p[k] += sx * b.h[0] * b.axis[0][k] + sy * b.h[1] * b.axis[1][k] + sz * b.h[2] * b.axis[2][k];
        }
        out.push_back(p);
      }
    }
  }
  return out;
}

double lowest_y(const BodyDesc& b) {
  double m = 1e300;
  for (const auto& p : corners(box_of(b))) m = std::min(m, p[1]);
  return m;
}

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Separating-axis test: true when the boxes' interiors intersect by more than
// eps (touching faces do not count).
bool boxes_overlap(const Box& a, const Box& b, double eps = 1e-9) {
  const std::array<double, 3> t = {b.c[0] - a.c[0], b.c[1] - a.c[1], b.c[2] - a.c[2]};
  auto separated_on = [&](const std::array<double, 3>& L) {
    const double len = std::sqrt(dot(L, L));
    if (len < 1e-9) return false;  // parallel edges: a face axis decides
    double ra = 0, rb = 0;
    for (int i = 0; i < 3; ++i) {
      ra += a.h[i] * std::fabs(dot(a.axis[i], L));
      rb += b.h[i] * std::fabs(dot(b.axis[i], L));
    }
    return std::fabs(dot(t, L)) >= (ra + rb) - eps * len;
  };
  for (int i = 0; i < 3; ++i) {
    if (separated_on(a.axis[i]) || separated_on(b.axis[i])) return false;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (separated_on(cross(a.axis[i], b.axis[j]))) return false;
    }
  }
  return true;
}

// Trilinear SDF sample at p, or nullopt-like NaN outside the grid.
double sample_sdf(const SdfDesc& s, const std::array<double, 3>& p) {
  const double lo[3] = {s.min.x, s.min.y, s.min.z};
  const double hi[3] = {s.max.x, s.max.y, s.max.z};
  const int n[3] = {s.nx, s.ny, s.nz};
  int i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    if (p[a] < lo[a] || p[a] > hi[a]) return std::nan("");
    const double u = (p[a] - lo[a]) / (hi[a] - lo[a]) * (n[a] - 1);
    i0[a] = std::min(static_cast<int>(std::floor(u)), n[a] - 2);
    f[a] = u - i0[a];
  }
  auto at = [&](int i, int j, int k) {
    return s.values[static_cast<std::size_t>(i + s.nx * (j + s.ny * k))];
  };
  double v = 0;
  for (int dk = 0; dk < 2; ++dk) {
    for (int dj = 0; dj < 2; ++dj) {
      for (int di = 0; di < 2; ++di) {
        const double w = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
        v += w * at(i0[0] + di, i0[1] + dj, i0[2] + dk);
      }
    }
  }
  return v;
}

// FNV-1a over the exact bits of everything scene-specific (not the default
// constants, so retuning a default does not change a scene's fingerprint).
std::uint64_t fingerprint(const Scene& s) {
  std::uint64_t h = 1469598103934665603ULL;
  auto bytes = [&](std::uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      h ^= (v >> (8 * i)) & 0xff;
      h *= 1099511628211ULL;
    }
  };
  auto d = [&](double v) { bytes(std::bit_cast<std::uint64_t>(v)); };
  auto v3 = [&](const Vec3d& v) { d(v.x); d(v.y); d(v.z); };
  auto mat = [&](const Material& m) { d(m.restitution); d(m.friction); };
  for (char c : s.name) bytes(static_cast<unsigned char>(c));
  bytes(static_cast<std::uint64_t>(s.frames));
  for (bool e : {s.effects.gravity, s.effects.damping, s.effects.ground, s.effects.contacts, s.effects.friction,
                 s.effects.restitution, s.effects.settling, s.effects.sleep, s.effects.sdf}) {
    bytes(e);
  }
  bytes(s.ground.present);
  d(s.ground.height);
  mat(s.ground.material);
  for (const BodyDesc& b : s.bodies) {
    v3(b.half_extents);
    d(b.mass);
    v3(b.position);
    d(b.orientation.w); d(b.orientation.x); d(b.orientation.y); d(b.orientation.z);
    v3(b.velocity);
    v3(b.angular_velocity);
    mat(b.material);
    bytes(b.is_static);
    bytes(b.asleep);
  }
  for (const SdfDesc& sd : s.sdfs) {
    for (char c : sd.name) bytes(static_cast<unsigned char>(c));
    v3(sd.min);
    v3(sd.max);
    bytes(static_cast<std::uint64_t>(sd.nx)); bytes(static_cast<std::uint64_t>(sd.ny)); bytes(static_cast<std::uint64_t>(sd.nz));
    for (double v : sd.values) d(v);
    mat(sd.material);
  }
  return h;
}

// ---------------------------------------------------------------------------
// Names, validity, round trip, reproducibility
// ---------------------------------------------------------------------------

TEST(BuiltinScenes, NamesInOrderUniqueAndDefaultExists) {
  const auto names = builtin_scene_names();
  EXPECT_EQ(names, kExpectedNames);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  EXPECT_NE(std::find(names.begin(), names.end(), kDefaultSceneName), names.end());
  EXPECT_FALSE(builtin_scene("no_such_scene").has_value());
  EXPECT_FALSE(builtin_scene("").has_value());
  EXPECT_FALSE(builtin_scene("Drop").has_value());
}

TEST(BuiltinScenes, EachIsValidAndRoundTripsExactly) {
  for (const std::string& name : builtin_scene_names()) {
    SCOPED_TRACE(name);
    const Scene s = get(name);
    EXPECT_EQ(s.name, name);
    EXPECT_NO_THROW(validate_scene(s));
    const Scene back = parse_scene(scene_to_json(s), name);
    EXPECT_TRUE(scenes_equal(s, back)) << scene_difference(s, back);
    EXPECT_TRUE(scenes_equal(s, get(name))) << "building twice gives different scenes";
    // Only the SDF scenes call for SDF collisions, and they have volumes.
    EXPECT_EQ(s.effects.sdf, !s.sdfs.empty());
    // Built-in scenes use the default constants.
    const Scene def;
    Scene only_constants = def;
    only_constants.constants = s.constants;
    EXPECT_TRUE(scenes_equal(only_constants, def)) << scene_difference(only_constants, def);
  }
}

// The exact bits of every built-in scene. A change here means the scene
// changed (update the value only when that is intended, and say so in the
// change log), or the platform computes it differently (a bug: scenes must
// be bit-reproducible).
TEST(BuiltinScenes, FingerprintsArePinned) {
  const std::pair<const char*, std::uint64_t> pinned[] = {
      {"drop", 0x2e9d0e75b6ea7583ULL},       {"bounce", 0xeabc8824fad5c501ULL},
      {"slide", 0x2bf2f21c51ec8b83ULL},      {"tip_edge", 0x75f0fac5b70789d1ULL},
      {"tip_corner", 0x76ed8a7ecdba3671ULL}, {"stack5", 0xed4fd083768e63b4ULL},
      {"pyramid", 0x659ba44e0f37bfafULL},    {"pile1000", 0xea6afbfec3f889c2ULL},
      {"bowl", 0xa55f0e1ac0bed2f3ULL},       {"terrain", 0x788153a023dbca37ULL},
  };
  for (const auto& [name, want] : pinned) {
    const std::uint64_t got = fingerprint(get(name));
    char buf[40];
    std::snprintf(buf, sizeof buf, "0x%016llxULL", static_cast<unsigned long long>(got));
    EXPECT_EQ(got, want) << name << " fingerprint is " << buf;
  }
}

// ---------------------------------------------------------------------------
// What each scene promises
// ---------------------------------------------------------------------------

TEST(BuiltinScenes, NoInitialOverlapsOrPenetration) {
  for (const std::string& name : builtin_scene_names()) {
    SCOPED_TRACE(name);
    const Scene s = get(name);
    std::vector<Box> boxes;
    for (const BodyDesc& b : s.bodies) boxes.push_back(box_of(b));
    int overlaps = 0;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k) d2 += (boxes[i].c[k] - boxes[j].c[k]) * (boxes[i].c[k] - boxes[j].c[k]);
        if (d2 > 4.0) continue;  // unit cubes: bounding spheres of radius 0.87 apart
        if (boxes_overlap(boxes[i], boxes[j])) {
          ++overlaps;
          ADD_FAILURE() << "bodies " << i << " and " << j << " overlap";
        }
      }
    }
    EXPECT_EQ(overlaps, 0);
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      if (s.ground.present) {
        EXPECT_GE(lowest_y(s.bodies[i]), s.ground.height - 1e-12) << "body " << i;
      }
      for (const SdfDesc& sdf : s.sdfs) {
        for (const auto& p : corners(boxes[i])) {
          const double d = sample_sdf(sdf, p);
          if (!std::isnan(d)) {
            EXPECT_GE(d, 0.0) << "body " << i << " corner inside " << sdf.name;
          }
        }
      }
    }
  }
}

double qnorm(const Quatd& q) { return std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z); }

TEST(BuiltinScenes, Drop) {
  const Scene s = get("drop");
  EXPECT_EQ(s.frames, 300);
  EXPECT_TRUE(s.effects.gravity && s.effects.damping && s.effects.ground && s.effects.contacts &&
              s.effects.friction && s.effects.restitution && s.effects.settling && s.effects.sleep);
  EXPECT_FALSE(s.effects.sdf);
  ASSERT_EQ(s.bodies.size(), 1u);
  const BodyDesc& b = s.bodies[0];
  EXPECT_EQ(b.position.y, 2.0);
  EXPECT_EQ(b.mass, 1.0);
  EXPECT_EQ(b.half_extents.x, 0.5);
  EXPECT_NEAR(qnorm(b.orientation), 1.0, 1e-15);
  EXPECT_NEAR(b.orientation.x / b.orientation.w, 0.05, 1e-15);
  EXPECT_NEAR(b.orientation.z / b.orientation.w, 0.03, 1e-15);
}

TEST(BuiltinScenes, Bounce) {
  const Scene s = get("bounce");
  EXPECT_EQ(s.frames, 600);
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(lowest_y(s.bodies[0]), 1.0);
  EXPECT_EQ(s.bodies[0].material.restitution, 0.8);
  EXPECT_EQ(s.ground.material.restitution, 0.8);
  EXPECT_FALSE(s.effects.damping);
  EXPECT_TRUE(s.effects.friction);
  EXPECT_TRUE(s.effects.restitution);
}

TEST(BuiltinScenes, Slide) {
  const Scene s = get("slide");
  EXPECT_EQ(s.frames, 300);
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(lowest_y(s.bodies[0]), 0.0);
  EXPECT_EQ(s.bodies[0].velocity.x, 4.0);
  EXPECT_EQ(s.bodies[0].material.friction, 0.5);
  EXPECT_EQ(s.ground.material.friction, 0.5);
  EXPECT_EQ(s.bodies[0].material.restitution, 0.0);
  EXPECT_EQ(s.ground.material.restitution, 0.0);
  EXPECT_FALSE(s.effects.damping);
}

TEST(BuiltinScenes, TipEdge) {
  const Scene s = get("tip_edge");
  EXPECT_EQ(s.frames, 600);
  ASSERT_EQ(s.bodies.size(), 1u);
  const BodyDesc& b = s.bodies[0];
  EXPECT_EQ(b.position.y, 0.05 + 0.5 * (0.766044443118978 + 0.6427876096865394));
  EXPECT_NEAR(lowest_y(b), 0.05, 1e-12);
  EXPECT_NEAR(qnorm(b.orientation), 1.0, 1e-15);
  // 40 degrees about z: cos 40 = 2 cos^2 20 - 1.
  EXPECT_NEAR(2 * b.orientation.w * b.orientation.w - 1, 0.766044443118978, 1e-15);
  EXPECT_EQ(b.orientation.x, 0.0);
  EXPECT_EQ(b.orientation.y, 0.0);
}

TEST(BuiltinScenes, TipCornerStandsOnALowestCornerSlightlyOffCentre) {
  const Scene s = get("tip_corner");
  EXPECT_EQ(s.frames, 900);
  ASSERT_EQ(s.bodies.size(), 1u);
  const BodyDesc& b = s.bodies[0];
  EXPECT_NEAR(qnorm(b.orientation), 1.0, 1e-15);
  EXPECT_NEAR(lowest_y(b), 0.05, 1e-12);
  auto cs = corners(box_of(b));
  std::sort(cs.begin(), cs.end(), [](const auto& p, const auto& q) { return p[1] < q[1]; });
  // One clear lowest corner; the next ones far above it (it stands on a corner).
  EXPECT_GT(cs[1][1] - cs[0][1], 0.4);
  // The body diagonal through that corner is a few degrees off vertical, so
  // the centre of mass is not above the corner and the cube tips.
  const double off = std::hypot(cs[0][0] - b.position.x, cs[0][2] - b.position.z);
  EXPECT_GT(off, 0.02);
  EXPECT_LT(off, 0.15);
}

TEST(BuiltinScenes, Stack5Touches) {
  const Scene s = get("stack5");
  EXPECT_EQ(s.frames, 600);
  ASSERT_EQ(s.bodies.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(s.bodies[i].position.y, 0.5 + i);
    EXPECT_EQ(s.bodies[i].position.x, 0.0);
    EXPECT_EQ(s.bodies[i].material.friction, 0.5);
    EXPECT_EQ(s.bodies[i].material.restitution, 0.1);
  }
  EXPECT_EQ(lowest_y(s.bodies[0]), 0.0);
}

TEST(BuiltinScenes, Pyramid) {
  const Scene s = get("pyramid");
  EXPECT_EQ(s.frames, 600);
  ASSERT_EQ(s.bodies.size(), 10u);
  std::size_t i = 0;
  for (int r = 0; r < 4; ++r) {
    const int n = 4 - r;
    double sum = 0;
    for (int k = 0; k < n; ++k, ++i) {
      EXPECT_EQ(s.bodies[i].position.y, 0.5 + r);
      sum += s.bodies[i].position.x;
      if (k > 0) {
        EXPECT_NEAR(s.bodies[i].position.x - s.bodies[i - 1].position.x, 1.05, 1e-12);
      }
    }
    EXPECT_NEAR(sum, 0.0, 1e-12);
  }
}

TEST(BuiltinScenes, Pile1000) {
  const Scene s = get("pile1000");
  EXPECT_EQ(s.frames, 600);
  ASSERT_EQ(s.bodies.size(), 1000u);
  double min_y = 1e300;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const BodyDesc& b = s.bodies[i];
    const int layer = static_cast<int>(i / 100), row = static_cast<int>(i / 10 % 10), col = static_cast<int>(i % 10);
    EXPECT_LE(std::fabs(b.position.x - (col - 4.5) * 1.25), 0.051);
    EXPECT_LE(std::fabs(b.position.y - (2.0 + 1.25 * layer)), 0.051);
    EXPECT_LE(std::fabs(b.position.z - (row - 4.5) * 1.25), 0.051);
    EXPECT_EQ(b.orientation.w, 1.0);
    for (double c : {b.orientation.x, b.orientation.y, b.orientation.z}) EXPECT_LE(std::fabs(c), 0.051);
    for (double c : {b.position.x, b.position.y, b.position.z, b.orientation.x}) {
      EXPECT_EQ(c * 65536.0, std::floor(c * 65536.0)) << "jittered values are Q16.16 multiples";
    }
    min_y = std::min(min_y, b.position.y);
  }
  EXPECT_NEAR(min_y, 2.0, 0.051);
}

TEST(BuiltinScenes, BowlHoldsItsCubes) {
  const Scene s = get("bowl");
  EXPECT_EQ(s.frames, 900);
  EXPECT_TRUE(s.ground.present);
  ASSERT_EQ(s.sdfs.size(), 1u);
  ASSERT_EQ(s.bodies.size(), 20u);
  const SdfDesc& sdf = s.sdfs[0];
  EXPECT_GE(sdf.nx, 24);
  EXPECT_LE(sdf.nx, 40);
  // Free inside the hollow, solid below it and in the rim, free above the rim.
  EXPECT_GT(sample_sdf(sdf, {0, 2, 0}), 0.5);
  EXPECT_LT(sample_sdf(sdf, {0, 0.5, 0}), -0.25);
  EXPECT_LT(sample_sdf(sdf, {7.5, 5, 0}), -0.25);
  EXPECT_GT(sample_sdf(sdf, {7.5, 8, 0}), 0.5);
  for (const BodyDesc& b : s.bodies) {
    // Above the rim (y = 7) and well inside the rim circle (radius 6).
    EXPECT_GT(lowest_y(b), 7.5);
    EXPECT_LT(std::hypot(b.position.x, b.position.z), 4.5);
  }
}

TEST(BuiltinScenes, TerrainHasCubesAboveIt) {
  const Scene s = get("terrain");
  EXPECT_EQ(s.frames, 900);
  ASSERT_EQ(s.sdfs.size(), 1u);
  ASSERT_EQ(s.bodies.size(), 16u);
  const SdfDesc& sdf = s.sdfs[0];
  double hi = -1e300;
  for (int i = 0; i < sdf.nx; ++i) {
    for (int k = 0; k < sdf.nz; ++k) {
      // The surface height at a column: the highest sample still in the solid.
      for (int j = 0; j < sdf.ny; ++j) {
        if (sdf.values[static_cast<std::size_t>(i + sdf.nx * (j + sdf.ny * k))] <= 0) {
          hi = std::max(hi, sdf.min.y + (sdf.max.y - sdf.min.y) * j / (sdf.ny - 1));
        }
      }
    }
  }
  EXPECT_GT(hi, 1.0);  // there are hills
  for (const BodyDesc& b : s.bodies) EXPECT_GT(lowest_y(b), hi + 1.0);
  EXPECT_TRUE(s.ground.present);
  EXPECT_LE(s.ground.height, sdf.min.y);
}

// ---------------------------------------------------------------------------
// SDF generators
// ---------------------------------------------------------------------------

TEST(SdfGenerators, QuantizeRoundsToQ16AndClamps) {
  EXPECT_EQ(sdf_quantize(0.0), 0.0);
  EXPECT_EQ(sdf_quantize(1.0 / 65536.0), 1.0 / 65536.0);
  EXPECT_EQ(sdf_quantize(0.4 / 65536.0), 0.0);
  EXPECT_EQ(sdf_quantize(0.5 / 65536.0), 1.0 / 65536.0);    // ties away from zero
  EXPECT_EQ(sdf_quantize(-0.5 / 65536.0), -1.0 / 65536.0);
  EXPECT_EQ(sdf_quantize(1e9), 30000.0);
  EXPECT_EQ(sdf_quantize(-1e9), -30000.0);
  EXPECT_EQ(sdf_quantize(0.1) * 65536.0, 6554.0);
}

TEST(SdfGenerators, BowlValuesAndLayout) {
  const SdfGrid grid{{-2, 0, -3}, {2, 4, 3}, 5, 9, 7};
  const BowlParams bowl{{0.0, 3.0, 0.0}, 2.5};
  const SdfDesc s = make_bowl_sdf(grid, bowl, "b", Material{0.3, 0.9});
  EXPECT_EQ(s.name, "b");
  EXPECT_EQ(s.material.restitution, 0.3);
  EXPECT_EQ(s.nx, 5);
  EXPECT_EQ(s.ny, 9);
  EXPECT_EQ(s.nz, 7);
  ASSERT_EQ(s.values.size(), 5u * 9u * 7u);
  for (int k = 0; k < 7; ++k) {
    for (int j = 0; j < 9; ++j) {
      for (int i = 0; i < 5; ++i) {
        const Vec3d p = sdf_grid_point(grid, i, j, k);
        EXPECT_EQ(s.values[static_cast<std::size_t>(i + 5 * (j + 9 * k))], sdf_quantize(bowl_distance(bowl, p)));
      }
    }
  }
  const Vec3d last = sdf_grid_point(grid, 4, 8, 6);
  EXPECT_EQ(last.x, 2.0);
  EXPECT_EQ(last.y, 4.0);
  EXPECT_EQ(last.z, 3.0);
  EXPECT_EQ(bowl_distance(bowl, {0, 3, 0}), 2.5);   // centre: deep in the hollow
  EXPECT_EQ(bowl_distance(bowl, {0, 0.5, 0}), 0.0); // bottom of the bowl
  EXPECT_EQ(bowl_distance(bowl, {0, 0, 0}), -0.5);  // in the solid
  EXPECT_EQ(bowl_distance(bowl, {5, 4, 0}), 1.0);   // above the rim plane
}

TEST(SdfGenerators, TerrainFlatAndBumps) {
  TerrainParams flat;
  flat.base_height = 0.5;
  EXPECT_EQ(terrain_distance(flat, {3, 2, -1}), 1.5);
  EXPECT_EQ(terrain_distance(flat, {3, -1, -1}), -1.5);
  TerrainParams t;
  t.bumps = {{1.0, 2.0, 2.0, 1.0}};
  EXPECT_EQ(terrain_height(t, 1.0, 2.0), 1.0);   // the bump's top
  EXPECT_EQ(terrain_height(t, 3.0, 2.0), 0.0);   // its edge
  EXPECT_EQ(terrain_height(t, 2.0, 2.0), 0.5625);  // (1 - 1/4)^2
  EXPECT_EQ(terrain_distance(t, {1.0, 3.0, 2.0}), 2.0);  // flat at the top
  // On the slope the distance is shortened by the slope factor.
  EXPECT_LT(terrain_distance(t, {2.0, 1.5625, 2.0}), 1.0);
  EXPECT_GT(terrain_distance(t, {2.0, 1.5625, 2.0}), 0.7);
  const SdfGrid grid{{-1, -1, 0}, {3, 2, 4}, 9, 7, 9};
  const SdfDesc s = make_terrain_sdf(grid, t);
  EXPECT_EQ(s.name, "terrain");
  for (double v : s.values) EXPECT_EQ(v, sdf_quantize(v));
}

TEST(SdfGenerators, RejectBadArguments) {
  EXPECT_THROW(make_bowl_sdf(SdfGrid{{0, 0, 0}, {1, 1, 1}, 1, 2, 2}, BowlParams{}), std::invalid_argument);
  EXPECT_THROW(make_bowl_sdf(SdfGrid{{0, 0, 0}, {1, 0, 1}, 2, 2, 2}, BowlParams{}), std::invalid_argument);
  EXPECT_THROW(make_bowl_sdf(SdfGrid{{0, 0, 0}, {1, 1, 1}, 2, 2, 2}, BowlParams{{0, 0, 0}, 0.0}),
               std::invalid_argument);
  TerrainParams t;
  t.bumps = {{0, 0, -1, 1}};
  EXPECT_THROW(make_terrain_sdf(SdfGrid{{0, 0, 0}, {1, 1, 1}, 2, 2, 2}, t), std::invalid_argument);
}

}  // namespace
}  // namespace lockstep
