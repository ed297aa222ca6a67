// World<T>: construction, the frame (docs/SPEC.md 7.2), hash and energy.
// Instantiated once per number type in world_<type>.cpp, so a build of the
// fixed engine alone (certification, cross compilers) needs no Boost.
#pragma once
#include "thread_pool.hpp"
#include "union_find.hpp"
#include "lockstep/world.hpp"

#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "broad_phase.hpp"
#include "contact_solver.hpp"
#include "input_forces.hpp"
#include "integrate.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "narrow_phase.hpp"
#include "queries.hpp"
#include "settle.hpp"
#include "sleep.hpp"
#include "snapshot.hpp"
#include "snapshot_scene.hpp"

namespace lockstep {

namespace world_detail {
template <class T>
Vec3<T> to_vec(const Vec3d& v) { return {Num<T>::from_double(v.x), Num<T>::from_double(v.y), Num<T>::from_double(v.z)}; }

// eq 10: a scene's (or an input's) orientation in T, normalised.
template <class T>
Quat<T> to_quat(const Quatd& q) {
  auto n = [](double x) { return Num<T>::from_double(x); };
  return normalize(Quat<T>{n(q.w), n(q.x), n(q.y), n(q.z)});
}

// A scene's body in T, as World(scene) builds it and create_body (eq 118)
// adds it; R and the AABB are left to update_derived.
template <class T>
Body<T> body_from_desc(const BodyDesc& d, bool sleep_effect) {
  auto n = [](double x) { return Num<T>::from_double(x); };
  const T three = Num<T>::from_int(3);
  Body<T> b;
  b.p = to_vec<T>(d.position);
  b.v = d.is_static ? Vec3<T>{} : to_vec<T>(d.velocity);
  b.w = d.is_static ? Vec3<T>{} : to_vec<T>(d.angular_velocity);
  b.q = to_quat<T>(d.orientation);  // eq 10
  b.half = to_vec<T>(d.half_extents);
  b.is_static = d.is_static;
  b.asleep = d.asleep && !d.is_static && sleep_effect;  // without the sleep effect nothing sleeps
  b.inv_mass = d.is_static ? T{} : Num<T>::from_int(1) / n(d.mass);
  b.inv_inertia = d.is_static ? Vec3<T>{} : box_inverse_inertia(b.half, b.inv_mass, three);  // eqs 14-18
  b.restitution = n(d.material.restitution);
  b.friction = n(d.material.friction);
  return b;
}
}  // namespace world_detail

template <class T>
World<T>::World(const Scene& scene)
    : scene_(scene), scene_section_(snap::encode_scene_section(scene)), constants_hash_(snap::constants_hash(scene.constants)),
      P_(Params<T>::from(scene.constants)) {
  Num<T>::take_faults();
  auto n = [](double x) { return Num<T>::from_double(x); };
  ground_y_ = n(scene.ground.height);
  ground_e_ = n(scene.ground.material.restitution);
  ground_mu_ = n(scene.ground.material.friction);
  check_faults(-1, "constants and ground");
  bodies_.reserve(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    Body<T> b = world_detail::body_from_desc<T>(scene.bodies[i], scene.effects.sleep);
    update_derived(b);
    bodies_.push_back(b);
    check_faults(static_cast<int>(i), "initial state (inverse mass, inertia, orientation, AABB)");
  }
  for (std::size_t k = 0; k < scene.sdfs.size(); ++k) {
    const SdfDesc& d = scene.sdfs[k];
    std::vector<T> values;
    values.reserve(d.values.size());
    for (double v : d.values) values.push_back(n(v));
    sdf_.values.push_back(std::move(values));
    SdfGrid<T> g;
    g.min = world_detail::to_vec<T>(d.min);
    g.max = world_detail::to_vec<T>(d.max);
    g.n[0] = d.nx; g.n[1] = d.ny; g.n[2] = d.nz;
    set_grid_spacing(g);  // eq 32
    sdf_.grids.push_back(g);
    sdf_e_.push_back(n(d.material.restitution));
    sdf_mu_.push_back(n(d.material.friction));
    check_faults(-1, "SDF volume");
  }
  for (std::size_t k = 0; k < sdf_.grids.size(); ++k) sdf_.grids[k].values = sdf_.values[k].data();
  support_.assign(bodies_.size(), -1);
  rests_.assign(bodies_.size(), {});
  support_n_.assign(bodies_.size(), Vec3<T>{});
  support_gap_.assign(bodies_.size(), T{});
  over_support_.assign(bodies_.size(), 1);
  leaning_.assign(bodies_.size(), 0);
  settle_limit_.assign(bodies_.size(), T{});
  can_rest_.assign(bodies_.size(), 1);
  sleep_support_.assign(bodies_.size(), SleepSupport{});
  wake_load_.assign(bodies_.size(), 0);
  // The id table: body i in slot i, generation 0 (docs/SPEC.md "Run-time inputs").
  ids_.reset(bodies_.size());
}

// docs/SPEC.md 7.2: the order of operations in a frame.
template <class T>
void World<T>::step() { step(StageObserver{}); }

template <class T>
void World<T>::step(const StageObserver& after_stage) {
  auto after = [&](FrameStage s) { if (after_stage) after_stage(s, *this); };
  // The workers spin between the frame's regions, and block after it (thread_pool.hpp).
  struct Hot {
    ThreadPool* pool;
    explicit Hot(ThreadPool* p) : pool(p) { if (pool != nullptr) pool->set_hot(true); }
    ~Hot() { if (pool != nullptr) pool->set_hot(false); }
    Hot(const Hot&) = delete;
    Hot& operator=(const Hot&) = delete;
  } hot(workers_.pool.get());
  ++frame_;
  Num<T>::take_faults();
  if (!forces_.empty()) apply_forces();                 // 0: eq 121 (run-time inputs)
  after(FrameStage::forces);
  integrate_velocities();                               // 1: eqs 1, 5, 6, 13
  after(FrameStage::integrate_velocities);
  const bool oriented = scene_.pair_contacts == PairModel::kOrientedBox;
  if (scene_.effects.sleep && oriented) wake_unsupported();  // 2a: eq 108
  after(FrameStage::support_wake);
  broad_phase();                                        // 2: eqs 31, 82, 83, 107
  after(FrameStage::broad_phase);
  narrow_phase();                                       // 3-4: eqs 32-47, 84, 85, 93; wake eq 81
  after(FrameStage::narrow_phase);
  solve_contacts();                                     // 5: eqs 48-62, 76, 86-88, 94-97
  after(FrameStage::solve);
  if (scene_.effects.settling) settle();                // 6: eqs 64-75, 77
  after(FrameStage::settle);
  correct_positions();                                  // 7: eqs 63, 89
  after(FrameStage::correct_positions);
  integrate_positions();                                // 8: eqs 2, 7-10
  after(FrameStage::integrate_positions);
  if (scene_.effects.sleep) update_sleep();             // 9: eqs 78-80
  after(FrameStage::sleep);
  if constexpr (!Num<T>::kExact) check_finite();
}

template <class T>
void World<T>::set_threads(int threads) {
  if (threads < 1 || threads > 256)
    throw std::invalid_argument("threads = " + std::to_string(threads) +
                                ": World<T>::set_threads needs 1 to 256 threads (1: the caller's alone)");
  if (threads != workers_.threads) workers_.pool.reset();
  workers_.threads = threads;
}

template <class T>
template <class Body>
void World<T>::parallel_for(std::size_t count, std::size_t grain, const Body& body) {
  run_items(count, grain, false, body);
}

template <class T>
template <class Body>
void World<T>::parallel_each(std::size_t count, std::size_t grain, const Body& body) {
  run_items(count, grain, true, body);
}

template <class T>
template <class Body>
void World<T>::run_items(std::size_t count, std::size_t grain, bool chunks, const Body& body) {
  // At most one part per thread, each of at least `grain` items; the work
  // each item does never depends on the part that runs it.
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t parts = std::min<std::size_t>(static_cast<std::size_t>(workers_.threads), count / grain);
  if (parts <= 1) {
    for (std::size_t k = 0; k < count; ++k) body(k, 0);
    return;
  }
  if (!workers_.pool) workers_.pool = std::make_shared<ThreadPool>(workers_.threads);  // (dropped when the count changes)
  // A part stops at its first RunError; the lowest item's is rethrown, the
  // one a single thread would have met first. (Chunks go out in ascending
  // order, so every item below a failing one has gone to some part, which
  // runs it.)
  const std::size_t chunk_count = (count + grain - 1) / grain;
  std::atomic<std::size_t> next{0};
  std::array<std::size_t, 256> failed;  // parts <= threads <= 256 (set_threads)
  std::array<std::exception_ptr, 256> errors;
  failed.fill(count);
  workers_.pool->run(static_cast<int>(parts), [&](int part) {
    // A worker's faults: none left from an earlier region. Part 0 runs on the
    // caller, whose pending faults the next check reports, as on one thread.
    if (part != 0) Num<T>::take_faults();
    auto items = [&](std::size_t lo, std::size_t hi) {
      for (std::size_t k = lo; k < hi; ++k) {
        try {
          body(k, part);
        } catch (const RunError&) {
          failed[static_cast<std::size_t>(part)] = k;
          errors[static_cast<std::size_t>(part)] = std::current_exception();
          return false;
        }
      }
      return true;
    };
    if (!chunks) {
      items(count * static_cast<std::size_t>(part) / parts, count * static_cast<std::size_t>(part + 1) / parts);
      return;
    }
    for (std::size_t c; (c = next.fetch_add(1, std::memory_order_relaxed)) < chunk_count;)
      if (!items(c * grain, std::min(count, (c + 1) * grain))) return;
  });
  std::size_t first = parts;
  for (std::size_t p = 0; p < parts; ++p)
    if (errors[p] && (first == parts || failed[p] < failed[first])) first = p;
  if (first < parts) std::rethrow_exception(errors[first]);
}

template <class T>
template <class Bodies, class Run>
void World<T>::items_by_groups(std::size_t count, const Bodies& bodies_of, const Run& run) {
  if (workers_.threads <= 1 || count < 128) {
    for (std::size_t k = 0; k < count; ++k) run(k);
    return;
  }
  // The groups: union-find over the items' bodies, the lower root joining.
  std::vector<int>& root = scratch_.group_root;
  root.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) root[i] = static_cast<int>(i);
  auto find = [&](int b) { return union_find_root(root, b); };
  for (std::size_t k = 0; k < count; ++k) {
    const std::array<int, 2> b = bodies_of(k);
    if (b[0] >= 0 && b[1] >= 0) union_find_join(root, b[0], b[1]);
  }
  // Each group's items in ascending order (a counting sort by group, stable).
  std::vector<int>& group_of = scratch_.group_of;  // per root: its group
  std::vector<int>& begin = scratch_.group_begin;
  std::vector<int>& members = scratch_.group_members;
  group_of.assign(bodies_.size(), -1);
  begin.assign(1, 0);
  auto group = [&](std::size_t k) {
    const std::array<int, 2> b = bodies_of(k);
    return &group_of[static_cast<std::size_t>(find(b[0] >= 0 ? b[0] : b[1]))];
  };
  for (std::size_t k = 0; k < count; ++k) {
    int& g = *group(k);
    if (g < 0) {
      g = static_cast<int>(begin.size()) - 1;
      begin.push_back(0);
    }
    ++begin[static_cast<std::size_t>(g) + 1];
  }
  const std::size_t groups = begin.size() - 1;
  if (groups < 2) {
    for (std::size_t k = 0; k < count; ++k) run(k);
    return;
  }
  for (std::size_t g = 0; g < groups; ++g) begin[g + 1] += begin[g];
  members.resize(count);
  {
    std::vector<int> at(begin.begin(), begin.end() - 1);
    for (std::size_t k = 0; k < count; ++k) members[static_cast<std::size_t>(at[static_cast<std::size_t>(*group(k))]++)] = static_cast<int>(k);
  }
  // Each group on its own; a RunError ends its group, and the one of the
  // lowest item is rethrown.
  std::vector<std::exception_ptr> errors(groups);
  std::vector<std::size_t> failed(groups, count);
  parallel_each(groups, 1, [&](std::size_t g, int) {
    for (int m = begin[g]; m < begin[g + 1]; ++m) {
      const auto k = static_cast<std::size_t>(members[static_cast<std::size_t>(m)]);
      try {
        run(k);
      } catch (const RunError&) {
        errors[g] = std::current_exception();
        failed[g] = k;
        return;
      }
    }
  });
  std::size_t first = groups;
  for (std::size_t g = 0; g < groups; ++g)
    if (errors[g] && (first == groups || failed[g] < failed[first])) first = g;
  if (first < groups) std::rethrow_exception(errors[first]);
}

