// Exact reference arithmetic for the Q16.16 tests: every expected result is
// computed here with unbounded integers (boost cpp_int) or exact rationals
// (cpp_rational), never with the int64 tricks of the implementation under
// test, then rounded and clamped by the rule written in fixed/README.md.
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <boost/multiprecision/cpp_int.hpp>

#include "lockstep/fixed/q16.hpp"
#include "lockstep/fixed/q16_vec.hpp"

namespace lockstep_test {

using Int = boost::multiprecision::cpp_int;
using Rat = boost::multiprecision::cpp_rational;

inline constexpr std::int32_t kMin32 = std::numeric_limits<std::int32_t>::min();
inline constexpr std::int32_t kMax32 = std::numeric_limits<std::int32_t>::max();

// An expected Q16 result: the raw value and the exact set of status flags.
struct Expect {
  std::int32_t raw = 0;
  std::uint32_t flags = 0;
};

// 2^k as an Int.
inline Int pow2(unsigned k) { return Int(1) << k; }

// The rule's clamp: v if it fits int32, else the nearer bound with kQ16Overflow.
inline Expect clamp(const Int& v) {
  if (v > kMax32) return {kMax32, lockstep::kQ16Overflow};
  if (v < kMin32) return {kMin32, lockstep::kQ16Overflow};
  return {static_cast<std::int32_t>(v), 0};
}

// floor(n / d) for d != 0 (cpp_int '/' truncates toward zero, like C++).
inline Int floor_div(const Int& n, const Int& d) {
  Int q = n / d;
  const Int r = n - q * d;
  if (r != 0 && ((r < 0) != (d < 0))) --q;
  return q;
}
// floor(r) of an exact rational.
inline Int floor_rat(const Rat& r) {
  return floor_div(boost::multiprecision::numerator(r), boost::multiprecision::denominator(r));
}
// round(n / d) to nearest, ties away from zero (libfixmath's rule), d != 0.
inline Int round_half_away(const Int& n, const Int& d) {
  const Int an = abs(n), ad = abs(d);
  Int q = (2 * an + ad) / (2 * ad);
  return ((n < 0) != (d < 0)) ? Int(-q) : q;
}
// floor(sqrt(n)) for n >= 0, exact.
inline Int isqrt(const Int& n) { return boost::multiprecision::sqrt(n); }

// Sign of a*sqrt(S) - t, exactly, for S >= 0.
inline int cmp_sqrt(const Rat& a, const Int& s, const Rat& t) {
  const int sx = (s == 0) ? 0 : (a > 0 ? 1 : (a < 0 ? -1 : 0));
  const int st = t > 0 ? 1 : (t < 0 ? -1 : 0);
  if (sx != st) return sx > st ? 1 : -1;
  if (sx == 0) return 0;
  const Rat lhs = a * a * Rat(s), rhs = t * t;
  const int mag = lhs > rhs ? 1 : (lhs < rhs ? -1 : 0);
  return sx > 0 ? mag : -mag;
}
// |n - t/sqrt(S)| < bound, exactly (S > 0): n - bound < t/sqrt(S) < n + bound,
// i.e. (n - bound)*sqrt(S) < t and (n + bound)*sqrt(S) > t.
inline bool within_over_sqrt(const Int& n, const Rat& bound, const Int& t, const Int& s) {
  return cmp_sqrt(Rat(n) - bound, s, Rat(t)) < 0 && cmp_sqrt(Rat(n) + bound, s, Rat(t)) > 0;
}
// The error n - t/sqrt(S) as a long double, for measuring (not for asserting).
inline long double err_over_sqrt(const Int& n, const Int& t, const Int& s) {
  // t/sqrt(S) = sign(t) * sqrt(t^2 * 2^80 / S) / 2^40, computed with an exact
  // integer square root: error < 2^-40 ulp.
  const Int num = t * t * pow2(80);
  const Int root = isqrt(num / s);
  long double v = static_cast<long double>(root) / static_cast<long double>(1ull << 40);
  if (t < 0) v = -v;
  return static_cast<long double>(n) - v;
}
inline long double to_ld(const Rat& r) {
  // Exact enough for reporting: numerator and denominator fit long double
  // after a shared scaling, since only differences of a few ulps are printed.
  const Int scaled = floor_rat(r * Rat(pow2(40)));
  return static_cast<long double>(scaled) / static_cast<long double>(1ull << 40);
}

// A finite double as an exact rational: m * 2^e with m an integer.
inline Rat exact_double(double x) {
  int e = 0;
  const double f = std::frexp(x, &e);                 // x = f * 2^e, 0.5 <= |f| < 1
  const auto m = static_cast<std::int64_t>(std::ldexp(f, 53));  // exact: 53 bits
  e -= 53;
  if (e >= 0) return Rat(Int(m) << e);
  return Rat(Int(m), pow2(static_cast<unsigned>(-e)));
}
// round(r) to nearest, ties to even.
inline Int round_half_even(const Rat& r) {
  const Int fl = floor_rat(r);
  const Rat frac = r - Rat(fl);
  const Rat half(1, 2);
  if (frac > half) return fl + 1;
  if (frac < half) return fl;
  return (fl % 2 == 0) ? fl : Int(fl + 1);
}

// round(n / d) to nearest, ties to even (the Q16 rule, Fix 11), d != 0.
inline Int round_div_even(const Int& n, const Int& d) {
  const Rat r = d < 0 ? Rat(Int(-n), Int(-d)) : Rat(n, d);
  return round_half_even(r);
}
// round(sqrt(n)) to nearest for n >= 0: r = floor(sqrt(n)) or r + 1,
// whichever is nearer: r + 1 when sqrt(n) > r + 1/2, i.e. 4n > (2r + 1)^2
// (never equal: the left side is even, the right odd).
inline Int isqrt_round(const Int& n) {
  const Int r = isqrt(n);
  return 4 * n > (2 * r + 1) * (2 * r + 1) ? Int(r + 1) : r;
}

// ---- The scalar rules (fixed/README.md) ------------------------------------

inline Expect ref_from_int(std::int64_t i) { return clamp(Int(i) * 65536); }
inline Expect ref_from_double(double x) {
  if (std::isnan(x)) return {0, lockstep::kQ16Invalid};
  if (std::isinf(x)) return x > 0 ? Expect{kMax32, lockstep::kQ16Overflow} : Expect{kMin32, lockstep::kQ16Overflow};
  return clamp(round_half_even(exact_double(x) * 65536));
}
inline Expect ref_add(std::int32_t a, std::int32_t b) { return clamp(Int(a) + Int(b)); }
inline Expect ref_sub(std::int32_t a, std::int32_t b) { return clamp(Int(a) - Int(b)); }
inline Expect ref_neg(std::int32_t a) { return clamp(-Int(a)); }
inline Expect ref_abs(std::int32_t a) { return clamp(abs(Int(a))); }
inline Expect ref_mul(std::int32_t a, std::int32_t b) { return clamp(round_div_even(Int(a) * Int(b), 65536)); }
inline Expect ref_div(std::int32_t a, std::int32_t b) {
  if (b == 0) return {a >= 0 ? kMax32 : kMin32, lockstep::kQ16DivByZero};
  return clamp(round_div_even(Int(a) * 65536, Int(b)));
}
inline Expect ref_sqrt(std::int32_t a) {
  if (a < 0) return {0, lockstep::kQ16SqrtNegative};
  return clamp(isqrt_round(Int(a) * 65536));
}
inline Expect ref_reciprocal(std::int32_t a) { return ref_div(65536, a); }
inline std::int32_t ref_floor_to_int(std::int32_t a) {
  return static_cast<std::int32_t>(floor_div(Int(a), 65536));
}

// ---- The vector rules: exact sums of raw products, rounded once ----------------

struct Expect3 {
  Expect c[3];
  std::uint32_t flags() const { return c[0].flags | c[1].flags | c[2].flags; }
};
struct Expect4 {
  Expect c[4];
  std::uint32_t flags() const { return c[0].flags | c[1].flags | c[2].flags | c[3].flags; }
};
struct Expect9 {
  Expect m[3][3];
  std::uint32_t flags() const {
    std::uint32_t f = 0;
    for (const auto& row : m)
      for (const Expect& e : row) f |= e.flags;
    return f;
  }
};

inline Int I(lockstep::Q16 q) { return Int(q.raw()); }
// round(sum / 2^16), to nearest, ties to even, clamped: the accumulator rule.
inline Expect acc(const Int& sum_of_products) { return clamp(round_div_even(sum_of_products, 65536)); }

inline Expect ref_dot(const lockstep::Vec3<lockstep::Q16>& a, const lockstep::Vec3<lockstep::Q16>& b) {
  return acc(I(a.x) * I(b.x) + I(a.y) * I(b.y) + I(a.z) * I(b.z));
}
inline Expect3 ref_cross(const lockstep::Vec3<lockstep::Q16>& a, const lockstep::Vec3<lockstep::Q16>& b) {
  return {{acc(I(a.y) * I(b.z) - I(a.z) * I(b.y)), acc(I(a.z) * I(b.x) - I(a.x) * I(b.z)),
           acc(I(a.x) * I(b.y) - I(a.y) * I(b.x))}};
}
inline Int raw_sum_sq(const lockstep::Vec3<lockstep::Q16>& a) { return I(a.x) * I(a.x) + I(a.y) * I(a.y) + I(a.z) * I(a.z); }
inline Expect ref_length_sq(const lockstep::Vec3<lockstep::Q16>& a) { return acc(raw_sum_sq(a)); }
// |a| in raw units is sqrt(sum R_i^2): rounded once.
inline Expect ref_length(const lockstep::Vec3<lockstep::Q16>& a) { return clamp(isqrt_round(raw_sum_sq(a))); }
// The normalise rule: L = round(sqrt(sum R_i^2)), n_i = round(R_i * 2^16 / L).
inline Expect3 ref_normalize(const lockstep::Vec3<lockstep::Q16>& a) {
  const Int l = isqrt_round(raw_sum_sq(a));
  if (l == 0) return {{{0, lockstep::kQ16NormalizeZero}, {0, 0}, {0, 0}}};
  return {{clamp(round_div_even(I(a.x) * 65536, l)), clamp(round_div_even(I(a.y) * 65536, l)),
           clamp(round_div_even(I(a.z) * 65536, l))}};
}

inline Expect4 ref_quat_mul(const lockstep::Quat<lockstep::Q16>& a, const lockstep::Quat<lockstep::Q16>& b) {
  return {{acc(I(a.w) * I(b.w) - I(a.x) * I(b.x) - I(a.y) * I(b.y) - I(a.z) * I(b.z)),
           acc(I(a.w) * I(b.x) + I(a.x) * I(b.w) + I(a.y) * I(b.z) - I(a.z) * I(b.y)),
           acc(I(a.w) * I(b.y) - I(a.x) * I(b.z) + I(a.y) * I(b.w) + I(a.z) * I(b.x)),
           acc(I(a.w) * I(b.z) + I(a.x) * I(b.y) - I(a.y) * I(b.x) + I(a.z) * I(b.w))}};
}
inline Int raw_sum_sq(const lockstep::Quat<lockstep::Q16>& q) {
  return I(q.w) * I(q.w) + I(q.x) * I(q.x) + I(q.y) * I(q.y) + I(q.z) * I(q.z);
}
inline Expect ref_quat_length_sq(const lockstep::Quat<lockstep::Q16>& q) { return acc(raw_sum_sq(q)); }
// The quaternion normalise rule: INT32_MIN components are first lifted to
// -INT32_MAX, then as for vectors; the zero quaternion gives the identity.
inline Expect4 ref_normalize(const lockstep::Quat<lockstep::Q16>& q) {
  auto lift = [](lockstep::Q16 v) { return v.raw() == kMin32 ? Int(-kMax32) : Int(v.raw()); };
  const Int c[4] = {lift(q.w), lift(q.x), lift(q.y), lift(q.z)};
  const Int l = isqrt_round(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (l == 0) return {{{65536, lockstep::kQ16NormalizeZero}, {0, 0}, {0, 0}, {0, 0}}};
  Expect4 out;
  for (int i = 0; i < 4; ++i) out.c[i] = clamp(round_div_even(c[i] * 65536, l));
  return out;
}

// The rotation-matrix rule: each entry is the exact polynomial in the raw
// components at scale 2^32 (1 = 2^32), rounded once to scale 2^16.
inline Int rot_poly_scaled(const lockstep::Quat<lockstep::Q16>& q, int i, int j) {
  const Int w = I(q.w), x = I(q.x), y = I(q.y), z = I(q.z);
  const Int one = pow2(32);
  switch (i * 3 + j) {
    case 0: return one - 2 * (y * y + z * z);
    case 1: return 2 * (x * y - w * z);
    case 2: return 2 * (x * z + w * y);
    case 3: return 2 * (x * y + w * z);
    case 4: return one - 2 * (x * x + z * z);
    case 5: return 2 * (y * z - w * x);
    case 6: return 2 * (x * z - w * y);
    case 7: return 2 * (y * z + w * x);
    default: return one - 2 * (x * x + y * y);
  }
}
inline Expect9 ref_rotation_matrix(const lockstep::Quat<lockstep::Q16>& q) {
  Expect9 out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.m[i][j] = acc(rot_poly_scaled(q, i, j));
  return out;
}
// The exact rotation matrix of q/|q| (rational, no square root), in raw units
// (scale 2^16): R_ij = 2^16 * (N*delta_ij + poly_ij - delta_ij * 2^32)/N, N = sum R^2.
inline Rat true_rotation_raw(const lockstep::Quat<lockstep::Q16>& q, int i, int j) {
  const Int n = raw_sum_sq(q);
  const Int poly = rot_poly_scaled(q, i, j);                  // scale 2^32
  const Int hom = i == j ? Int(poly - pow2(32) + n) : poly;   // homogeneous form
  return Rat(hom * 65536, n);
}
inline Expect3 ref_mat_vec(const lockstep::Mat3<lockstep::Q16>& m, const lockstep::Vec3<lockstep::Q16>& v) {
  Expect3 out;
  for (int i = 0; i < 3; ++i) out.c[i] = ref_dot(m.row[i], v);
  return out;
}
inline Expect3 ref_mat_transpose_vec(const lockstep::Mat3<lockstep::Q16>& m, const lockstep::Vec3<lockstep::Q16>& v) {
  Expect3 out;
  for (int i = 0; i < 3; ++i) out.c[i] = acc(I(m.row[0][i]) * I(v.x) + I(m.row[1][i]) * I(v.y) + I(m.row[2][i]) * I(v.z));
  return out;
}
// rotate = (rotation matrix, rounded and clamped) * v, rounded and clamped.
inline Expect3 ref_rotate(const lockstep::Quat<lockstep::Q16>& q, const lockstep::Vec3<lockstep::Q16>& v) {
  const Expect9 m9 = ref_rotation_matrix(q);
  lockstep::Mat3<lockstep::Q16> m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.row[i][j] = lockstep::Q16::from_raw(m9.m[i][j].raw);
  Expect3 out = ref_mat_vec(m, v);
  out.c[0].flags |= m9.flags();
  return out;
}

}  // namespace lockstep_test
