// The GPU engine's snapshot body (gpu_snapshot.hpp, docs/SNAPSHOTS.md "The
// GPU engine").
#include "gpu_snapshot.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "snapshot_bytes.hpp"
#include "snapshot.hpp"
#include "lockstep/fixed/q16_num.hpp"

namespace lockstep::gpu {

namespace {

constexpr double kMaxCoordinate = 32768.0;  // positions, support points (m); velocities (m/s, rad/s)
constexpr double kMaxImpulse = 2147483648.0;

// A value's 4 bytes: a float's IEEE bits, a Q16.16's raw int32.
void f32(snap::Writer& w, float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  w.u32(u);
}
void f32(snap::Writer& w, Q16 x) { w.u32(static_cast<std::uint32_t>(x.raw())); }
template <class T>
void f4(snap::Writer& w, const T4<T>& a) { f32(w, a.x); f32(w, a.y); f32(w, a.z); f32(w, a.w); }
template <class T>
void f3(snap::Writer& w, const T4<T>& a) { f32(w, a.x); f32(w, a.y); f32(w, a.z); }

[[noreturn]] void refuse(const std::string& field, const std::string& what) { throw SnapshotError(field + ": " + what, field); }

template <class T>
class In {
 public:
  using F4 = T4<T>;
  In(const std::uint8_t* data, std::size_t size) : r(data, size) {}
  snap::Reader r;
  T f32(const char* field) {
    const std::uint32_t u = r.u32(field);
    if constexpr (Num<T>::kExact) {
      return T::from_raw(static_cast<std::int32_t>(u));
    } else {
      T x;
      std::memcpy(&x, &u, sizeof x);
      return x;
    }
  }
  // A value within |x| < limit (finite).
  T bounded(const std::string& field, double limit) {
    const T x = f32(field.c_str());
    const double d = Num<T>::to_double(x);
    if (!(std::fabs(d) < limit)) refuse(field, std::to_string(d) + " is not finite or not below " + std::to_string(limit));
    return x;
  }
  F4 f3(const std::string& field, double limit) {
    F4 a;
    a.x = bounded(field, limit); a.y = bounded(field, limit); a.z = bounded(field, limit);
    return a;
  }
  F4 f4(const std::string& field, double limit) {
    F4 a = f3(field, limit);
    a.w = bounded(field, limit);
    return a;
  }
  // A count whose items take at least `bytes_each` bytes, at most `most`.
  std::size_t count(const std::string& field, std::size_t most, std::size_t bytes_each) {
    const std::uint64_t n = r.varint(field.c_str());
    if (n > most || n * bytes_each > r.left())
      refuse(field, std::to_string(n) + " items: at most " + std::to_string(most) + ", and " + std::to_string(r.left()) +
                        " bytes are left");
    return static_cast<std::size_t>(n);
  }
  int index(const std::string& field, std::size_t n) {
    const std::uint64_t v = r.varint(field.c_str());
    if (v >= n) refuse(field, std::to_string(v) + " names no body (bodies: " + std::to_string(n) + ")");
    return static_cast<int>(v);
  }
  int small(const std::string& field, std::int64_t lo, std::int64_t hi) {
    const std::int64_t v = r.svarint(field.c_str());
    if (v < lo || v > hi) refuse(field, std::to_string(v) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
};

bool pow2(int x) { return x > 0 && (x & (x - 1)) == 0; }

}  // namespace

template <class T>
void write_gpu_state(std::vector<std::uint8_t>& out, const GpuState<T>& s, std::uint8_t options, bool oriented,
                     int imm_stride) {
  snap::Writer w(out);
  w.u8(options);
  const std::size_t n = s.pos.size();
  for (std::size_t i = 0; i < n; ++i) {
    w.u8(s.flags[i]);
    f3(w, s.pos[i]);
    f4(w, s.rot[i]);
    f3(w, s.vel[i]);
    f3(w, s.ang[i]);
    f4(w, s.aabb[i]);
    w.svarint(s.sleep_counter[i]);
    w.svarint(s.sleep_frame[i]);
    if (oriented) {
      f32(w, s.grow[i]);
      const int rests = s.rest_count[i];
      w.u8(static_cast<std::uint8_t>(rests));
      for (int k = 0; k < rests; ++k) {
        const std::size_t e = i * kMaxRests + static_cast<std::size_t>(k);
        w.varint(static_cast<std::uint64_t>(s.rest_body[e]));
        f4(w, s.rest_local[e]);
        f4(w, s.rest_point[e]);
        f4(w, s.rest_last[e]);
      }
      if (!s.sleep_parent.empty() && (s.flags[i] & kFlagAsleep) != 0) {  // eq 124's record of a sleeper
        w.varint(static_cast<std::uint64_t>(s.sleep_parent[i] + 1));  // 0: none
        const int count = s.sleep_count[i];
        w.varint(static_cast<std::uint64_t>(count));
        for (int k = 0; k < count && k < kMaxSupportPoints; ++k) {
          const T4<T>& a = s.sleep_arms[i * kMaxSupportPoints + static_cast<std::size_t>(k)];
          f32(w, a.x);
          f32(w, a.z);
        }
      }
    }
  }
  w.varint(s.awake.size());
  for (int b : s.awake) w.varint(static_cast<std::uint64_t>(b));
  w.varint(static_cast<std::uint64_t>(s.stride[0]));
  w.varint(static_cast<std::uint64_t>(s.stride[1]));
  w.varint(static_cast<std::uint64_t>(s.colours));
  w.u8(s.frozen_dirty ? 1 : 0);
  w.varint(s.slot_body.size());
  const T4<T> zero{};
  for (std::size_t k = 0; k < s.slot_body.size(); ++k) {
    w.varint(static_cast<std::uint64_t>(s.slot_body[k]));
    w.varint(static_cast<std::uint64_t>(s.ground_mask[k]));
    const auto per = static_cast<std::size_t>(imm_stride);
    std::size_t used = 0;
    for (std::size_t e = 0; e < per; ++e) used += std::memcmp(&s.imm[k * per + e], &zero, sizeof zero) != 0 ? 1 : 0;
    w.varint(used);
    for (std::size_t e = 0; e < per; ++e) {
      if (std::memcmp(&s.imm[k * per + e], &zero, sizeof zero) == 0) continue;
      w.varint(e);
      f4(w, s.imm[k * per + e]);
    }
    const int begin = s.nbr_begin[k], end = s.nbr_begin[k + 1];
    w.varint(static_cast<std::uint64_t>(end - begin));
    for (int t = begin; t < end; ++t) {
      const auto ut = static_cast<std::size_t>(t);
      w.varint(static_cast<std::uint64_t>(s.nbr[ut]));
      if (oriented) {
        w.u8(static_cast<std::uint8_t>(s.man_count[ut]));
        for (int u = 0; u < s.man_count[ut]; ++u) {
          w.svarint(s.man_feature[ut * kSnapshotManifoldPoints + static_cast<std::size_t>(u)]);
          f4(w, s.man_impulse[ut * kSnapshotManifoldPoints + static_cast<std::size_t>(u)]);
        }
      } else {
        f4(w, s.pair[ut]);
      }
    }
  }
  // The id table, as World<T>'s snapshots write it.
  w.varint(s.generations.size());
  for (std::uint32_t g : s.generations) w.varint(g);
  if (!s.generations.empty())
    for (std::uint32_t k : s.slot_of_body) w.varint(k);
  snap::each_counter(s.counters, [&w](std::uint64_t x) { w.varint(x); });
}

template <class T>
GpuState<T> read_gpu_state(const std::uint8_t* data, std::size_t size, const InitialState<T>& init, int imm_stride,
                           std::uint32_t frame, std::uint8_t& options) {
  In<T> in(data, size);
  GpuState<T> s;
  s.frame = static_cast<int>(frame);
  options = in.r.u8("gpu.options");
  if (options > kSnapshotJacobi) refuse("gpu.options", "unknown option bits " + std::to_string(options));
  const auto n = static_cast<std::size_t>(init.n);
  const bool oriented = init.oriented;
  const std::size_t min_body = 1 + 12 + 16 + 24 + 16 + 2 + (oriented ? 5 : 0);
  if (n * min_body > in.r.left()) refuse("bodies", std::to_string(n) + " bodies cannot fit in " + std::to_string(in.r.left()) + " bytes");
  s.pos.resize(n); s.rot.resize(n); s.vel.resize(n); s.ang.resize(n); s.aabb.resize(n);
  s.flags.resize(n); s.sleep_counter.resize(n); s.sleep_frame.resize(n);
  if (oriented) {
    s.grow.resize(n); s.rest_count.assign(n, 0); s.rest_body.assign(kMaxRests * n, 0);
    s.rest_local.assign(kMaxRests * n, T4<T>{}); s.rest_point.assign(kMaxRests * n, T4<T>{}); s.rest_last.assign(kMaxRests * n, T4<T>{});
    if (init.fx.sleep) {  // eq 124's records
      s.sleep_parent.assign(n, kLoadNone);
      s.sleep_count.assign(n, 0);
      s.sleep_arms.assign(static_cast<std::size_t>(kMaxSupportPoints) * n, T4<T>{});
    }
  }
  std::size_t awake_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string b = "bodies[" + std::to_string(i) + "]";
    const std::uint8_t flags = in.r.u8("bodies.flags");
    if ((flags & ~(kFlagStatic | kFlagAsleep)) != 0 || (flags & kFlagStatic) != (init.flags[i] & kFlagStatic) ||
        ((flags & kFlagStatic) && (flags & kFlagAsleep)) || ((flags & kFlagAsleep) && !init.fx.sleep))
      refuse(b + ".flags", "flags " + std::to_string(flags) + " do not fit the scene's body (static " +
                               std::to_string(init.flags[i] & kFlagStatic) + ", sleep effect " + std::to_string(init.fx.sleep) + ")");
    s.flags[i] = flags;
    awake_count += is_awake(flags) ? 1 : 0;
    s.pos[i] = in.f3(b + ".p", kMaxCoordinate);
    s.pos[i].w = init.pos[i].w;  // the inverse mass: the scene's
    s.rot[i] = in.f4(b + ".q", 2.0);
    const T4<T> q = s.rot[i];
    auto d = [](const T& x) { return Num<T>::to_double(x); };
    const double norm = d(q.x) * d(q.x) + d(q.y) * d(q.y) + d(q.z) * d(q.z) + d(q.w) * d(q.w);
    if (!(norm >= 0.25 && norm <= 4.0)) refuse(b + ".q", "not a unit quaternion (squared norm " + std::to_string(norm) + ")");
    s.vel[i] = in.f3(b + ".v", kMaxCoordinate);
    s.ang[i] = in.f3(b + ".w", kMaxCoordinate);
    s.aabb[i] = in.f4(b + ".aabb", 2 * kMaxCoordinate);
    if (s.aabb[i].x < T{} || s.aabb[i].y < T{} || s.aabb[i].z < T{} || s.aabb[i].w < T{}) refuse(b + ".aabb", "a negative half extent");
    if ((flags & kFlagStatic) && (s.vel[i].x != T{} || s.vel[i].y != T{} || s.vel[i].z != T{} || s.ang[i].x != T{} ||
                                  s.ang[i].y != T{} || s.ang[i].z != T{}))
      refuse(b, "a static body that moves");
    s.sleep_counter[i] = in.small(b + ".sleep_counter", 0, 1 << 30);
    s.sleep_frame[i] = in.small(b + ".sleep_frame", -1, static_cast<std::int64_t>(frame));
    if (oriented) {
      s.grow[i] = in.bounded(b + ".grow", kMaxCoordinate);
      if (s.grow[i] < T{}) refuse(b + ".grow", "negative");
      const int rests = in.r.u8("bodies.rests");
      if (rests > kMaxRests || ((flags & kFlagStatic) && rests > 0))
        refuse(b + ".rests", std::to_string(rests) + " records (at most " + std::to_string(kMaxRests) + ", none for a static body)");
      s.rest_count[i] = rests;
      for (int k = 0; k < rests; ++k) {
        const std::size_t e = i * kMaxRests + static_cast<std::size_t>(k);
        const std::string f = b + ".rests[" + std::to_string(k) + "]";
        s.rest_body[e] = in.index(f + ".body", n);
        if (static_cast<std::size_t>(s.rest_body[e]) == i || (init.flags[static_cast<std::size_t>(s.rest_body[e])] & kFlagStatic))
          refuse(f + ".body", "a record names the body itself or a static body");
        s.rest_local[e] = in.f4(f + ".local", kMaxCoordinate);
        s.rest_point[e] = in.f4(f + ".point", kMaxCoordinate);
        s.rest_last[e] = in.f4(f + ".last", kMaxCoordinate);
      }
      if (init.fx.sleep && (flags & kFlagAsleep) != 0) {  // eq 124's record
        const std::uint64_t parent = in.r.varint("bodies.support.parent");
        if (parent > n || parent == i + 1 || (parent > 0 && (init.flags[parent - 1] & kFlagStatic)))
          refuse(b + ".support.parent", "load parent " + std::to_string(static_cast<std::int64_t>(parent) - 1) +
                                            " is not another dynamic body of the " + std::to_string(n));
        s.sleep_parent[i] = static_cast<int>(parent) - 1;
        const std::uint64_t count = in.r.varint("bodies.support.count");
        if (count > static_cast<std::uint64_t>(kMaxSupportPoints) + 1)
          refuse(b + ".support.count", std::to_string(count) + " support points; at most " +
                                           std::to_string(kMaxSupportPoints + 1) + " (many)");
        s.sleep_count[i] = static_cast<int>(count);
        for (int k = 0; k < s.sleep_count[i] && k < kMaxSupportPoints; ++k) {
          T4<T>& a = s.sleep_arms[i * kMaxSupportPoints + static_cast<std::size_t>(k)];
          a.x = in.bounded(b + ".support.arms", kMaxCoordinate);
          a.z = in.bounded(b + ".support.arms", kMaxCoordinate);
        }
      }
    }
  }
  const std::size_t awake = in.count("awake", n, 1);
  if (awake != awake_count)
    refuse("awake", std::to_string(awake) + " bodies in the awake list, but " + std::to_string(awake_count) + " are awake");
  std::vector<char> seen(n, 0);
  s.awake.resize(awake);
  for (std::size_t k = 0; k < awake; ++k) {
    const int b = in.index("awake[" + std::to_string(k) + "]", n);
    if (seen[static_cast<std::size_t>(b)] || !is_awake(s.flags[static_cast<std::size_t>(b)]))
      refuse("awake[" + std::to_string(k) + "]", "body " + std::to_string(b) + " is listed twice or is not awake");
    seen[static_cast<std::size_t>(b)] = 1;
    s.awake[k] = b;
  }
  int most_stride = 16;
  while (static_cast<std::size_t>(most_stride) < n) most_stride *= 2;
  for (int p = 0; p < 2; ++p) {
    const std::uint64_t st = in.r.varint("stride");
    if (st > static_cast<std::uint64_t>(most_stride) || !pow2(static_cast<int>(st)) || st < 16)
      refuse("stride[" + std::to_string(p) + "]", std::to_string(st) + " is not a power of two in [16, " + std::to_string(most_stride) + "]");
    s.stride[static_cast<std::size_t>(p)] = static_cast<int>(st);
  }
  s.colours = static_cast<int>(in.count("colours", std::max<std::size_t>(64, n), 0));
  const std::uint8_t dirty = in.r.u8("frozen_dirty");
  if (dirty > 1) refuse("frozen_dirty", std::to_string(dirty) + " is not 0 or 1");
  s.frozen_dirty = dirty == 1;
  const std::size_t slots = in.count("slots", frame > 0 ? n : 0, 4);
  const int stride = s.stride[frame & 1u];
  const auto per = static_cast<std::size_t>(imm_stride);
  std::fill(seen.begin(), seen.end(), 0);
  s.slot_body.resize(slots);
  s.ground_mask.resize(slots);
  s.imm.assign(slots * per, T4<T>{});
  s.nbr_begin.assign(1, 0);
  for (std::size_t k = 0; k < slots; ++k) {
    const std::string f = "slots[" + std::to_string(k) + "]";
    const int b = in.index(f + ".body", n);
    if (seen[static_cast<std::size_t>(b)] || (init.flags[static_cast<std::size_t>(b)] & kFlagStatic))
      refuse(f + ".body", "body " + std::to_string(b) + " has two slots or is static");
    seen[static_cast<std::size_t>(b)] = 1;
    s.slot_body[k] = b;
    const std::uint64_t mask = in.r.varint("slots.ground_mask");
    if (mask > 255 || (mask != 0 && !init.ground_on)) refuse(f + ".ground_mask", std::to_string(mask) + " is not a set of ground corners");
    s.ground_mask[k] = static_cast<int>(mask);
    const std::size_t used = in.count(f + ".imm", per, 17);
    std::size_t last = 0;
    for (std::size_t u = 0; u < used; ++u) {
      const std::uint64_t e = in.r.varint("slots.imm.entry");
      if (e >= per || (u > 0 && e <= last)) refuse(f + ".imm", "entry " + std::to_string(e) + " is out of order or beyond " + std::to_string(per));
      last = static_cast<std::size_t>(e);
      s.imm[k * per + last] = in.f4(f + ".imm", kMaxImpulse);
    }
    const std::size_t count = in.count(f + ".neighbours", static_cast<std::size_t>(stride), 1);
    int previous = -1;
    for (std::size_t t = 0; t < count; ++t) {
      const int j = in.index(f + ".neighbours", n);
      if (j <= previous || j == b) refuse(f + ".neighbours", "body " + std::to_string(j) + " is out of ascending order or the body itself");
      previous = j;
      s.nbr.push_back(j);
      if (init.oriented) {
        const int points = in.r.u8("slots.manifold.count");
        if (points > kSnapshotManifoldPoints) refuse(f + ".manifold", std::to_string(points) + " points (at most 4)");
        s.man_count.push_back(points);
        for (int u = 0; u < kSnapshotManifoldPoints; ++u) {
          const bool present = u < points;
          s.man_feature.push_back(present ? in.small(f + ".manifold.feature", 0, 1 << 20) : 0);
          s.man_impulse.push_back(present ? in.f4(f + ".manifold.impulse", kMaxImpulse) : T4<T>{});
        }
      } else {
        s.pair.push_back(in.f4(f + ".pair", kMaxImpulse));
      }
    }
    s.nbr_begin.push_back(static_cast<int>(s.nbr.size()));
  }
  const std::uint64_t id_slots = in.r.varint("ids.slots");
  if (id_slots != 0) {
    if (id_slots < n || id_slots > in.r.left())
      refuse("ids.slots", std::to_string(id_slots) + " slots for " + std::to_string(n) +
                              " bodies (at least one slot per body, one byte per slot)");
    s.generations.resize(static_cast<std::size_t>(id_slots));
    for (std::uint32_t& g : s.generations) {
      const std::uint64_t v = in.r.varint("ids.generation");
      if (v > UINT32_MAX) refuse("ids.generation", std::to_string(v) + " is beyond 2^32 - 1");
      g = static_cast<std::uint32_t>(v);
    }
    std::vector<char> used(static_cast<std::size_t>(id_slots), 0);
    s.slot_of_body.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t k = in.r.varint("ids.slot");
      if (k >= id_slots || used[static_cast<std::size_t>(k)])
        refuse("ids.slot[" + std::to_string(i) + "]", "slot " + std::to_string(k) + " is past the " + std::to_string(id_slots) +
                                                        " slots or holds another body");
      used[static_cast<std::size_t>(k)] = 1;
      s.slot_of_body[i] = static_cast<std::uint32_t>(k);
    }
  }
  snap::each_counter(s.counters, [&in](std::uint64_t& x) { x = in.r.varint("counters"); });
  if (in.r.left() != 0) refuse("end", std::to_string(in.r.left()) + " bytes after the counters");
  return s;
}

template void write_gpu_state<float>(std::vector<std::uint8_t>&, const GpuState<float>&, std::uint8_t, bool, int);
template void write_gpu_state<Q16>(std::vector<std::uint8_t>&, const GpuState<Q16>&, std::uint8_t, bool, int);
template GpuState<float> read_gpu_state<float>(const std::uint8_t*, std::size_t, const InitialState<float>&, int,
                                               std::uint32_t, std::uint8_t&);
template GpuState<Q16> read_gpu_state<Q16>(const std::uint8_t*, std::size_t, const InitialState<Q16>&, int,
                                           std::uint32_t, std::uint8_t&);

}  // namespace lockstep::gpu
