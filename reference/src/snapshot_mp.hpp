// The snapshot codec of Mp (docs/SNAPSHOTS.md "Numbers"): exact, as a tag
// byte (0: +0, 1: -0, 2: positive, 3: negative) and, for a non-zero value
// x = m 2^e with m in [0.5, 1), e as int32 and the 113-bit significand m 2^113
// as two little-endian uint64 (high 64 bits, then the low 49 bits shifted to
// the top of the second word).
#pragma once
#include <cmath>
#include <cstdint>

#include "lockstep/math/num_mp.hpp"
#include "snapshot_number.hpp"

namespace lockstep::snap {

template <>
struct NumCodec<Mp> {
  static constexpr SnapshotNumber kNumber = SnapshotNumber::kMp;
  static constexpr std::size_t kMaxBytes = 21;
  static void put(Cursor& c, const Mp& x) {
    const bool neg = boost::multiprecision::signbit(x);
    if (x == 0) {
      c.u8(neg ? 1 : 0);
      return;
    }
    c.u8(neg ? 3 : 2);
    int e = 0;
    const Mp m = boost::multiprecision::frexp(boost::multiprecision::abs(x), &e);  // [0.5, 1)
    const Mp top = boost::multiprecision::ldexp(m, 64);
    const Mp hi_part = boost::multiprecision::floor(top);
    const std::uint64_t hi = hi_part.convert_to<std::uint64_t>();
    const std::uint64_t lo = boost::multiprecision::ldexp(top - hi_part, 64).convert_to<std::uint64_t>();
    c.u32(static_cast<std::uint32_t>(e));
    c.u64(hi);
    c.u64(lo);
  }
  static Mp get(Reader& r, const char* field) {
    const std::uint8_t tag = r.u8(field);
    if (tag > 3) throw SnapshotError(std::string(field) + ": mp tag " + std::to_string(tag) + " is not 0-3", field);
    if (tag < 2) return tag == 1 ? -Mp(0) : Mp(0);
    const std::int32_t e = r.i32(field);
    const std::uint64_t hi = r.u64(field), lo = r.u64(field);
    if (e < -16000 || e > 16000 || (hi >> 63) == 0 || (lo & 0x7fff) != 0)
      throw SnapshotError(std::string(field) + ": not a normalised 113-bit mp value (exponent " + std::to_string(e) + ")", field);
    Mp x = boost::multiprecision::ldexp(Mp(hi) + boost::multiprecision::ldexp(Mp(lo), -64), e - 64);
    return tag == 3 ? Mp(-x) : x;
  }
  static bool within(const Mp& x, double limit) {
    return boost::multiprecision::isfinite(x) && boost::multiprecision::abs(x) < Mp(limit);
  }
  static bool is_zero_bits(const Mp& x) { return x == 0 && !boost::multiprecision::signbit(x); }
  static bool same_bits(const Mp& a, const Mp& b) {
    return a == b && boost::multiprecision::signbit(a) == boost::multiprecision::signbit(b);
  }
};

}  // namespace lockstep::snap
