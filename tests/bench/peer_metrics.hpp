// What peer_bench reports of a run, from body snapshots only, so that every
// engine (lockstep's, Bullet in process, Jolt from a trajectory) is measured
// by the same code: the worst penetration into the ground and between two
// boxes over all frames and at the last (separating axes in double,
// peer/box_pair.hpp), the
// frame from which every body stayed asleep, and how many columns stand at
// the end.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "hard/body_geometry.hpp"
#include "lockstep/scene.hpp"
#include "peer/box_pair.hpp"

namespace lockstep::peer {

struct PeerMetrics {
  double worst_ground_m = 0;  // deepest corner below the ground plane, all frames
  double worst_pair_m = 0;    // deepest box-box overlap (penetration depth), all frames
  double end_ground_m = 0, end_pair_m = 0;  // the same at the last frame: how deep bodies rest
  int worst_ground_frame = -1, worst_ground_body = -1;
  int worst_pair_frame = -1, worst_pair_a = -1, worst_pair_b = -1;
  int all_asleep_frame = -1;  // from this frame on every body was asleep (-1: not at the end)
  int asleep_at_end = 0;
  int columns = 0;
  int standing = 0;  // every cube within 2 cm of its stacked height (tests/peer's rule)
  int upright = 0;   // every cube within a quarter of its size of its level (README "Stacking"'s rule)
};

// The scene's columns: bodies grouped by where they start (x, z), a body
// joining the first column whose first body starts within half its size.
inline std::vector<std::vector<int>> columns_of(const Scene& s) {
  std::vector<std::vector<int>> cols;
  for (int i = 0; i < static_cast<int>(s.bodies.size()); ++i) {
    const BodyDesc& b = s.bodies[static_cast<std::size_t>(i)];
    bool placed = false;
    for (auto& c : cols) {
      const BodyDesc& f = s.bodies[static_cast<std::size_t>(c.front())];
      if (std::hypot(b.position.x - f.position.x, b.position.z - f.position.z) < f.half_extents.y) {
        c.push_back(i);
        placed = true;
        break;
      }
    }
    if (!placed) cols.push_back({i});
  }
  return cols;
}

class MetricsRecorder {
 public:
  explicit MetricsRecorder(const Scene& s) : scene_(s), cols_(columns_of(s)) { m_.columns = static_cast<int>(cols_.size()); }

  // One frame's snapshots (body order of the scene).
  void frame(int frame, const std::vector<BodySnapshot>& b) {
    const std::size_t n = b.size();
    geo_.clear();
    for (std::size_t i = 0; i < n; ++i) geo_.push_back(hard::geometry_of(b[i], scene_.bodies[i].half_extents));
    bool all = n > 0;
    int asleep = 0;
    m_.end_ground_m = m_.end_pair_m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      all = all && b[i].asleep;
      asleep += b[i].asleep;
      if (scene_.ground.present) m_.end_ground_m = std::max(m_.end_ground_m, scene_.ground.height - geo_[i].lowest_y);
      if (scene_.ground.present && scene_.ground.height - geo_[i].lowest_y > m_.worst_ground_m) {
        m_.worst_ground_m = scene_.ground.height - geo_[i].lowest_y;
        m_.worst_ground_frame = frame;
        m_.worst_ground_body = static_cast<int>(i);
      }
    }
    if (!all) m_.all_asleep_frame = -1;
    else if (m_.all_asleep_frame < 0) m_.all_asleep_frame = frame;
    m_.asleep_at_end = asleep;
    // Pairs whose bounding spheres meet: sweep along x.
    order_.resize(n);
    for (std::size_t i = 0; i < n; ++i) order_[i] = i;
    std::sort(order_.begin(), order_.end(), [&b](std::size_t x, std::size_t y) { return b[x].p[0] < b[y].p[0]; });
    for (std::size_t a = 0; a < n; ++a) {
      const std::size_t i = order_[a];
      const double ri = radius(i);
      for (std::size_t c = a + 1; c < n; ++c) {
        const std::size_t j = order_[c];
        const double r = ri + radius(j);
        if (b[j].p[0] - b[i].p[0] > r) break;
        const double dy = b[j].p[1] - b[i].p[1], dz = b[j].p[2] - b[i].p[2], dx = b[j].p[0] - b[i].p[0];
        if (dx * dx + dy * dy + dz * dz > r * r) continue;
        const double sep = box_pair_separation(b[i], geo_[i], scene_.bodies[i].half_extents, b[j], geo_[j], scene_.bodies[j].half_extents);
        m_.end_pair_m = std::max(m_.end_pair_m, -sep);
        if (-sep > m_.worst_pair_m) {
          m_.worst_pair_m = -sep;
          m_.worst_pair_frame = frame;
          m_.worst_pair_a = static_cast<int>(std::min(i, j));
          m_.worst_pair_b = static_cast<int>(std::max(i, j));
        }
      }
    }
    last_ = b;
  }

  // The counts from the last frame: a column stands when, sorted by height,
  // its k-th cube is within 2 cm of size/2 + k size and within half its size
  // of the column's mean axis (tests/peer/columns.hpp's rule, less the sleep,
  // which all_asleep_frame reports); it is upright when each is within a
  // quarter of its size of that height instead (README "Stacking": a column
  // whose cubes sink into each other, as Jolt's do by its penetration slop,
  // is upright but does not stand).
  PeerMetrics finish() {
    m_.standing = 0;
    m_.upright = 0;
    for (const auto& c : cols_) {
      std::vector<const BodySnapshot*> s;
      double cx = 0, cz = 0;
      for (int i : c) {
        s.push_back(&last_[static_cast<std::size_t>(i)]);
        cx += s.back()->p[0];
        cz += s.back()->p[2];
      }
      cx /= static_cast<double>(c.size());
      cz /= static_cast<double>(c.size());
      std::sort(s.begin(), s.end(), [](const BodySnapshot* x, const BodySnapshot* y) { return x->p[1] < y->p[1]; });
      const double size = 2 * scene_.bodies[static_cast<std::size_t>(c.front())].half_extents.y;
      bool ok = true, upright = true;
      for (std::size_t k = 0; k < s.size(); ++k) {
        const double ideal = scene_.ground.height + size / 2 + static_cast<double>(k) * size;
        const bool on_axis = std::hypot(s[k]->p[0] - cx, s[k]->p[2] - cz) < size / 2;
        ok = ok && on_axis && std::fabs(s[k]->p[1] - ideal) < 0.02;
        upright = upright && on_axis && std::fabs(s[k]->p[1] - ideal) < size / 4;
      }
      m_.standing += ok;
      m_.upright += upright;
    }
    return m_;
  }

 private:
  double radius(std::size_t i) const {
    const Vec3d& h = scene_.bodies[i].half_extents;
    return std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
  }
  const Scene& scene_;
  std::vector<std::vector<int>> cols_;
  std::vector<hard::BodyGeometry> geo_;
  std::vector<std::size_t> order_;
  std::vector<BodySnapshot> last_;
  PeerMetrics m_;
};

}  // namespace lockstep::peer
