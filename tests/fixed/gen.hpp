// RapidCheck generators for Q16.16 raw values: a mix of (a) uniform over all of
// int32, (b) values at and near the edges, (c) log-uniform magnitudes (so that
// products and quotients land inside the range, not only at the clamp), and,
// per operation, (d) inputs engineered to sit on the rounding boundaries.
//
// Every generator is resized to rc::kNominalSize, so that the distribution does
// not depend on RapidCheck's growing size parameter.
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <utility>

#include <rapidcheck.h>

#include "exact.hpp"

namespace lockstep_test::gen {

// Uniform integer in [lo, hi] (inclusive).
inline rc::Gen<std::int64_t> uniform(std::int64_t lo, std::int64_t hi) {
  if (lo == std::numeric_limits<std::int64_t>::min() && hi == std::numeric_limits<std::int64_t>::max()) {
    // All 64 bits, uniform (arbitrary<> draws size * 64 / kNominalSize bits).
    return rc::gen::map(rc::gen::resize(rc::kNominalSize, rc::gen::arbitrary<std::uint64_t>()),
                        [](std::uint64_t v) { return static_cast<std::int64_t>(v); });
  }
  if (hi == std::numeric_limits<std::int64_t>::max()) {
    // inRange is half open: take [lo - 1, hi) and shift by one.
    return rc::gen::map(rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int64_t>(lo - 1, hi)),
                        [](std::int64_t v) { return v + 1; });
  }
  return rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::int64_t>(lo, hi + 1));
}
inline std::int32_t sat32(std::int64_t v) {
  return static_cast<std::int32_t>(v > kMax32 ? kMax32 : (v < kMin32 ? kMin32 : v));
}
inline std::int32_t wrap32(std::uint64_t v) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(v)); }

// (a) uniform over all of int32.
inline rc::Gen<std::int32_t> uniform_raw() {
  return rc::gen::map(uniform(kMin32, kMax32), [](std::int64_t v) { return static_cast<std::int32_t>(v); });
}

inline constexpr std::array<std::int64_t, 16> kEdges = {
    kMin32, std::int64_t{kMin32} + 1, -65536, -32768, -1, 0, 1, 32768, 65536, kMax32 - 1, kMax32,
    -46341, 46341, -(std::int64_t{1} << 24), std::int64_t{1} << 24, -(std::int64_t{1} << 16) * 32767};

// (b) an edge value plus a small offset, saturated to int32.
inline rc::Gen<std::int32_t> edge_raw() {
  return rc::gen::map(rc::gen::pair(rc::gen::elementOf(kEdges), uniform(-4, 4)),
                      [](const std::pair<std::int64_t, std::int64_t>& p) { return sat32(p.first + p.second); });
}

// (c) log-uniform magnitude: |v| < 2^k, k uniform in [0, 31], random sign.
inline rc::Gen<std::int32_t> scaled_raw() {
  return rc::gen::map(rc::gen::pair(uniform(0, 31), uniform(kMin32, kMax32)),
                      [](const std::pair<std::int64_t, std::int64_t>& p) {
                        const std::int64_t m = (std::int64_t{1} << p.first) - 1;  // |v| <= 2^k - 1
                        const std::int64_t v = p.second;
                        return static_cast<std::int32_t>(v < 0 ? -((-v) & m) : (v & m));
                      });
}

// The mix used for every plain operand.
inline rc::Gen<std::int32_t> raw() {
  return rc::gen::weightedOneOf<std::int32_t>({{4, uniform_raw()}, {4, scaled_raw()}, {2, edge_raw()}});
}
inline rc::Gen<std::int32_t> nonzero_raw() {
  return rc::gen::map(raw(), [](std::int32_t v) { return v == 0 ? 1 : v; });
}

// Inverse of an odd number modulo 2^32 (Newton: each step doubles the bits).
inline std::uint32_t inverse_odd(std::uint32_t o) {
  std::uint32_t x = o;  // correct to 3 bits
  for (int i = 0; i < 4; ++i) x *= 2u - o * x;
  return x;
}

