// World<T>'s snapshots (docs/SNAPSHOTS.md): save_state here; load_state and
// restore_state in snapshot_load.hpp (the fixed engine's certification
// build, vectors/certify, steps and saves but never loads, so it needs
// neither the scene loader nor the scene limits). The header and scene section are snapshot_scene.cpp's; this
// file writes and reads the moving state: per body its pose, velocities and
// sleep state with eq 108's records, then the warm-start cache (eq 96), the
// id table and pending forces of the run-time inputs, and the stage counters. Per-frame scratch (contacts, pairs, supports, the
// broadphase grid, ...) is rebuilt by every step before it is read and is
// not saved (snapshot_test checks it).
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "lockstep/scene_limits.hpp"
#include "lockstep/world.hpp"
#include "snapshot_bytes.hpp"
#include "snapshot_number.hpp"
#include "snapshot_scene.hpp"

namespace lockstep {

namespace snap {
// Bounds a snapshot's values must keep (docs/SNAPSHOTS.md "What is refused").
inline constexpr double kMaxCoordinate = 32768.0;   // positions, support points (m)
inline constexpr double kMaxSpeed = 32768.0;        // velocity components (m/s, rad/s)
inline constexpr double kMaxQuatComponent = 2.0;    // orientation components
inline constexpr double kMaxImpulse = 2147483648.0; // a cached normal impulse (N s)
inline constexpr std::size_t kMaxIntVarint = 10;

// The 16 stage counters in StageCounters' declaration order.
template <class C, class F>
void each_counter(C& c, F&& f) {
  f(c.integrate_velocity); f(c.damping); f(c.integrate_position); f(c.broadphase_bodies); f(c.pairs_tested);
  f(c.ground_contacts); f(c.sdf_contacts); f(c.body_contacts); f(c.solver_contacts); f(c.normal_impulses);
  f(c.restitution_bounces); f(c.friction_steps); f(c.corrections); f(c.settling_bodies); f(c.sleep_updates); f(c.wakes);
}
static_assert(sizeof(StageCounters) == 16 * sizeof(std::uint64_t), "a counter was added: add it to each_counter");

[[noreturn]] inline void refuse(const std::string& field, const std::string& what) {
  throw SnapshotError(field + ": " + what, field);
}
}  // namespace snap

template <class T>
std::vector<std::uint8_t> World<T>::save_state() const {
  std::vector<std::uint8_t> out;
  save_state(out);
  return out;
}

template <class T>
void World<T>::save_state(std::vector<std::uint8_t>& out) const {
  using C = snap::NumCodec<T>;
  constexpr std::size_t s = C::kMaxBytes, v = snap::kMaxIntVarint;
  std::size_t records = 0;
  for (const std::vector<Rest>& r : rests_) records += r.size();
  const std::size_t bound = kSnapshotHeaderSize + scene_section_.size() + bodies_.size() * (1 + 13 * s + 2 * v) +
                            records * (v + 9 * s) + v + warm_.size() * (3 * v + s) +
                            v + (ids_.slots() + ids_.bodies()) * v + v + forces_.size() * (v + 6 * s) + 16 * v +
                            kSnapshotChecksumSize;
  out.clear();
  out.reserve(bound);
  snap::Writer w(out);
  snap::write_header(w, C::kNumber, static_cast<std::uint32_t>(bodies_.size()), constants_hash_,
                     static_cast<std::uint32_t>(frame_));
  w.bytes(scene_section_.data(), scene_section_.size());
  const std::size_t at = out.size();
  out.resize(bound);
  snap::Cursor c{out.data() + at};
  auto vec = [&c](const Vec3<T>& x) { C::put(c, x.x); C::put(c, x.y); C::put(c, x.z); };
  auto zero = [](const Vec3<T>& x) { return C::is_zero_bits(x.x) && C::is_zero_bits(x.y) && C::is_zero_bits(x.z); };
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body<T>& b = bodies_[i];
    const std::vector<Rest>& rests = rests_[i];
    const bool has_v = !zero(b.v), has_w = !zero(b.w), has_sleep_frame = b.sleep_frame >= 0;
    c.u8(static_cast<std::uint8_t>((b.asleep ? 1 : 0) | (has_v ? 2 : 0) | (has_w ? 4 : 0) | (has_sleep_frame ? 8 : 0) |
                                   (rests.size() << 4)));
    vec(b.p);
    C::put(c, b.q.w); C::put(c, b.q.x); C::put(c, b.q.y); C::put(c, b.q.z);
    if (has_v) vec(b.v);
    if (has_w) vec(b.w);
    c.svarint(b.sleep_counter);
    if (has_sleep_frame) c.svarint(static_cast<std::int64_t>(frame_) - b.sleep_frame);
    for (const Rest& r : rests) {
      const bool moved = !(C::same_bits(r.last.x, r.rest.x) && C::same_bits(r.last.y, r.rest.y) && C::same_bits(r.last.z, r.rest.z));
      const std::int64_t d = static_cast<std::int64_t>(r.body) - static_cast<std::int64_t>(i);
      const std::uint64_t zz = (static_cast<std::uint64_t>(d) << 1) ^ static_cast<std::uint64_t>(d < 0 ? -1 : 0);
      c.varint((zz << 1) | (moved ? 1 : 0));
      vec(r.local);
      vec(r.rest);
      if (moved) vec(r.last);
    }
  }
  c.varint(warm_.size());
  int prev_a = 0;
  for (const CachedImpulse& e : warm_) {
    c.svarint(static_cast<std::int64_t>(e.a) - prev_a);
    prev_a = e.a;
    c.svarint(e.b);
    c.svarint(e.feature);
    C::put(c, e.j_n);
  }
  // The id table: 0 when slot i holds body i at generation 0 and there is no
  // other slot (no body was ever destroyed); else the slots' generations and
  // each body's slot.
  if (ids_.identity()) {
    c.varint(0);
  } else {
    c.varint(ids_.slots());
    for (std::size_t k = 0; k < ids_.slots(); ++k) c.varint(ids_.generation(k));
    for (std::size_t i = 0; i < ids_.bodies(); ++i) c.varint(ids_.slot_of(i));
  }
  // The forces pending for the next step (eq 121), ascending body index.
  c.varint(forces_.size());
  int prev_body = 0;
  for (const PendingForce& f : forces_) {
    c.varint(static_cast<std::uint64_t>(f.body - prev_body));
    prev_body = f.body;
    vec(f.f);
    vec(f.tau);
  }
  snap::each_counter(counters_, [&c](std::uint64_t x) { c.varint(x); });
  out.resize(static_cast<std::size_t>(c.p - out.data()));
  snap::finish(out);
}

}  // namespace lockstep
