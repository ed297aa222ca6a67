#include "lockstep/compare/resting.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "lockstep/math/num.hpp"
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/sdf.hpp"

namespace lockstep::compare {
namespace {

struct Unit {
  double w, x, y, z;
};

Unit normalised(const double q[4]) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(n > 0)) return {1, 0, 0, 0};
  return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}

// Rotation matrix of a unit quaternion (the R of eq 64), row-major.
void rotation(const double q[4], double R[3][3]) {
  const Unit u = normalised(q);
  const double w = u.w, x = u.x, y = u.y, z = u.z;
  R[0][0] = 1 - 2 * (y * y + z * z); R[0][1] = 2 * (x * y - w * z);     R[0][2] = 2 * (x * z + w * y);
  R[1][0] = 2 * (x * y + w * z);     R[1][1] = 1 - 2 * (x * x + z * z); R[1][2] = 2 * (y * z - w * x);
  R[2][0] = 2 * (x * z - w * y);     R[2][1] = 2 * (y * z + w * x);     R[2][2] = 1 - 2 * (x * x + y * y);
}

struct Box {
  double lo[3], hi[3];  // AABB (eq 31) (m)
  double corners[8][3];  // in the corner order of eq 84
  double p[3], R[3][3], h[3];
};

// Distance from point c to the (oriented) box; 0 inside.
double distance_to(const Box& b, const double c[3]) {
  double d2 = 0;
  for (int i = 0; i < 3; ++i) {
    double local = 0;  // R^T (c - p)
    for (int a = 0; a < 3; ++a) local += b.R[a][i] * (c[a] - b.p[a]);
    const double out = std::fabs(local) - b.h[i];
    if (out > 0) d2 += out * out;
  }
  return std::sqrt(d2);
}

// Points on the faces of b: near each corner, on each of the three faces
// that meet there, 10 % of the face inside its edges.
std::vector<std::array<double, 3>> face_points(const Box& b) {
  std::vector<std::array<double, 3>> out;
  for (int k = 0; k < 8; ++k)
    for (int m = 0; m < 3; ++m) {
      double local[3];
      for (int a = 0; a < 3; ++a) local[a] = ((k >> a) & 1 ? b.h[a] : -b.h[a]) * (a == m ? 1.0 : 0.9);
      std::array<double, 3> w{};
      for (int a = 0; a < 3; ++a) {
        w[a] = b.p[a];
        for (int i = 0; i < 3; ++i) w[a] += b.R[a][i] * local[i];
      }
      out.push_back(w);
    }
  return out;
}

// Body j (below) supports body i: a point on a face of one lies within `gap`
// of the other, between their centres' heights (below i's centre, above
// j's: a neighbour touching side to side is no support; face points, not
// corners, so that boxes meeting only edge to edge are no support either).
// The boxes may be tilted (a cube resting on a tilted cube, in a heap).
bool supports(const Box& i, const Box& j, double gap) {
  if (!(j.p[1] < i.p[1])) return false;
  for (const auto& c : face_points(i))
    if (c[1] < i.p[1] && c[1] > j.p[1] && distance_to(j, c.data()) <= gap) return true;
  for (const auto& c : face_points(j))
    if (c[1] > j.p[1] && c[1] < i.p[1] && distance_to(i, c.data()) <= gap) return true;
  return false;
}

Box box_of(const BodyDesc& desc, const BodySnapshot& s) {
  double R[3][3];
  rotation(s.q, R);
  const double h[3] = {desc.half_extents.x, desc.half_extents.y, desc.half_extents.z};
  Box b{};
  for (int a = 0; a < 3; ++a) {
    b.p[a] = s.p[a];
    b.h[a] = h[a];
    for (int i = 0; i < 3; ++i) b.R[a][i] = R[a][i];
  }
  for (int a = 0; a < 3; ++a) {
    const double e = std::fabs(R[a][0]) * h[0] + std::fabs(R[a][1]) * h[1] + std::fabs(R[a][2]) * h[2];
    b.lo[a] = s.p[a] - e;
    b.hi[a] = s.p[a] + e;
  }
  for (int k = 0; k < 8; ++k) {
    for (int a = 0; a < 3; ++a) {
      b.corners[k][a] = s.p[a];
      for (int i = 0; i < 3; ++i) b.corners[k][a] += R[a][i] * ((k >> i) & 1 ? h[i] : -h[i]);
    }
  }
  return b;
}