// (d) for mul: pairs whose exact product Ra*Rb has low 16 bits equal to one of
// 0x0000, 0x0001, 0x7FFF, 0x8000, 0x8001, 0xFFFF (the floor boundary, and the
// ties of round-to-nearest, which libfixmath uses).
inline rc::Gen<std::pair<std::int32_t, std::int32_t>> mul_tie_pair() {
  return rc::gen::exec([] {
    static constexpr std::array<std::uint32_t, 6> kLow = {0x0000, 0x0001, 0x7FFF, 0x8000, 0x8001, 0xFFFF};
    const std::uint32_t low = *rc::gen::elementOf(kLow);
    // a = 2^k * odd with 2^k dividing low (k <= 15 for 0x8000, any k <= 16 for 0).
    const unsigned max_k = low == 0 ? 16u : static_cast<unsigned>(std::countr_zero(low));
    const auto k = static_cast<unsigned>(*uniform(0, max_k));
    const auto a0 = static_cast<std::uint32_t>(*raw());
    const std::uint32_t a = ((a0 | 1u) << k);
    const std::uint32_t odd = (a0 | 1u);
    const unsigned bits = 16 - k;  // need odd * b == low / 2^k (mod 2^bits)
    const std::uint32_t mask = bits == 0 ? 0u : ((1u << bits) - 1u);
    const std::uint32_t target = (low >> k) & mask;
    const std::uint32_t b_low = (target * inverse_odd(odd)) & mask;
    const auto b_hi = static_cast<std::uint32_t>(*raw());
    const std::uint32_t b = (b_hi & ~mask) | b_low;
    std::pair<std::int32_t, std::int32_t> p{wrap32(a), wrap32(b)};
    if (*rc::gen::arbitrary<bool>()) std::swap(p.first, p.second);
    return p;
  });
}
inline rc::Gen<std::pair<std::int32_t, std::int32_t>> mul_pair() {
  return rc::gen::weightedOneOf<std::pair<std::int32_t, std::int32_t>>(
      {{5, rc::gen::pair(raw(), raw())}, {5, mul_tie_pair()}});
}

// a uniform in int32 with a == r (mod m), m >= 1.
inline std::int32_t pick_congruent(std::int64_t r, std::int64_t m) {
  r %= m;
  if (r < 0) r += m;
  const std::int64_t tlo = -((r - kMin32) / m);   // smallest t with r + t*m >= kMin32
  const std::int64_t thi = (kMax32 - r) / m;      // largest t with r + t*m <= kMax32
  const std::int64_t t = *uniform(tlo, thi);
  return static_cast<std::int32_t>(r + t * m);
}
// (2^16)^-1 mod m for odd m >= 1.
inline std::int64_t inverse_2_16(std::int64_t m) {
  const std::int64_t inv2 = (m + 1) / 2;
  std::int64_t x = 1 % m;
  for (int i = 0; i < 16; ++i) x = (x * inv2) % m;
  return x;
}

// (d) for div: Ra * 2^16 = q*Rb + d with d in {0, +-1, +-2, Rb/2 +-1} (the floor
// boundary and the round-to-nearest ties), and Ra = k*Rb + {-1, 0, 1}.
inline rc::Gen<std::pair<std::int32_t, std::int32_t>> div_tie_pair() {
  return rc::gen::exec([] {
    const std::int32_t b = *nonzero_raw();
    const std::int64_t m = b < 0 ? -std::int64_t{b} : std::int64_t{b};
    const std::int64_t mo = std::min<std::int64_t>(m | 1, kMax32);  // odd, fits int32
    const auto signed_mo = static_cast<std::int32_t>(b < 0 ? -mo : mo);
    const auto mode = *uniform(0, 3);
    std::int32_t a = 0;
    if (mode == 0) {
      // Exact: a * 2^16 == 0 (mod m)  <=>  a == 0 (mod m / gcd(m, 2^16)).
      const std::int64_t g = std::int64_t{1} << std::min(16, std::countr_zero(static_cast<std::uint64_t>(m)));
      a = pick_congruent(0, m / g);
    } else if (mode == 1) {
      // a * 2^16 == d (mod m), d small: needs m odd (then 2^16 is invertible).
      const std::int64_t d = *uniform(-2, 2);
      a = pick_congruent(d * inverse_2_16(mo), mo);
      return std::pair<std::int32_t, std::int32_t>{a, signed_mo};
    } else if (mode == 2) {
      // Half-way (round-to-nearest ties): a * 2^16 == m/2 + d (mod m), m odd only with d.
      const std::int64_t d = *uniform(-1, 1);
      a = pick_congruent((mo / 2 + d) % mo * inverse_2_16(mo), mo);
      return std::pair<std::int32_t, std::int32_t>{a, signed_mo};
    } else {
      // Raw multiples: a = k*b + {-1, 0, 1}.
      a = sat32(std::int64_t{pick_congruent(0, m)} + *uniform(-1, 1));
    }
    return std::pair<std::int32_t, std::int32_t>{a, b};
  });
}
inline rc::Gen<std::pair<std::int32_t, std::int32_t>> div_pair() {
  return rc::gen::weightedOneOf<std::pair<std::int32_t, std::int32_t>>(
      {{5, rc::gen::pair(raw(), raw())}, {5, div_tie_pair()}});
}

