// Generators for static SDF volumes (SdfDesc): a bowl and a terrain.
//
// Sign convention (as everywhere in lockstep): d > 0 in free space, d < 0
// inside the solid, |d| approximately the distance (m) to the surface.
//
// Bit reproducibility: the generators use only + - * / and std::sqrt (all
// correctly rounded in IEEE double, so identical on every conforming
// platform; build with -ffp-contract=off as lockstep does), and every
// generated value is rounded to the Q16.16 grid (a multiple of 2^-16) and
// clamped to [-30000, 30000] m, so every engine reads exactly the same
// numbers. The same generators run when a scene file uses "generator"
// (docs/SCENES.md).
#pragma once
#include <string>
#include <vector>

#include "lockstep/scene.hpp"

namespace lockstep {

// The sample grid of an SDF volume: nx * ny * nz samples over the box
// [min, max]; sample (i, j, k) lies at min + (max - min) * (i, j, k) / (n - 1)
// per axis and is stored at index i + nx * (j + ny * k).
struct SdfGrid {
  Vec3d min;
  Vec3d max;
  int nx = 2, ny = 2, nz = 2;
};

// Position of sample (i, j, k) of the grid.
Vec3d sdf_grid_point(const SdfGrid& grid, int i, int j, int k);

// Rounds to the nearest multiple of 2^-16 (ties away from zero) and clamps
// to [-30000, 30000]: how every generated SDF value is stored.
double sdf_quantize(double d);

// A hemispherical bowl: solid below the rim plane y = center.y except for a
// spherical hollow of the given radius around center. Free space is the
// hollow and everything above the rim plane:
//   d(p) = max(p.y - center.y, radius - |p - center|)
// (exact inside the solid and near the spherical surface). With
// center = (0, 7, 0) and radius 6, the bowl's lowest free point is (0, 1, 0).
struct BowlParams {
  Vec3d center{0.0, 7.0, 0.0};
  double radius = 6.0;
};
double bowl_distance(const BowlParams& bowl, Vec3d p);
SdfDesc make_bowl_sdf(const SdfGrid& grid, const BowlParams& bowl, std::string name = "bowl",
                      Material material = {});

// A heightfield terrain y = h(x, z) built from polynomial bumps (no trig):
//   h(x, z) = base_height + sum_b height_b * (1 - r_b^2 / radius_b^2)^2  for r_b < radius_b,
//   r_b^2 = (x - x_b)^2 + (z - z_b)^2,
// a C1-smooth bump of the given height (negative: a dip). Solid below.
//   d(p) = (p.y - h(x, z)) / sqrt(1 + |grad h(x, z)|^2)
// (the first-order distance to the surface: exact on flat parts, close on
// gentle slopes).
struct TerrainBump {
  double x = 0.0;       // centre (m)
  double z = 0.0;       // centre (m)
  double radius = 1.0;  // (m), > 0
  double height = 1.0;  // (m), negative for a dip
};
struct TerrainParams {
  double base_height = 0.0;
  std::vector<TerrainBump> bumps;
};
double terrain_height(const TerrainParams& terrain, double x, double z);
double terrain_distance(const TerrainParams& terrain, Vec3d p);
SdfDesc make_terrain_sdf(const SdfGrid& grid, const TerrainParams& terrain,
                         std::string name = "terrain", Material material = {});

}  // namespace lockstep
