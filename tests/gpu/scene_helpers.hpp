// Helpers shared by the GPU engine's tests: runs of built-in scenes and the
// settling pile of the benchmark.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/compare/engine.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "lockstep/world.hpp"

namespace lockstep::gpu_test {

// A built-in scene with the given pair model (docs/GPU.md "Pair models":
// the GPU engine runs both).
inline Scene scene(const std::string& name, PairModel model) {
  auto s = builtin_scene(name);
  if (!s) throw std::runtime_error("no built-in scene " + name);
  s->pair_contacts = model;
  return *s;
}
// The source's AABB pair model.
inline Scene scene(const std::string& name) { return scene(name, PairModel::kAabb); }

inline const char* model_name(PairModel m) { return m == PairModel::kAabb ? "aabb" : "oriented_box"; }
inline constexpr PairModel kBothModels[] = {PairModel::kOrientedBox, PairModel::kAabb};

inline gpu::GpuOptions host_options() {
  gpu::GpuOptions o;
  o.backend = gpu::Backend::kHost;
  o.quiet = true;
  return o;
}

// The per-frame state hashes of a run (frame 1 .. frames).
template <class Engine>
std::vector<std::uint64_t> hashes(Engine& e, int frames) {
  std::vector<std::uint64_t> h;
  for (int f = 0; f < frames; ++f) {
    e.step();
    h.push_back(e.state_hash());
  }
  return h;
}

// The body axis (0..2, +1 for +axis, -1 for -axis, as 2*axis + (sign < 0))
// that points most nearly up: which face is up.
inline int face_up(const BodySnapshot& b) {
  const double w = b.q[0], x = b.q[1], y = b.q[2], z = b.q[3];
  // Row 1 of the rotation matrix: the world y of each body axis.
  const double up[3] = {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)};
  int best = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(up[a]) > std::fabs(up[best])) best = a;
  return 2 * best + (up[best] < 0 ? 1 : 0);
}

// World<T>::body(i) as the EngineRun snapshot (converted to double).
template <class T>
BodySnapshot snapshot(const World<T>& w, int i) { return snapshot_of(w.body(i)); }

inline double distance(const BodySnapshot& a, const BodySnapshot& b) {
  return std::sqrt((a.p[0] - b.p[0]) * (a.p[0] - b.p[0]) + (a.p[1] - b.p[1]) * (a.p[1] - b.p[1]) +
                   (a.p[2] - b.p[2]) * (a.p[2] - b.p[2]));
}

// A settling pile: n unit cubes (1 kg, e 0.2, mu 0.5) in columns of `height`
// on a square lattice, 0.2 m apart horizontally and vertically, the lowest
// 0.1 m above the ground, each turned by up to `jitter` (about radians per
// axis; deterministic integer jitter) so that the columns topple. With
// `asleep`, the cubes instead rest in stacks on the ground, all asleep.
inline Scene settling_pile(int n, int height, bool asleep, double jitter = 0.05) {
  Scene s;
  s.pair_contacts = PairModel::kAabb;  // the model of gpu_bench's measurements (docs/GPU.md); tests may switch it
  s.name = asleep ? "pile_asleep" : "pile";
  s.frames = 600;
  s.effects.sdf = false;
  const int columns = (n + height - 1) / height;
  int side = 1;
  while (side * side < columns) ++side;
  const double pitch = 1.2;
  std::uint32_t seed = 12345u;
  auto rand = [&seed]() {  // in [-1, 1], multiples of 2^-10
    seed = seed * 1664525u + 1013904223u;
    return static_cast<double>(static_cast<int>((seed >> 16) % 2049u) - 1024) / 1024.0;
  };
  for (int k = 0; k < n; ++k) {
    const int column = k / height, level = k % height;
    const int cx = column % side, cz = column / side;
    BodyDesc b;
    b.position = {(cx - side / 2) * pitch, asleep ? 0.5 + level : 0.6 + level * 1.2, (cz - side / 2) * pitch};
    if (!asleep) {
      const double jx = jitter * rand(), jy = jitter * rand(), jz = jitter * rand();
      b.orientation = {1.0, jx, jy, jz};
    }
    b.asleep = asleep;
    s.bodies.push_back(b);
  }
  return s;
}

}  // namespace lockstep::gpu_test
