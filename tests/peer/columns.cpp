#include "columns.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "box_pair.hpp"
#include "hard/body_geometry.hpp"

namespace lockstep::peer {
namespace {

// SplitMix64: a fixed, portable stream (std:: distributions are
// implementation-defined).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : x_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (x_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double symmetric() { return 2.0 * unit() - 1.0; }                        // [-1, 1)

 private:
  std::uint64_t x_;
};

}  // namespace

std::vector<Column> harder_columns(int count, std::uint64_t seed) {
  Rng rng(seed);
  const double max_tilt = 2.0 * M_PI / 180.0;
  std::vector<Column> out;
  for (int c = 0; c < count; ++c) {
    Column col;
    col.index = c;
    const int n = 2 + static_cast<int>(rng.next() % 9);  // 2..10
    col.size = 0.25 + 0.75 * rng.unit();
    const double h = col.size / 2;
    col.scene.name = "peer_column_" + std::to_string(c);
    col.scene.frames = 600;
    col.scene.effects.sdf = false;
    col.scene.ground.material = {0.2, 0.5};
    double top = 0.0;  // the highest point of the cube below (the ground first)
    for (int i = 0; i < n; ++i) {
      BodyDesc b;
      b.half_extents = {h, h, h};
      b.mass = 0.5 + 1.5 * rng.unit();
      // A random axis (uniform on the sphere, by rejection) and angle.
      double ax, ay, az, l2;
      do {
        ax = rng.symmetric();
        ay = rng.symmetric();
        az = rng.symmetric();
        l2 = ax * ax + ay * ay + az * az;
      } while (l2 > 1.0 || l2 < 1e-6);
      const double angle = max_tilt * rng.unit();
      const double s = std::sin(angle / 2) / std::sqrt(l2);
      b.orientation = {std::cos(angle / 2), ax * s, ay * s, az * s};
      const double dx = 0.1 * col.size * rng.symmetric();
      const double dz = 0.1 * col.size * rng.symmetric();
      const double gap = 0.3 * rng.unit();
      // The half height of the tilted cube (its AABB's y half extent).
      BodySnapshot snap{{0, 0, 0}, {b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z}, {}, {}, false, -1};
      const double half_height = hard::geometry_of(snap, b.half_extents).aabb_half[1];
      b.position = {dx, top + gap + half_height, dz};
      top = b.position.y + half_height;
      b.material = {0.2, 0.5};
      col.scene.bodies.push_back(b);
    }
    out.push_back(std::move(col));
  }
  return out;
}

double snapshot_energy(const EngineRun& engine, const Scene& scene) {
  double e = 0.0;
  for (int i = 0; i < engine.body_count(); ++i) {
    const BodyDesc& d = scene.bodies[static_cast<std::size_t>(i)];
    const BodySnapshot s = engine.body(i);
    e += hard::body_energy(s, hard::geometry_of(s, d.half_extents), d, scene.constants.gravity);
  }
  return e;
}

double worst_sleeping_gap(const EngineRun& engine, const Scene& scene) {
  const int n = engine.body_count();
  std::vector<BodySnapshot> s;
  std::vector<hard::BodyGeometry> g;
  for (int i = 0; i < n; ++i) {
    s.push_back(engine.body(i));
    g.push_back(hard::geometry_of(s.back(), scene.bodies[static_cast<std::size_t>(i)].half_extents));
  }
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    if (!s[i].asleep) continue;
    double gap = scene.ground.present ? g[i].lowest_y - scene.ground.height : INFINITY;
    for (int j = 0; j < n; ++j) {
      if (j == i || !(s[j].p[1] < s[i].p[1])) continue;
      gap = std::min(gap, box_pair_separation(s[i], g[i], scene.bodies[static_cast<std::size_t>(i)].half_extents, s[j], g[j],
                                              scene.bodies[static_cast<std::size_t>(j)].half_extents));
    }
    worst = std::max(worst, gap);
  }
  return worst;
}

ColumnResult run_column(EngineRun& engine, const Column& c) {
  ColumnResult r;
  r.energy_start = snapshot_energy(engine, c.scene);
  r.energy_gain = -INFINITY;
  double least = r.energy_start;
  for (int f = 0; f < c.scene.frames; ++f) {
    engine.step();
    const double e = snapshot_energy(engine, c.scene);
    if (e - r.energy_start > r.energy_gain) {
      r.energy_gain = e - r.energy_start;
      r.gain_frame = engine.frame();
    }
    if (e - least > r.rebound) {
      r.rebound = e - least;
      r.rebound_frame = engine.frame();
    }
    least = std::min(least, e);
    const double gap = worst_sleeping_gap(engine, c.scene);
    if (gap > r.worst_sleeping_gap) r.worst_sleeping_gap = gap;
    if (gap > kSleepGap && r.gap_frame < 0) r.gap_frame = engine.frame();
    bool all = true;
    for (int i = 0; i < engine.body_count() && all; ++i) all = engine.body(i).asleep;
    if (!all) r.all_asleep_frame = -1;
    else if (r.all_asleep_frame < 0) r.all_asleep_frame = engine.frame();
  }
  const int n = engine.body_count();
  std::vector<BodySnapshot> fin;
  for (int i = 0; i < n; ++i) fin.push_back(engine.body(i));
  std::sort(fin.begin(), fin.end(), [](const BodySnapshot& a, const BodySnapshot& b) { return a.p[1] < b.p[1]; });
  double cx = 0, cz = 0;
  for (const BodySnapshot& b : fin) {
    cx += b.p[0];
    cz += b.p[2];
  }
  cx /= n;
  cz /= n;
  std::ostringstream why;
  for (int k = 0; k < n && why.str().empty(); ++k) {
    const BodySnapshot& b = fin[static_cast<std::size_t>(k)];
    const double ideal = c.size / 2 + k * c.size;
    const double off = std::hypot(b.p[0] - cx, b.p[2] - cz);
    if (!(std::fabs(b.p[1] - ideal) < kHeightTolerance))
      why << "cube " << k << " of " << n << " ends at y " << b.p[1] << ", " << std::fabs(b.p[1] - ideal) << " m from its ideal " << ideal;
    else if (!(off < c.size / 2))
      why << "cube " << k << " of " << n << " ends " << off << " m off the column's axis (size " << c.size << ")";
    else if (!b.asleep)
      why << "cube " << k << " of " << n << " is awake at frame " << engine.frame();
  }
  if (why.str().empty() && r.gap_frame >= 0)
    why << "a sleeping cube hung " << r.worst_sleeping_gap << " m over its support (first at frame " << r.gap_frame << ")";
  r.why = why.str();
  r.stands = r.why.empty();
  return r;
}

}  // namespace lockstep::peer
