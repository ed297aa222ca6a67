// World<T>'s snapshot loading (docs/SNAPSHOTS.md): load_state,
// restore_state and the moving state they read. Included by the world_*.cpp
// that instantiate them (world_fixed_load.cpp for the fixed engine).
#pragma once
#include "lockstep/scene_limits.hpp"
#include "snapshot.hpp"

namespace lockstep {

template <class T>
void World<T>::read_moving_state(snap::Reader& r, std::uint32_t frame, bool derived_valid) {
  using C = snap::NumCodec<T>;
  using snap::refuse;
  const std::size_t n = bodies_.size();
  const int frame_now = static_cast<int>(frame);
  frame_ = frame_now;
  auto get_vec = [&r](const char* field) {
    Vec3<T> x;
    x.x = C::get(r, field);
    x.y = C::get(r, field);
    x.z = C::get(r, field);
    return x;
  };
  auto within = [](const Vec3<T>& x, double limit) { return C::within(x.x, limit) && C::within(x.y, limit) && C::within(x.z, limit); };
  std::size_t i = 0;
  // Another dynamic body, named relative to body i as zigzag(other - i).
  auto other_body = [&](std::uint64_t zz, const char* field, const char* what) {
    const std::int64_t d = static_cast<std::int64_t>(zz >> 1) ^ -static_cast<std::int64_t>(zz & 1);
    const std::int64_t other = static_cast<std::int64_t>(i) + d;
    if (other < 0 || other >= static_cast<std::int64_t>(n) || other == static_cast<std::int64_t>(i) ||
        bodies_[static_cast<std::size_t>(other)].is_static)
      refuse(field, std::string(what) + " " + std::to_string(other) + " is not another dynamic body of the " +
                        std::to_string(n));
    return static_cast<int>(other);
  };
  try {
    for (; i < n; ++i) {
      Body<T>& b = bodies_[i];
      const std::uint8_t flags = r.u8("flags");
      const std::size_t records = (flags >> 4) & 7;
      if (records > static_cast<std::size_t>(kMaxRests))
        refuse("flags", "byte " + std::to_string(flags) + " names more than " + std::to_string(kMaxRests) +
                            " support records");
      if ((flags & 0x80) != 0 && (flags & 1) == 0) refuse("flags", "an eq 124 record on a body that is not asleep");
      if (b.is_static && (flags & 0x0f) != 0) refuse("flags", "a static body cannot be asleep, move or have slept");
      if ((flags & 1) != 0 && !scene_.effects.sleep) refuse("flags", "asleep in a scene without the sleep effect");
      b.asleep = (flags & 1) != 0;
      const Vec3<T> p = get_vec("p");
      Quat<T> q;
      q.w = C::get(r, "q"); q.x = C::get(r, "q"); q.y = C::get(r, "q"); q.z = C::get(r, "q");
      if (!within(p, snap::kMaxCoordinate)) refuse("p", "a coordinate is not finite or not within |x| < 32768 m");
      const double qn = Num<T>::to_double(q.w) * Num<T>::to_double(q.w) + Num<T>::to_double(q.x) * Num<T>::to_double(q.x) +
                        Num<T>::to_double(q.y) * Num<T>::to_double(q.y) + Num<T>::to_double(q.z) * Num<T>::to_double(q.z);
      if (!(C::within(q.w, snap::kMaxQuatComponent) && C::within(q.x, snap::kMaxQuatComponent) &&
            C::within(q.y, snap::kMaxQuatComponent) && C::within(q.z, snap::kMaxQuatComponent)) ||
          !(qn >= 0.25 && qn <= 4.0))
        refuse("q", "not a unit quaternion (norm^2 " + std::to_string(qn) + ")");
      b.v = (flags & 2) != 0 ? get_vec("v") : Vec3<T>{};
      b.w = (flags & 4) != 0 ? get_vec("w") : Vec3<T>{};
      if (!within(b.v, snap::kMaxSpeed)) refuse("v", "a component is not finite or not within |v| < 32768 m/s");
      if (!within(b.w, snap::kMaxSpeed)) refuse("w", "a component is not finite or not within |w| < 32768 rad/s");
      const std::int64_t counter = r.svarint("sleep_counter");
      if (counter < 0 || counter > INT32_MAX || (b.is_static && counter != 0))
        refuse("sleep_counter", std::to_string(counter) + " is outside [0, 2^31)" + (b.is_static ? " or not 0 (static)" : ""));
      b.sleep_counter = static_cast<int>(counter);
      b.sleep_frame = -1;
      if ((flags & 8) != 0) {
        const std::int64_t ago = r.svarint("sleep_frame");
        if (ago < 0 || ago > frame_now) refuse("sleep_frame", std::to_string(ago) + " frames ago is outside [0, frame]");
        b.sleep_frame = frame_now - static_cast<int>(ago);
      }
      std::vector<Rest>& rests = rests_[i];
      rests.resize(records);
      for (Rest& rec : rests) {
        const std::uint64_t key = r.varint("rests.body");
        rec.body = other_body(key >> 1, "rests.body", "supporter");
        rec.local = get_vec("rests.local");
        rec.rest = get_vec("rests.rest");
        rec.last = (key & 1) != 0 ? get_vec("rests.last") : rec.rest;
        if (!within(rec.local, snap::kMaxCoordinate) || !within(rec.rest, snap::kMaxCoordinate) ||
            !within(rec.last, snap::kMaxCoordinate))
          refuse("rests", "a support point is not finite or not within |x| < 32768 m");
      }
      SleepSupport& sup = sleep_support_[i];  // the arms past count are never read: not cleared
      sup.parent = kLoadNone;
      sup.count = 0;
      if ((flags & 0x80) != 0) {  // eq 124's record
        const std::uint64_t key = r.varint("support.parent");
        if (key != 0) sup.parent = other_body(key - 1, "support.parent", "load parent");
        const std::uint64_t count = r.varint("support.count");
        if (count > static_cast<std::uint64_t>(kMaxSupportPoints) + 1)
          refuse("support.count", std::to_string(count) + " support points; at most " +
                                      std::to_string(kMaxSupportPoints + 1) + " (many)");
        sup.count = static_cast<int>(count);
        for (int k = 0; k < sup.count && k < kMaxSupportPoints; ++k) {
          Vec3<T>& arm = sup.arms[static_cast<std::size_t>(k)];
          arm.x = C::get(r, "support.arms");
          arm.z = C::get(r, "support.arms");
          if (!within(arm, snap::kMaxCoordinate)) refuse("support.arms", "a lever arm is not finite or not within |x| < 32768 m");
        }
      }
      // R and the AABB are functions of q: recomputed unless q is unchanged.
      const bool same_q = derived_valid && C::same_bits(q.w, b.q.w) && C::same_bits(q.x, b.q.x) &&
                          C::same_bits(q.y, b.q.y) && C::same_bits(q.z, b.q.z);
      b.p = p;
      b.q = q;
      if (!same_q) update_derived(b);
    }
  } catch (const SnapshotError& e) {
    std::string what = e.what();
    const std::string prefix = "snapshot: ";
    if (what.compare(0, prefix.size(), prefix) == 0) what.erase(0, prefix.size());
    if (i < n) throw SnapshotError("body " + std::to_string(i) + ": " + what, "bodies[" + std::to_string(i) + "]." + e.field);
    throw;
  }
  const std::uint64_t count = r.varint("warm.count");
  if (count > r.left() / 4) refuse("warm.count", std::to_string(count) + " cached impulses cannot fit in the bytes left");
  warm_.resize(static_cast<std::size_t>(count));
  const std::int64_t sdfs = static_cast<std::int64_t>(sdf_.grids.size());
  std::int64_t a = 0;
  for (std::size_t k = 0; k < warm_.size(); ++k) {
    const std::string field = "warm[" + std::to_string(k) + "]";
    const std::int64_t step = r.svarint("warm.a");
    if (step < 0 || step >= static_cast<std::int64_t>(n))  // checked before the sum: no overflow
      refuse(field, "a steps by " + std::to_string(step) + " (bodies: " + std::to_string(n) + ")");
    a += step;
    const std::int64_t b = r.svarint("warm.b");
    const std::int64_t feature = r.svarint("warm.feature");
    const T j_n = C::get(r, "warm.j_n");
    if (a < 0 || a >= static_cast<std::int64_t>(n) || b < -1 - sdfs || b >= static_cast<std::int64_t>(n) || b == a ||
        feature < 0 || feature > 65535)
      refuse(field, "contact (" + std::to_string(a) + ", " + std::to_string(b) + ", " + std::to_string(feature) +
                        ") names no possible contact");
    if (!C::within(j_n, snap::kMaxImpulse) || !(j_n > T{})) refuse(field + ".j_n", "not a positive finite impulse below 2^31 N s");
    CachedImpulse& e = warm_[k];
    e = {static_cast<int>(a), static_cast<int>(b), static_cast<int>(feature), j_n};
    if (k > 0) {
      const CachedImpulse& p = warm_[k - 1];
      if (!(p.a != e.a ? p.a < e.a : (p.b != e.b ? p.b < e.b : p.feature < e.feature)))
        refuse(field, "the cache is not in strictly ascending (a, b, feature) order");
    }
  }
  read_ids_and_forces(r);
  snap::each_counter(counters_, [&r](std::uint64_t& x) { x = r.varint("counters"); });
  if (r.left() != 0) refuse("end", std::to_string(r.left()) + " bytes after the counters");
  contacts_.clear();  // the last step's contacts are not state (stage 3 rebuilds them)
}

// The id table and the pending forces (docs/SNAPSHOTS.md "Then").
template <class T>
void World<T>::read_ids_and_forces(snap::Reader& r) {
  using C = snap::NumCodec<T>;
  using snap::refuse;
  const std::size_t n = bodies_.size();
  const std::uint64_t slots = r.varint("ids.slots");
  if (slots == 0) {
    ids_.reset(n);
  } else {
    if (slots < n || slots > r.left())
      refuse("ids.slots", std::to_string(slots) + " slots for " + std::to_string(n) +
                              " bodies (at least one slot per body, one byte per slot)");
    std::vector<std::uint32_t> generations(static_cast<std::size_t>(slots)), slot_of_body(n);
    for (std::size_t s = 0; s < generations.size(); ++s) {
      const std::uint64_t g = r.varint("ids.generation");
      if (g > UINT32_MAX) refuse("ids.generation[" + std::to_string(s) + "]", std::to_string(g) + " is beyond 2^32 - 1");
      generations[s] = static_cast<std::uint32_t>(g);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t slot = r.varint("ids.slot");
      if (slot >= slots) refuse("ids.slot[" + std::to_string(i) + "]", "slot " + std::to_string(slot) + " is past the " + std::to_string(slots) + " slots");
      slot_of_body[i] = static_cast<std::uint32_t>(slot);
    }
    const std::string wrong = ids_.assign(std::move(generations), std::move(slot_of_body));
    if (!wrong.empty()) refuse("ids", wrong);
  }
  const std::uint64_t count = r.varint("forces.count");
  if (count > n || count > r.left()) refuse("forces.count", std::to_string(count) + " pending forces for " + std::to_string(n) + " bodies");
  forces_.resize(static_cast<std::size_t>(count));
  std::uint64_t body = 0;
  auto get_vec = [&r](const char* field) {
    Vec3<T> x;
    x.x = C::get(r, field);
    x.y = C::get(r, field);
    x.z = C::get(r, field);
    return x;
  };
  auto within = [](const Vec3<T>& x) {
    return C::within(x.x, snap::kMaxImpulse) && C::within(x.y, snap::kMaxImpulse) && C::within(x.z, snap::kMaxImpulse);
  };
  for (std::size_t k = 0; k < forces_.size(); ++k) {
    const std::string field = "forces[" + std::to_string(k) + "]";
    const std::uint64_t step = r.varint("forces.body");
    if (step >= n || (k > 0 && step == 0)) refuse(field, "body steps by " + std::to_string(step) + " (bodies: " + std::to_string(n) + ", ascending)");
    body += step;
    if (body >= n || !bodies_[static_cast<std::size_t>(body)].awake())
      refuse(field, "body " + std::to_string(body) + " is not an awake dynamic body of the " + std::to_string(n));
    PendingForce& f = forces_[k];
    f.body = static_cast<int>(body);
    f.f = get_vec("forces.f");
    f.tau = get_vec("forces.tau");
    if (!within(f.f) || !within(f.tau)) refuse(field, "a component is not finite or not within |x| < 2^31");
  }
}

template <class T>
World<T> World<T>::load_state(const std::uint8_t* data, std::size_t size) {
  using C = snap::NumCodec<T>;
  const SnapshotInfo info = read_snapshot_info(data, size);
  if (info.number != C::kNumber)
    throw SnapshotError(std::string("a snapshot of the ") + snapshot_number_name(info.number) + " engine cannot be loaded into the " +
                            Num<T>::kName + " engine",
                        "header.number_type");
  snap::Reader r(data + kSnapshotHeaderSize, size - kSnapshotHeaderSize - kSnapshotChecksumSize);
  Scene scene = snap::read_checked_scene(r, info, Num<T>::kName, "this engine");
  World w = [&] {
    try {
      return World(scene);
    } catch (const RunError& e) {
      throw SnapshotError(std::string("the scene section cannot be built: ") + e.what(), "scene");
    }
  }();
  w.read_moving_state(r, info.frame, false);
  auto d = [](const T& x) { return Num<T>::to_double(x); };
  for (std::size_t i = 0; i < w.bodies_.size(); ++i) {
    const Body<T>& b = w.bodies_[i];
    BodyDesc& desc = w.scene_.bodies[i];
    desc.position = {d(b.p.x), d(b.p.y), d(b.p.z)};
    desc.orientation = {d(b.q.w), d(b.q.x), d(b.q.y), d(b.q.z)};
    desc.velocity = {d(b.v.x), d(b.v.y), d(b.v.z)};
    desc.angular_velocity = {d(b.w.x), d(b.w.y), d(b.w.z)};
    desc.asleep = b.asleep;
  }
  return w;
}

template <class T>
void World<T>::restore_state(const std::uint8_t* data, std::size_t size) {
  using C = snap::NumCodec<T>;
  const SnapshotInfo info = read_snapshot_info(data, size);
  if (info.number != C::kNumber)
    throw SnapshotError(std::string("a snapshot of the ") + snapshot_number_name(info.number) + " engine cannot be loaded into the " +
                            Num<T>::kName + " engine",
                        "header.number_type");
  const std::size_t moving_at = kSnapshotHeaderSize + scene_section_.size();
  if (info.body_count == bodies_.size() && info.constants_hash == constants_hash_ &&
      size >= moving_at + kSnapshotChecksumSize &&
      std::memcmp(data + kSnapshotHeaderSize, scene_section_.data(), scene_section_.size()) == 0) {
    snap::Reader r(data + moving_at, size - moving_at - kSnapshotChecksumSize);
    read_moving_state(r, info.frame, true);
    return;
  }
  const int threads = workers_.threads;  // the world's threads are not state: kept
  *this = load_state(data, size);
  set_threads(threads);
}

template <class T>
World<T> World<T>::load_state(const std::vector<std::uint8_t>& bytes) {
  return load_state(bytes.data(), bytes.size());
}

template <class T>
void World<T>::restore_state(const std::vector<std::uint8_t>& bytes) {
  restore_state(bytes.data(), bytes.size());
}

}  // namespace lockstep