template <class T>
template <class Dep, class Run>
void World<T>::in_order_by_groups(const std::vector<int>& order, bool reverse, const Dep& dep, const Run& run) {
  const std::size_t n = order.size();
  auto at = [&](std::size_t k) { return order[reverse ? n - 1 - k : k]; };
  items_by_groups(n, [&](std::size_t k) { return std::array<int, 2>{at(k), dep(at(k))}; }, [&](std::size_t k) { run(at(k)); });
}

template <class T>
void World<T>::check_faults(int body, const char* quantity) {
  if (const std::uint32_t f = Num<T>::take_faults()) throw RunError(frame_, body, quantity, q16_flag_name(f));
}

template <class T>
void World<T>::check_finite() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body<T>& b = bodies_[i];
    if (!b.awake()) continue;
    auto fin = [](const Vec3<T>& v) { return Num<T>::finite(v.x) && Num<T>::finite(v.y) && Num<T>::finite(v.z); };
    const char* what = !fin(b.p) ? "position" : !fin(b.v) ? "velocity" : !fin(b.w) ? "angular velocity"
                     : !(Num<T>::finite(b.q.w) && Num<T>::finite(b.q.x) && Num<T>::finite(b.q.y) && Num<T>::finite(b.q.z)) ? "orientation"
                     : nullptr;
    if (what != nullptr) throw RunError(frame_, static_cast<int>(i), what, "not finite (NaN or infinity)");
  }
}

