// The built-in scenes. Bit-reproducible on every platform: literal constants,
// integer arithmetic, and (for positions on a lattice and the SDF volumes)
// correctly rounded IEEE operations only; no sin/cos/exp/pow. Quaternion
// literals were computed offline (mpmath, 40 digits) and are written as the
// shortest decimals of the nearest doubles; the engine normalises them.
#include "lockstep/builtin_scenes.hpp"

#include <cstdint>
#include <utility>

#include "lockstep/sdf_generators.hpp"

namespace lockstep {
namespace {

// 64-bit LCG (Knuth's MMIX constants), wrapping mod 2^64 (unsigned: defined).
class Lcg {
 public:
  explicit Lcg(std::uint64_t seed) : x_(seed) {}
  std::uint64_t next() {
    x_ = x_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return x_;
  }
  // A uniform integer in [-m, m] from the high 32 bits (the good ones).
  std::int64_t symmetric(std::int64_t m) {
    const std::uint64_t hi = next() >> 32;
    return static_cast<std::int64_t>(hi % static_cast<std::uint64_t>(2 * m + 1)) - m;
  }
  // A multiple of 2^-16 in [-raw_max, raw_max] / 2^16 (exact in double).
  double q16(std::int64_t raw_max) { return static_cast<double>(symmetric(raw_max)) / 65536.0; }

