// Piles must stand, sleep and not sink (issue 12, oriented-box contacts):
//   pile1000            the built-in scene: 100 columns of 10 cubes jittered by
//                       up to 5 cm and about 6 degrees per axis (Jolt stands all 100);
//   boxfall-1000 tilted 100 columns of 10 unit cubes, 0.2 m apart, each cube
//                       tilted by up to 1 degree about a random axis and shifted by
//                       up to 2 cm (the peers' scene, shared ANCHORS.md);
//   boxfall-8000        400 aligned columns of 20 unit cubes (the scene that
//                       exploded in the fixed engine under the AABB pair model).
// On every engine that runs the scene: every column stands (each cube within
// 2 cm of its ideal stacked height and within half its size of the column's
// axis, the rule of StackingProp), every body is asleep by the last frame,
// and at the last frame no cube is more than 1 cm into the ground or into
// another cube (separating-axis depth, computed here in double independently
// of the engine's narrow phase). The deepest penetration while the columns
// land (every kDepthEvery frames) is printed beside it. mp runs under the
// label long.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/engine.hpp"

namespace lockstep {
namespace {

constexpr double kHeightTol = 0.02;  // (m) a standing cube's distance from its ideal stacked height
constexpr double kRestDepthTol = 0.01;  // (m) the deepest a resting cube may be in the ground or another cube
constexpr int kDepthEvery = 10;      // frames between depth measurements

struct Pile {
  Scene scene;
  std::vector<int> column;  // body -> column id
};

// The ground plane is y = 0 in every scene here.
Pile pile1000() {
  Pile p{*builtin_scene("pile1000"), {}};
  for (std::size_t i = 0; i < p.scene.bodies.size(); ++i) p.column.push_back(static_cast<int>(i % 100));
  return p;
}

// side x side columns of `high` unit cubes (1 kg, friction 0.5, restitution
// 0.2 as the ground), 0.2 m apart in x, y and z; tilted by up to `tilt`
// radians about a uniformly random axis and shifted by up to `shift` m in x
// and z (seeded, std::mt19937_64 with explicit arithmetic, so the same scene
// on every platform that has IEEE double).
Pile boxfall(int side, int high, double tilt, double shift, std::uint64_t seed) {
  Pile p;
  p.scene.name = "boxfall";
  p.scene.frames = 600;
    std::mt19937_64 rng(seed);
  auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
  };
  for (int layer = 0; layer < high; ++layer) {
    for (int k = 0; k < side * side; ++k) {
      BodyDesc b;
      const double dx = shift > 0 ? uniform(-shift, shift) : 0.0;
      const double dz = shift > 0 ? uniform(-shift, shift) : 0.0;
      b.position = {1.2 * (k % side) + dx, 0.6 + 1.2 * layer, 1.2 * (k / side) + dz};
      if (tilt > 0) {
        const double angle = uniform(0.0, tilt);
        const double ax = uniform(-1, 1), ay = uniform(-1, 1), az = uniform(-1, 1);
        const double l = std::sqrt(ax * ax + ay * ay + az * az);
        const double s = l > 0 ? std::sin(angle / 2) / l : 0.0;
        b.orientation = {std::cos(angle / 2), s * ax, s * ay, s * az};
      }
      p.scene.bodies.push_back(b);
      p.column.push_back(k);
    }
  }
  return p;
}

// A body's oriented box in double: centre, axes (columns of R) and half extents.
struct Obb {
  std::array<double, 3> c;
  std::array<std::array<double, 3>, 3> axis;
  std::array<double, 3> h;
};

Obb obb_of(const BodySnapshot& b, const BodyDesc& desc) {
  double w = b.q[0], x = b.q[1], y = b.q[2], z = b.q[3];
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  Obb o;
  o.c = {b.p[0], b.p[1], b.p[2]};
  o.axis[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
  o.axis[1] = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
  o.axis[2] = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
  o.h = {desc.half_extents.x, desc.half_extents.y, desc.half_extents.z};
  return o;
}

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Depth of the box below the plane y = 0 (m; <= 0 when above it).
double ground_depth(const Obb& o) {
  double reach = 0;
  for (int i = 0; i < 3; ++i) reach += std::fabs(o.axis[i][1]) * o.h[i];
  return reach - o.c[1];
}

// Separating-axis depth of two boxes (m): the least overlap over the 15 axes,
// <= 0 when some axis separates them.
double pair_depth(const Obb& a, const Obb& b) {
  const std::array<double, 3> d{b.c[0] - a.c[0], b.c[1] - a.c[1], b.c[2] - a.c[2]};
  double least = 1e300;
  auto test = [&](std::array<double, 3> l) {
    const double len = std::sqrt(dot(l, l));
    if (len < 1e-9) return;
    for (double& v : l) v /= len;
    double ra = 0, rb = 0;
    for (int i = 0; i < 3; ++i) {
      ra += std::fabs(dot(a.axis[i], l)) * a.h[i];
      rb += std::fabs(dot(b.axis[i], l)) * b.h[i];
    }
    least = std::min(least, ra + rb - std::fabs(dot(d, l)));
  };
  for (int i = 0; i < 3; ++i) test(a.axis[i]);
  for (int i = 0; i < 3; ++i) test(b.axis[i]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const auto& u = a.axis[i];
      const auto& v = b.axis[j];
      test({u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]});
    }
  return least;
}

struct Depths {
  double ground = 0, pair = 0;
  int ground_body = -1, pair_a = -1, pair_b = -1;
};

// The deepest ground and pair penetration now; pairs whose centres are closer
// than the sum of their bounding radii (cells of 2 m in x and z).
Depths depths(const EngineRun& e, const Scene& s) {
  const int n = e.body_count();
  std::vector<Obb> boxes;
  std::map<std::pair<long, long>, std::vector<int>> cells;
  for (int i = 0; i < n; ++i) {
    boxes.push_back(obb_of(e.body(i), s.bodies[static_cast<std::size_t>(i)]));
    cells[{std::lround(std::floor(boxes.back().c[0] / 2)), std::lround(std::floor(boxes.back().c[2] / 2))}].push_back(i);
  }
  Depths out;
  for (int i = 0; i < n; ++i) {
    const double g = ground_depth(boxes[static_cast<std::size_t>(i)]);
    if (g > out.ground) out = {g, out.pair, i, out.pair_a, out.pair_b};
  }
  for (const auto& [cell, members] : cells)
    for (long dx = -1; dx <= 1; ++dx)
      for (long dz = -1; dz <= 1; ++dz) {
        const auto other = cells.find({cell.first + dx, cell.second + dz});
        if (other == cells.end()) continue;
        for (int a : members)
          for (int b : other->second) {
            if (b <= a) continue;
            const Obb& A = boxes[static_cast<std::size_t>(a)];
            const Obb& B = boxes[static_cast<std::size_t>(b)];
            const double r = std::sqrt(dot(A.h, A.h)) + std::sqrt(dot(B.h, B.h));
            const std::array<double, 3> dc{B.c[0] - A.c[0], B.c[1] - A.c[1], B.c[2] - A.c[2]};
            if (dot(dc, dc) >= r * r) continue;
            const double p = pair_depth(A, B);
            if (p > out.pair) out = {out.ground, p, out.ground_body, a, b};
          }
      }
  return out;
}

void check_pile(const std::string& engine, const Pile& pile) {
  std::unique_ptr<EngineRun> e = make_engine(engine, pile.scene);
  Depths worst;
  int worst_ground_frame = 0, worst_pair_frame = 0;
  int all_asleep = -1;
  for (int f = 0; f < pile.scene.frames; ++f) {
    e->step();
    if (e->frame() % kDepthEvery == 0 || f + 1 == pile.scene.frames) {
      const Depths now = depths(*e, pile.scene);
      if (now.ground > worst.ground) worst = {now.ground, worst.pair, now.ground_body, worst.pair_a, worst.pair_b}, worst_ground_frame = e->frame();
      if (now.pair > worst.pair) worst = {worst.ground, now.pair, worst.ground_body, now.pair_a, now.pair_b}, worst_pair_frame = e->frame();
    }
    if (all_asleep < 0) {
      bool asleep = true;
      for (int i = 0; i < e->body_count() && asleep; ++i) asleep = e->body(i).asleep;
      if (asleep) all_asleep = e->frame();
    }
  }
  const Depths rest = depths(*e, pile.scene);
  // Columns: cubes sorted by height; the k-th (from 0) belongs at 0.5 + k.
  std::map<int, std::vector<BodySnapshot>> columns;
  for (int i = 0; i < e->body_count(); ++i) columns[pile.column[static_cast<std::size_t>(i)]].push_back(e->body(i));
  int standing = 0, awake = 0;
  std::ostringstream fallen;
  for (auto& [id, cubes] : columns) {
    std::sort(cubes.begin(), cubes.end(), [](const BodySnapshot& a, const BodySnapshot& b) { return a.p[1] < b.p[1]; });
    double cx = 0, cz = 0;
    for (const BodySnapshot& b : cubes) cx += b.p[0], cz += b.p[2];
    cx /= static_cast<double>(cubes.size());
    cz /= static_cast<double>(cubes.size());
    bool stands = true;
    for (std::size_t k = 0; k < cubes.size(); ++k) {
      const BodySnapshot& b = cubes[k];
      awake += b.asleep ? 0 : 1;
      const bool ok = std::fabs(b.p[1] - (0.5 + static_cast<double>(k))) < kHeightTol &&
                      std::hypot(b.p[0] - cx, b.p[2] - cz) < 0.5;
      if (!ok && stands && fallen.tellp() < 600)
        fallen << " column " << id << " cube " << k << " at (" << b.p[0] << ", " << b.p[1] << ", " << b.p[2] << ");";
      stands = stands && ok;
    }
    standing += stands ? 1 : 0;
  }
  std::ostringstream summary;
  summary << engine << " " << pile.scene.name << ": " << standing << " of " << columns.size() << " columns stand, "
          << awake << " of " << e->body_count() << " awake at frame " << e->frame() << ", all asleep at "
          << all_asleep << ", deepest in the ground " << worst.ground * 1000 << " mm (body " << worst.ground_body
          << ", frame " << worst_ground_frame << "), deepest pair " << worst.pair * 1000 << " mm (bodies "
          << worst.pair_a << ", " << worst.pair_b << ", frame " << worst_pair_frame << "); at rest: ground "
          << rest.ground * 1000 << " mm, pair " << rest.pair * 1000 << " mm";
  std::printf("%s\n", summary.str().c_str());
  EXPECT_EQ(standing, static_cast<int>(columns.size())) << summary.str() << "; first fallen:" << fallen.str();
  EXPECT_EQ(awake, 0) << summary.str();
  EXPECT_LE(rest.ground, kRestDepthTol) << summary.str();
  EXPECT_LE(rest.pair, kRestDepthTol) << summary.str();
}

class PileTest : public ::testing::TestWithParam<std::string> {
 protected:
  void run(const Pile& p) {
    const std::vector<std::string> names = engine_names_for(p.scene);
    if (std::find(names.begin(), names.end(), GetParam()) == names.end())
      GTEST_SKIP() << GetParam() << " does not run this scene: " << engine_limitation(GetParam(), p.scene);
    check_pile(GetParam(), p);
  }
};

TEST_P(PileTest, Pile1000Stands) { run(pile1000()); }
TEST_P(PileTest, TiltedBoxfall1000Stands) { run(boxfall(10, 10, M_PI / 180, 0.02, 0x626f7866616c6cULL)); }
TEST_P(PileTest, AlignedBoxfall8000Stands) { run(boxfall(20, 20, 0.0, 0.0, 0)); }

INSTANTIATE_TEST_SUITE_P(Engines, PileTest, ::testing::ValuesIn(engine_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace lockstep
