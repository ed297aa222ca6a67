// Two oriented boxes in double, from body snapshots (an oracle independent of
// every engine): the separating-axis value over the 15 axes of the pair.
#pragma once
#include <cmath>

#include "hard/body_geometry.hpp"

namespace lockstep::peer {

// The largest of |d.L| - (r_a + r_b) over the 15 separating axes L (3 face
// normals of each box and the 9 edge-edge cross products), d the centre
// offset. Positive: the boxes are apart, by at least this much (a lower bound
// of their distance). Zero or negative: they overlap, and its negation is the
// penetration depth (the shortest translation that parts them: for convex
// polyhedra it lies along one of these axes).
inline double box_pair_separation(const BodySnapshot& a, const hard::BodyGeometry& ga, const Vec3d& half_a,
                                  const BodySnapshot& b, const hard::BodyGeometry& gb, const Vec3d& half_b) {
  const double ha[3] = {half_a.x, half_a.y, half_a.z}, hb[3] = {half_b.x, half_b.y, half_b.z};
  const double d[3] = {b.p[0] - a.p[0], b.p[1] - a.p[1], b.p[2] - a.p[2]};
  double ua[3][3], ub[3][3];  // the boxes' axes in world coordinates (columns of R)
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      ua[j][i] = ga.R[i][j];
      ub[j][i] = gb.R[i][j];
    }
  auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
  auto along = [&](const double* L) {
    double ra = 0.0, rb = 0.0;
    for (int j = 0; j < 3; ++j) {
      ra += ha[j] * std::fabs(dot(L, ua[j]));
      rb += hb[j] * std::fabs(dot(L, ub[j]));
    }
    return std::fabs(dot(d, L)) - (ra + rb);
  };
  double best = -INFINITY;
  for (int j = 0; j < 3; ++j) {
    best = std::fmax(best, along(ua[j]));
    best = std::fmax(best, along(ub[j]));
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double L[3] = {ua[i][1] * ub[j][2] - ua[i][2] * ub[j][1], ua[i][2] * ub[j][0] - ua[i][0] * ub[j][2],
                     ua[i][0] * ub[j][1] - ua[i][1] * ub[j][0]};
      const double n = std::sqrt(dot(L, L));
      if (n < 1e-6) continue;  // (nearly) parallel edges: the face axes cover this direction
      for (double& x : L) x /= n;
      best = std::fmax(best, along(L));
    }
  return best;
}

}  // namespace lockstep::peer
