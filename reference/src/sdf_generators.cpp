// SDF volume generators. Only + - * / and std::sqrt (correctly rounded), so
// the output is the same bit for bit on every IEEE platform.
#include "lockstep/sdf_generators.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

namespace lockstep {
namespace {

constexpr double kSdfLimit = 30000.0;

void check_grid(const SdfGrid& g) {
  const int n[3] = {g.nx, g.ny, g.nz};
  for (int v : n) {
    if (v < 2 || v > 256) throw std::invalid_argument("SdfGrid: resolution must be in [2, 256] per axis");
  }
  if (!(g.max.x > g.min.x) || !(g.max.y > g.min.y) || !(g.max.z > g.min.z)) {
    throw std::invalid_argument("SdfGrid: max must be greater than min on every axis");
  }
}

double axis_point(double lo, double hi, int i, int n) {
  if (i == n - 1) return hi;
  return lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n - 1);
}

template <class F>
SdfDesc generate(const SdfGrid& g, std::string name, Material material, F&& distance) {
  check_grid(g);
  SdfDesc s;
  s.name = std::move(name);
  s.min = g.min;
  s.max = g.max;
  s.nx = g.nx;
  s.ny = g.ny;
  s.nz = g.nz;
  s.material = material;
  s.values.resize(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny) *
                  static_cast<std::size_t>(g.nz));
  std::size_t idx = 0;
  for (int k = 0; k < g.nz; ++k) {
    for (int j = 0; j < g.ny; ++j) {
      for (int i = 0; i < g.nx; ++i) {
        s.values[idx++] = sdf_quantize(distance(sdf_grid_point(g, i, j, k)));
      }
    }
  }
  return s;
}

}  // namespace

Vec3d sdf_grid_point(const SdfGrid& g, int i, int j, int k) {
  return {axis_point(g.min.x, g.max.x, i, g.nx), axis_point(g.min.y, g.max.y, j, g.ny),
          axis_point(g.min.z, g.max.z, k, g.nz)};
}

double sdf_quantize(double d) {
  if (std::isnan(d)) return 0.0;
  if (d >= kSdfLimit) return kSdfLimit;
  if (d <= -kSdfLimit) return -kSdfLimit;
  // |d * 2^16| < 2^31: exact product, round half away from zero.
  const double scaled = d * 65536.0;
  const double r = scaled >= 0.0 ? std::floor(scaled + 0.5) : -std::floor(-scaled + 0.5);
  return static_cast<double>(static_cast<std::int64_t>(r)) / 65536.0;
}

double bowl_distance(const BowlParams& b, Vec3d p) {
  const double dx = p.x - b.center.x, dy = p.y - b.center.y, dz = p.z - b.center.z;
  const double to_sphere = b.radius - std::sqrt(dx * dx + dy * dy + dz * dz);
  const double above_rim = dy;
  return above_rim > to_sphere ? above_rim : to_sphere;
}

SdfDesc make_bowl_sdf(const SdfGrid& grid, const BowlParams& bowl, std::string name, Material material) {
  if (!(bowl.radius > 0.0)) throw std::invalid_argument("make_bowl_sdf: radius must be > 0");
  return generate(grid, std::move(name), material, [&](Vec3d p) { return bowl_distance(bowl, p); });
}

namespace {
// h(x, z) and its gradient.
void terrain_eval(const TerrainParams& t, double x, double z, double& h, double& gx, double& gz) {
  h = t.base_height;
  gx = 0.0;
  gz = 0.0;
  for (const TerrainBump& b : t.bumps) {
    const double dx = x - b.x, dz = z - b.z;
    const double r2 = dx * dx + dz * dz;
    const double R2 = b.radius * b.radius;
    if (!(r2 < R2)) continue;
    const double u = 1.0 - r2 / R2;
    h += b.height * u * u;
    // d/dx [H u^2] = H * 2u * (-2 dx / R^2)
    const double s = -4.0 * b.height * u / R2;
    gx += s * dx;
    gz += s * dz;
  }
}
}  // namespace

double terrain_height(const TerrainParams& t, double x, double z) {
  double h, gx, gz;
  terrain_eval(t, x, z, h, gx, gz);
  return h;
}

double terrain_distance(const TerrainParams& t, Vec3d p) {
  double h, gx, gz;
  terrain_eval(t, p.x, p.z, h, gx, gz);
  return (p.y - h) / std::sqrt(1.0 + gx * gx + gz * gz);
}

SdfDesc make_terrain_sdf(const SdfGrid& grid, const TerrainParams& terrain, std::string name,
                         Material material) {
  for (const TerrainBump& b : terrain.bumps) {
    if (!(b.radius > 0.0)) throw std::invalid_argument("make_terrain_sdf: bump radius must be > 0");
  }
  return generate(grid, std::move(name), material, [&](Vec3d p) { return terrain_distance(terrain, p); });
}

}  // namespace lockstep
