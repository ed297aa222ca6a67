// Geometry of a body snapshot, recomputed in double by the tests (an oracle
// independent of the engine's own derived values): the rotation matrix of q,
// the world AABB half-extents (eq 31), the lowest corner (eq 84), the
// alignment (eqs 64-66) and the quaternion norm.
#pragma once
#include <array>
#include <cmath>

#include "lockstep/compare/engine.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::hard {

struct BodyGeometry {
  double R[3][3];        // mat3(q / |q|): the rotation of the snapshot's orientation
  double aabb_half[3];   // eq 31: sum_j |R_ij| h_j (m)
  double lowest_y;       // y of the lowest of the 8 corners (m)
  double alignment;      // eq 66 (with Fix 4): max_i |R[1][i]|, 1 = a face flat
  double q_norm;         // |q| (1)
};

inline BodyGeometry geometry_of(const BodySnapshot& s, const Vec3d& half) {
  BodyGeometry g{};
  g.q_norm = std::sqrt(s.q[0] * s.q[0] + s.q[1] * s.q[1] + s.q[2] * s.q[2] + s.q[3] * s.q[3]);
  const double inv = g.q_norm > 0.0 ? 1.0 / g.q_norm : 0.0;
  const double w = s.q[0] * inv, x = s.q[1] * inv, y = s.q[2] * inv, z = s.q[3] * inv;
  g.R[0][0] = 1 - 2 * (y * y + z * z); g.R[0][1] = 2 * (x * y - w * z);     g.R[0][2] = 2 * (x * z + w * y);
  g.R[1][0] = 2 * (x * y + w * z);     g.R[1][1] = 1 - 2 * (x * x + z * z); g.R[1][2] = 2 * (y * z - w * x);
  g.R[2][0] = 2 * (x * z - w * y);     g.R[2][1] = 2 * (y * z + w * x);     g.R[2][2] = 1 - 2 * (x * x + y * y);
  const double h[3] = {half.x, half.y, half.z};
  for (int i = 0; i < 3; ++i) {
    g.aabb_half[i] = 0.0;
    for (int j = 0; j < 3; ++j) g.aabb_half[i] += std::fabs(g.R[i][j]) * h[j];
  }
  // The lowest corner is p.y minus the y half-extent of the AABB (the AABB of
  // a box is tight in each axis: some corner reaches it).
  g.lowest_y = s.p[1] - g.aabb_half[1];
  g.alignment = std::fmax(std::fabs(g.R[1][0]), std::fmax(std::fabs(g.R[1][1]), std::fabs(g.R[1][2])));
  return g;
}

// Body-frame inertia diagonal of a box (eqs 14-16), kg m^2.
inline std::array<double, 3> box_inertia(const BodyDesc& d) {
  const double m = d.mass, hx = d.half_extents.x, hy = d.half_extents.y, hz = d.half_extents.z;
  return {m / 3.0 * (hy * hy + hz * hz), m / 3.0 * (hx * hx + hz * hz), m / 3.0 * (hx * hx + hy * hy)};
}

// Kinetic + gravitational potential energy of one dynamic body (J), in double
// from the snapshot: 1/2 m v^2 + 1/2 w_b . I w_b - m g . p, w_b = R^T w.
inline double body_energy(const BodySnapshot& s, const BodyGeometry& g, const BodyDesc& d, const Vec3d& gravity) {
  if (d.is_static) return 0.0;
  const double m = d.mass;
  double e = 0.5 * m * (s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]);
  e -= m * (gravity.x * s.p[0] + gravity.y * s.p[1] + gravity.z * s.p[2]);
  const std::array<double, 3> I = box_inertia(d);
  for (int a = 0; a < 3; ++a) {
    const double wb = g.R[0][a] * s.w[0] + g.R[1][a] * s.w[1] + g.R[2][a] * s.w[2];
    e += 0.5 * I[static_cast<std::size_t>(a)] * wb * wb;
  }
  return e;
}

}  // namespace lockstep::hard