 private:
  std::uint64_t x_;
};

// Jitter amplitudes (raw Q16.16). bowl and terrain space their cubes so that
// no jitter can make two touch (bounding spheres). pile1000's 1.25 m lattice
// leaves only 0.25 m between faces: with +-0.1 m and +-0.2 quaternion
// components 1106 neighbour pairs would start interpenetrating, so it uses
// +-0.05 m and +-0.05 (rotations up to about 6 degrees per axis), for which
// tests/reference/builtin_scenes_test.cpp checks (separating axes) that no
// two cubes overlap.
constexpr std::int64_t kJitterPos = 6553;        // 0.0999908... m
constexpr std::int64_t kJitterQuat = 13107;      // 0.1999969...
constexpr std::int64_t kPileJitterPos = 3277;    // 0.0500030... m
constexpr std::int64_t kPileJitterQuat = 3277;   // 0.0500030...

// Millimetres to metres: the double nearest the decimal value (one correctly
// rounded division).
double mm(std::int64_t millimetres) { return static_cast<double>(millimetres) / 1000.0; }

BodyDesc cube(double x, double y, double z) {
  BodyDesc b;
  b.half_extents = {0.5, 0.5, 0.5};
  b.mass = 1.0;
  b.position = {x, y, z};
  return b;
}

// A cube with jittered position (+-pos_raw / 2^16 m per axis) and orientation
// (1, a, b, c), a, b, c in +-quat_raw / 2^16, unnormalised (the engine
// normalises). The draws are separate statements: the order in which function
// arguments are evaluated is unspecified, so draws must never share an
// expression.
BodyDesc jittered_cube(Lcg& rng, double x, double y, double z, std::int64_t pos_raw = kJitterPos,
                       std::int64_t quat_raw = kJitterQuat) {
  const double dx = rng.q16(pos_raw);
  const double dy = rng.q16(pos_raw);
  const double dz = rng.q16(pos_raw);
  const double a = rng.q16(quat_raw);
  const double b = rng.q16(quat_raw);
  const double c = rng.q16(quat_raw);
  BodyDesc body = cube(x + dx, y + dy, z + dz);
  body.orientation = {1.0, a, b, c};
  return body;
}

Scene base(const char* name, int frames) {
  Scene s;
  s.name = name;
  s.frames = frames;
  s.effects.sdf = false;  // only bowl and terrain have SDF volumes
  return s;
}

Scene drop() {
  Scene s = base("drop", 300);
  BodyDesc b = cube(0.0, 2.0, 0.0);
  // (1, 0.05, 0, 0.03) / sqrt(1.0034)
  b.orientation = {0.998304322753929, 0.04991521613769645, 0.0, 0.02994912968261787};
  s.bodies.push_back(b);
  return s;
}

Scene bounce() {
  Scene s = base("bounce", 600);
  s.effects.damping = false;
  s.ground.material.restitution = 0.8;
  BodyDesc b = cube(0.0, 1.5, 0.0);  // bottom face 1 m above the ground
  b.material.restitution = 0.8;
  s.bodies.push_back(b);
  return s;
}

Scene slide() {
  Scene s = base("slide", 300);
  s.effects.damping = false;
  s.ground.material = {0.0, 0.5};
  BodyDesc b = cube(0.0, 0.5, 0.0);  // resting on the ground
  b.velocity = {4.0, 0.0, 0.0};
  b.material = {0.0, 0.5};
  s.bodies.push_back(b);
  return s;
}

Scene tip_edge() {
  Scene s = base("tip_edge", 600);
  // Rotated 40 degrees about z: q = (cos 20deg, 0, 0, sin 20deg). The lowest
  // edge is 0.5 (cos 40deg + sin 40deg) below the centre; it starts 0.05 m
  // above the ground: y = 0.05 + 0.5 * (0.766044443118978 + 0.6427876096865394).
  BodyDesc b = cube(0.0, 0.05 + 0.5 * (0.766044443118978 + 0.6427876096865394), 0.0);
  b.orientation = {0.9396926207859084, 0.0, 0.0, 0.3420201433256687};
  s.bodies.push_back(b);
  return s;
}

Scene tip_corner() {
  Scene s = base("tip_corner", 900);
  // The rotation taking the body diagonal (1,1,1)/sqrt(3) to -y, followed by
  // a 4 degree tilt about the world axis (1,0,2)/sqrt(5), so the centre of
  // mass is 0.06 m off the lowest corner and the cube tips. The lowest corner
  // (body (+0.5,+0.5,+0.5)) is then 0.8639158094271043 m below the centre;
  // the centre is placed so that corner starts 0.05 m above the ground.
  BodyDesc b = cube(0.0, 0.9139158094271044, 0.0);
  b.orientation = {0.4692217575047687, 0.6347552865174967, 0.029402854370616637, -0.6132309032306567};
  s.bodies.push_back(b);
  return s;
}

Scene stack5() {
  Scene s = base("stack5", 600);
  s.ground.material = {0.1, 0.5};
  for (int i = 0; i < 5; ++i) {
    BodyDesc b = cube(0.0, 0.5 + i, 0.0);  // touching faces
    b.material = {0.1, 0.5};
    s.bodies.push_back(b);
  }
  return s;
}

Scene pyramid() {
  Scene s = base("pyramid", 600);
  for (int r = 0; r < 4; ++r) {
    const int n = 4 - r;
    for (int k = 0; k < n; ++k) {
      // x = (k - (n-1)/2) * 1.05 m, in millimetres: (2k - n + 1) * 525.
      s.bodies.push_back(cube(mm((2 * k - n + 1) * 525), 0.5 + r, 0.0));
    }
  }
  return s;
}

Scene pile1000() {
  Scene s = base("pile1000", 600);
  Lcg rng(0x6c6f636b73746570ULL);  // "lockstep"
  for (int j = 0; j < 10; ++j) {
    for (int k = 0; k < 10; ++k) {
      for (int i = 0; i < 10; ++i) {
        // Lattice spaced 1.25 m, centred on x = z = 0, lowest layer at y = 2.
        s.bodies.push_back(jittered_cube(rng, (2 * i - 9) * 0.625, 2.0 + 1.25 * j, (2 * k - 9) * 0.625,
                                         kPileJitterPos, kPileJitterQuat));
      }
    }
  }
  return s;
}

Scene bowl() {
  Scene s = base("bowl", 900);
  s.effects.sdf = true;
  // A bowl of radius 6 m centred at (0, 7, 0): rim at y = 7, lowest free point
  // (0, 1, 0). Samples every 0.5 m over [-8, 8] x [0, 10] x [-8, 8] (33x21x33).
  const SdfGrid grid{{-8.0, 0.0, -8.0}, {8.0, 10.0, 8.0}, 33, 21, 33};
  s.sdfs.push_back(make_bowl_sdf(grid, BowlParams{{0.0, 7.0, 0.0}, 6.0}, "bowl"));
  // 20 cubes on a 5x4 grid spaced 1.5 m, heights alternating 9 and 10.5 m in
  // a checkerboard (so no two can touch initially), jittered.
  Lcg rng(0x626f776c00000001ULL);
  for (int iz = 0; iz < 4; ++iz) {
    for (int ix = 0; ix < 5; ++ix) {
      const double y = ((ix + iz) % 2 == 0) ? 9.0 : 10.5;
      s.bodies.push_back(jittered_cube(rng, mm((ix - 2) * 1500), y, mm((2 * iz - 3) * 750)));
    }
  }
  return s;
}

Scene terrain() {
  Scene s = base("terrain", 900);
  s.effects.sdf = true;
  // A safety net below the terrain volume for a body that leaves it.
  s.ground.height = -1.0;
  TerrainParams t;
  t.base_height = 0.0;
  t.bumps = {
      {0.0, 0.0, 5.0, 2.0},      // central hill
      {5.5, 3.0, 3.5, 1.25},     // side hill
      {-5.0, -4.5, 4.0, 1.5},    // side hill
      {-5.0, 5.0, 3.0, -0.75},   // dip
      {4.5, -5.5, 3.0, 0.75},    // mound
  };
  // Samples every 0.5 m over [-10, 10] x [-1, 4] x [-10, 10] (41x11x41).
  const SdfGrid grid{{-10.0, -1.0, -10.0}, {10.0, 4.0, 10.0}, 41, 11, 41};
  SdfDesc sdf = make_terrain_sdf(grid, t, "terrain");
  s.sdfs.push_back(std::move(sdf));
  // 16 cubes on a 4x4 grid spaced 2.5 m, heights alternating 5 and 6 m.
  Lcg rng(0x7465727261696e01ULL);
  for (int iz = 0; iz < 4; ++iz) {
    for (int ix = 0; ix < 4; ++ix) {
      const double y = ((ix + iz) % 2 == 0) ? 5.0 : 6.0;
      s.bodies.push_back(jittered_cube(rng, mm((2 * ix - 3) * 1250), y, mm((2 * iz - 3) * 1250)));
    }
  }
  return s;
}

struct Entry {
  const char* name;
  Scene (*make)();
};
constexpr Entry kScenes[] = {
    {"drop", drop},       {"bounce", bounce},   {"slide", slide},       {"tip_edge", tip_edge},
    {"tip_corner", tip_corner}, {"stack5", stack5}, {"pyramid", pyramid}, {"pile1000", pile1000},
    {"bowl", bowl},       {"terrain", terrain},
};

}  // namespace

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const Entry& e : kScenes) names.emplace_back(e.name);
  return names;
}

std::optional<Scene> builtin_scene(std::string_view name) {
  for (const Entry& e : kScenes) {
    if (name == e.name) return e.make();
  }
  return std::nullopt;
}

}  // namespace lockstep