double overlap(double alo, double ahi, double blo, double bhi) { return std::min(ahi, bhi) - std::max(alo, blo); }

}  // namespace

FaceUp face_up(const double q[4], double flat_alignment) {
  double R[3][3];
  rotation(q, R);
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (std::fabs(R[1][i]) > std::fabs(R[1][best])) best = i;  // ties: lowest i (eq 65)
  FaceUp f;
  f.alignment = std::fabs(R[1][best]);
  if (f.alignment <= flat_alignment) {
    f.label = "none";
  } else {
    f.label = std::string(R[1][best] >= 0 ? "+" : "-") + "xyz"[best];
  }
  return f;
}

double orientation_angle(const double a[4], const double b[4]) {
  const Unit p = normalised(a), q = normalised(b);
  // r = conj(p) * q
  const double w = p.w * q.w + p.x * q.x + p.y * q.y + p.z * q.z;
  const double x = p.w * q.x - p.x * q.w - p.y * q.z + p.z * q.y;
  const double y = p.w * q.y + p.x * q.z - p.y * q.w - p.z * q.x;
  const double z = p.w * q.z - p.x * q.y + p.y * q.x - p.z * q.w;
  return 2.0 * std::atan2(std::sqrt(x * x + y * y + z * z), std::fabs(w));
}

std::string Support::label() const {
  switch (kind) {
    case ground: return "ground";
    case sdf: return "sdf " + std::to_string(index);
    case body: return "body " + std::to_string(index);
  }
  return "?";
}

std::string supports_label(const std::vector<Support>& supports) {
  if (supports.empty()) return "none";
  std::string s;
  for (const Support& x : supports) s += (s.empty() ? "" : " + ") + x.label();
  return s;
}

std::vector<RestingState> resting_states(const Scene& scene, const std::vector<BodySnapshot>& bodies, double gap,
                                         double flat_alignment) {
  const std::size_t n = std::min(bodies.size(), scene.bodies.size());
  std::vector<Box> boxes;
  for (std::size_t i = 0; i < n; ++i) boxes.push_back(box_of(scene.bodies[i], bodies[i]));

  std::vector<SdfGrid<double>> grids;
  for (const SdfDesc& d : scene.sdfs) {
    SdfGrid<double> g;
    g.min = {d.min.x, d.min.y, d.min.z};
    g.max = {d.max.x, d.max.y, d.max.z};
    g.n[0] = d.nx; g.n[1] = d.ny; g.n[2] = d.nz;
    for (int a = 0; a < 3; ++a) {
      g.inv_spacing[a] = (g.n[a] - 1) / (g.max[a] - g.min[a]);
      g.spacing[a] = (g.max[a] - g.min[a]) / (g.n[a] - 1);
    }
    g.values = d.values.data();
    grids.push_back(g);
  }

  std::vector<RestingState> out;
  for (std::size_t i = 0; i < n; ++i) {
    const BodySnapshot& s = bodies[i];
    const Box& b = boxes[i];
    RestingState r;
    std::copy(s.p, s.p + 3, r.p);
    r.face = face_up(s.q, flat_alignment);
    r.asleep = s.asleep;
    r.lowest = b.lo[1];
    if (scene.ground.present && scene.effects.ground && std::fabs(b.lo[1] - scene.ground.height) <= gap)
      r.supports.push_back({Support::ground, -1});
    if (scene.effects.sdf) {
      for (std::size_t k = 0; k < grids.size(); ++k) {
        double d = std::numeric_limits<double>::infinity();
        for (const auto& corner : b.corners) {
          const Vec3<double> c{corner[0], corner[1], corner[2]};
          if (sdf_contains(grids[k], c)) d = std::min(d, sdf_distance(grids[k], c));
        }
        if (std::fabs(d) <= gap) r.supports.push_back({Support::sdf, static_cast<int>(k)});
      }
    }
    if (scene.effects.contacts) {
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const bool aabb = std::fabs(b.lo[1] - boxes[j].hi[1]) <= gap && bodies[j].p[1] < s.p[1] &&
                          overlap(b.lo[0], b.hi[0], boxes[j].lo[0], boxes[j].hi[0]) > 0 &&
                          overlap(b.lo[2], b.hi[2], boxes[j].lo[2], boxes[j].hi[2]) > 0;
        if (aabb || supports(b, boxes[j], gap)) r.supports.push_back({Support::body, static_cast<int>(j)});
      }
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace lockstep::compare