template <class T>
int World<T>::awake_count() const {
  int count = 0;
  for (const Body<T>& b : bodies_) count += b.awake() ? 1 : 0;
  return count;
}

template <class T>
bool World<T>::all_asleep() const { return awake_count() == 0; }

// eq 92: FNV-1a 64.
template <class T>
std::uint64_t World<T>::state_hash() const {
  std::uint64_t h = 0xcbf29ce484222325ull;
  auto byte = [&h](std::uint8_t b) { h ^= b; h *= 0x100000001b3ull; };
  auto value = [&](const T& x) {
    if constexpr (std::is_same_v<T, Q16>) {
      const auto u = static_cast<std::uint32_t>(x.raw());
      for (int s = 0; s < 32; s += 8) byte(static_cast<std::uint8_t>(u >> s));
    } else {
      const double d = Num<T>::to_double(x);
      std::uint64_t u;
      std::memcpy(&u, &d, sizeof u);
      for (int s = 0; s < 64; s += 8) byte(static_cast<std::uint8_t>(u >> s));
    }
  };
  for (const Body<T>& b : bodies_) {
    for (const T& x : {b.p.x, b.p.y, b.p.z, b.q.w, b.q.x, b.q.y, b.q.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z}) value(x);
    byte(b.asleep ? 1 : 0);
  }
  return h;
}

template <class T>
double World<T>::energy() const {
  double e = 0.0;
  const Vec3d& g = scene_.constants.gravity;
  for (const Body<T>& b : bodies_) {
    if (b.is_static) continue;
    const double m = 1.0 / Num<T>::to_double(b.inv_mass);
    auto d = [](const T& x) { return Num<T>::to_double(x); };
    const double vx = d(b.v.x), vy = d(b.v.y), vz = d(b.v.z);
    e += 0.5 * m * (vx * vx + vy * vy + vz * vz);
    e -= m * (g.x * d(b.p.x) + g.y * d(b.p.y) + g.z * d(b.p.z));
    const Vec3<T> wb = mat_transpose_mul(b.R, b.w);  // body-frame omega
    for (int a = 0; a < 3; ++a) {
      const double inv_i = d(b.inv_inertia[a]);
      if (inv_i > 0.0) e += 0.5 * d(wb[a]) * d(wb[a]) / inv_i;
    }
  }
  return e;
}

}  // namespace lockstep
