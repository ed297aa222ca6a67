// How a snapshot stores one number of the engine's type (docs/SNAPSHOTS.md
// "Numbers"): Q16.16 as its raw int32, float as its IEEE binary32 bits,
// double as its IEEE binary64 bits, little-endian. Mp's codec is in
// snapshot_mp.hpp (it needs Boost). Each codec also says whether a value is
// within a bound (finite and |x| < limit), in T, without conversion error.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/snapshot.hpp"
#include "snapshot_bytes.hpp"

namespace lockstep::snap {

template <class T>
struct NumCodec;

template <>
struct NumCodec<Q16> {
  static constexpr SnapshotNumber kNumber = SnapshotNumber::kFixed;
  static constexpr std::size_t kMaxBytes = 4;
  static void put(Cursor& c, const Q16& x) { c.u32(static_cast<std::uint32_t>(x.raw())); }
  static Q16 get(Reader& r, const char* field) { return Q16::from_raw(r.i32(field)); }
  static bool within(const Q16& x, double limit) { return std::fabs(static_cast<double>(x.raw()) / 65536.0) < limit; }
  static bool is_zero_bits(const Q16& x) { return x.raw() == 0; }
  static bool same_bits(const Q16& a, const Q16& b) { return a.raw() == b.raw(); }
};

template <class F, class U, SnapshotNumber N>
struct IeeeCodec {
  static constexpr SnapshotNumber kNumber = N;
  static constexpr std::size_t kMaxBytes = sizeof(U);
  static U bits(const F& x) {
    U u;
    std::memcpy(&u, &x, sizeof u);
    return u;
  }
  static void put(Cursor& c, const F& x) {
    if constexpr (sizeof(U) == 4) c.u32(bits(x));
    else c.u64(bits(x));
  }
  static F get(Reader& r, const char* field) {
    const U u = sizeof(U) == 4 ? static_cast<U>(r.u32(field)) : static_cast<U>(r.u64(field));
    F x;
    std::memcpy(&x, &u, sizeof x);
    return x;
  }
  static bool within(const F& x, double limit) { return std::isfinite(x) && std::fabs(static_cast<double>(x)) < limit; }
  static bool is_zero_bits(const F& x) { return bits(x) == 0; }
  static bool same_bits(const F& a, const F& b) { return bits(a) == bits(b); }
};

template <>
struct NumCodec<float> : IeeeCodec<float, std::uint32_t, SnapshotNumber::kFloat> {};
template <>
struct NumCodec<double> : IeeeCodec<double, std::uint64_t, SnapshotNumber::kDouble> {};

}  // namespace lockstep::snap