// (d) for sqrt: a*2^16 at and next to perfect squares (the floor boundary), and
// next to (s + 1/2)^2 (the round-to-nearest boundary, for libfixmath).
inline rc::Gen<std::int32_t> sqrt_raw() {
  auto near_square = rc::gen::exec([] {
    const auto mode = *uniform(0, 2);
    if (mode == 2) {  // a*2^16 next to s^2 + s + 1/4 = (s + 1/2)^2
      const std::int64_t s = *uniform(0, 11863282);
      return sat32(((s * s + s) >> 16) + *uniform(0, 1));
    }
    if (mode == 0) {  // a = t^2 + {-1, 0, 1}: a*2^16 = (256 t)^2 exactly at 0
      const std::int64_t t = *uniform(0, 46340);
      return sat32(t * t + *uniform(-1, 1));
    }
    // a = floor(s^2 / 2^16) + {0, 1}: a*2^16 just below / above s^2.
    const std::int64_t s = *uniform(0, 11863283);  // floor(sqrt(INT32_MAX * 2^16))
    return sat32(((s * s) >> 16) + *uniform(0, 1));
  });
  return rc::gen::weightedOneOf<std::int32_t>({{5, raw()}, {5, near_square}});
}

// (d) for reciprocal: divisors of 2^32 - 1 = 3*5*17*257*65537 and of
// 2^32 + 1 = 641*6700417 (2^32 / b is then an integer +-1/b), powers of two.
inline rc::Gen<std::int32_t> reciprocal_raw() {
  static constexpr std::array<std::int64_t, 14> kDiv = {
      3, 5, 15, 17, 51, 255, 257, 65537, 3 * 65537, 255 * 257, 641, 6700417, 65535, 16711935};
  auto special = rc::gen::exec([] {
    std::int64_t v = 0;
    if (*rc::gen::arbitrary<bool>()) v = kDiv[static_cast<std::size_t>(*uniform(0, kDiv.size() - 1))];
    else v = std::int64_t{1} << *uniform(0, 30);
    v += *uniform(-1, 1);
    return sat32(*rc::gen::arbitrary<bool>() ? -v : v);
  });
  return rc::gen::weightedOneOf<std::int32_t>({{6, raw()}, {4, special}});
}

// Doubles for from_double: every bit pattern (NaNs, infinities, subnormals,
// huge), values near the Q16 grid and its ties, and the named specials.
inline rc::Gen<double> any_double() {
  auto bits = rc::gen::map(uniform(std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()),
                           [](std::int64_t v) { return std::bit_cast<double>(v); });
  auto grid = rc::gen::exec([] {
    // k/2^17 for k in a range a little wider than int32 * 2: grid points (k
    // even) and exact ties (k odd), then nudged by 0..2 ulps of the double.
    const std::int64_t k = *uniform(-(std::int64_t{1} << 32) - 8, (std::int64_t{1} << 32) + 8);
    double x = std::ldexp(static_cast<double>(k), -17);
    const auto nudge = *uniform(-2, 2);
    for (std::int64_t i = 0; i < nudge; ++i) x = std::nextafter(x, INFINITY);
    for (std::int64_t i = 0; i > nudge; --i) x = std::nextafter(x, -INFINITY);
    return x;
  });
  auto real = rc::gen::exec([] {  // x = m * 2^e, 53-bit m, e giving |x| in [2^-40, 2^20]
    const std::int64_t m = *uniform(-(std::int64_t{1} << 53), std::int64_t{1} << 53);
    return std::ldexp(static_cast<double>(m), static_cast<int>(*uniform(-93, -33)));
  });
  static const std::array<double, 24> kSpecial = {
      std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::signaling_NaN(), INFINITY, -INFINITY, 0.0, -0.0,
      std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::denorm_min(),
      std::numeric_limits<double>::min(), -std::numeric_limits<double>::min(),
      std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
      32767.0, 32768.0, -32768.0, -32769.0, 2147483647.0 / 65536.0, 2147483647.5 / 65536.0,
      -2147483648.5 / 65536.0, 0.5 / 65536.0, -0.5 / 65536.0, 1.5 / 65536.0, -1.5 / 65536.0};
  auto special = rc::gen::exec([] {
    double x = kSpecial[static_cast<std::size_t>(*uniform(0, kSpecial.size() - 1))];
    const auto nudge = *uniform(-1, 1);
    if (nudge != 0 && std::isfinite(x)) x = std::nextafter(x, nudge > 0 ? INFINITY : -INFINITY);
    return x;
  });
  return rc::gen::weightedOneOf<double>({{3, bits}, {4, grid}, {2, real}, {1, special}});
}

// Integers for from_int: all of int64, near the +-32768 limits, small.
inline rc::Gen<std::int64_t> any_int() {
  auto near = rc::gen::map(rc::gen::pair(rc::gen::elementOf(std::array<std::int64_t, 4>{-32769, -32768, 32767, 32768}),
                                         uniform(-3, 3)),
                           [](const std::pair<std::int64_t, std::int64_t>& p) { return p.first + p.second; });
  return rc::gen::weightedOneOf<std::int64_t>(
      {{3, uniform(std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max())},
       {3, uniform(-40000, 40000)},
       {2, near},
       {1, rc::gen::elementOf(std::array<std::int64_t, 4>{std::numeric_limits<std::int64_t>::min(),
                                                          std::numeric_limits<std::int64_t>::max(), 0, -1})}});
}

}  // namespace lockstep_test::gen
