// Vector, quaternion and matrix operations on Q16.16 that accumulate exact
// products and round once (the source's "fixed ordering and integer
// accumulators"). Each output component is round(sum of exact raw products /
// 2^16), to nearest, ties to even (Fix 11), clamped to int32 with kQ16Overflow; the error of each is stated
// beside it in ulps (1 ulp = 2^-16) and tested against exact arithmetic in
// tests/fixed/q16_vec_test.cpp.
#pragma once
#include <cstdint>

#include "lockstep/fixed/q16.hpp"
#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/math/vec.hpp"

namespace lockstep {

// Exact sum of int64 products, rounded by 2^16 once at the end (to nearest,
// ties to even, as q16detail::round_shift16). Each product p
// is split as p = (p >> 16) * 2^16 + (p & 0xFFFF) (two's complement, exact), so
// neither partial sum can overflow for up to 2^15 terms.
class Q16Accumulator {
 public:
  LOCKSTEP_Q16_INLINE void add_product(std::int32_t a, std::int32_t b) { add(std::int64_t{a} * b); }
  LOCKSTEP_Q16_INLINE void sub_product(std::int32_t a, std::int32_t b) { add(-(std::int64_t{a} * b)); }
  // Adds a raw value r (scale 2^16) exactly: r * 2^16 in product scale.
  LS_HD void add_raw(std::int32_t r) { high_ += r; }
  // round(sum / 2^16), to nearest, ties to even, as an exact int64: the sum
  // is high_ 2^16 + low_ with low_ >= 0, so its floor is high_ + (low_ >> 16)
  // and the dropped bits are low_ & 0xFFFF.
  LOCKSTEP_Q16_INLINE std::int64_t round_result() const {
    const std::int64_t q = high_ + (low_ >> 16), r = low_ & 0xFFFF;
    return q + ((r + 0x7FFF + (q & 1)) >> 16);  // +1 when r > 2^15, or r = 2^15 and q is odd
  }
  LOCKSTEP_Q16_INLINE Q16 result() const { return Q16::from_raw(q16detail::saturate(round_result())); }

 private:
  LOCKSTEP_Q16_INLINE void add(std::int64_t p) {  // -(a*b) cannot overflow: |a*b| <= 2^62
    high_ += p >> 16;
    low_ += p & 0xFFFF;
  }
  std::int64_t high_ = 0;
  std::int64_t low_ = 0;
};

// The component-wise operations of lockstep/math/vec.hpp for Q16, the same
// formulas (each component one Q16 operation), forced inline: as templates
// the compiler called them out of line, and they were a third of a frame.
LOCKSTEP_Q16_INLINE Vec3<Q16> operator+(const Vec3<Q16>& a, const Vec3<Q16>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
LOCKSTEP_Q16_INLINE Vec3<Q16> operator-(const Vec3<Q16>& a, const Vec3<Q16>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
LOCKSTEP_Q16_INLINE Vec3<Q16> operator-(const Vec3<Q16>& a) { return {-a.x, -a.y, -a.z}; }
LOCKSTEP_Q16_INLINE Vec3<Q16> operator*(const Vec3<Q16>& a, const Q16& s) { return {a.x * s, a.y * s, a.z * s}; }
LOCKSTEP_Q16_INLINE Vec3<Q16> operator*(const Q16& s, const Vec3<Q16>& a) { return {a.x * s, a.y * s, a.z * s}; }
LOCKSTEP_Q16_INLINE Vec3<Q16>& operator+=(Vec3<Q16>& a, const Vec3<Q16>& b) { a = a + b; return a; }
LOCKSTEP_Q16_INLINE Vec3<Q16>& operator-=(Vec3<Q16>& a, const Vec3<Q16>& b) { a = a - b; return a; }
LOCKSTEP_Q16_INLINE Vec3<Q16> hadamard(const Vec3<Q16>& a, const Vec3<Q16>& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

namespace q16detail {
// sum3's and diff2's rare paths (the int64 sum overflows), out of line.
LOCKSTEP_Q16_COLD LS_HD inline Q16 sum3_exact(std::int32_t a0, std::int32_t b0, std::int32_t a1, std::int32_t b1,
                                              std::int32_t a2, std::int32_t b2) {
  Q16Accumulator acc;
  acc.add_product(a0, b0);
  acc.add_product(a1, b1);
  acc.add_product(a2, b2);
  return acc.result();
}
LOCKSTEP_Q16_COLD LS_HD inline Q16 diff2_exact(std::int32_t a0, std::int32_t b0, std::int32_t a1, std::int32_t b1) {
  Q16Accumulator acc;
  acc.add_product(a0, b0);
  acc.sub_product(a1, b1);
  return acc.result();
}
// round((a0 b0 + a1 b1 + a2 b2) / 2^16) of the exact sum, clamped: the int64
// sum when it does not overflow (|products| <= 2^62, so it rarely can), else
// Q16Accumulator; the same value either way.
LOCKSTEP_Q16_INLINE Q16 sum3(std::int32_t a0, std::int32_t b0, std::int32_t a1, std::int32_t b1, std::int32_t a2,
                             std::int32_t b2) {
  std::int64_t s;
  const bool o1 = add_overflow(std::int64_t{a0} * b0, std::int64_t{a1} * b1, &s);
  const bool o2 = add_overflow(s, std::int64_t{a2} * b2, &s);
  if (!(o1 || o2)) [[likely]] return Q16::from_raw(round_saturate(s));
  return sum3_exact(a0, b0, a1, b1, a2, b2);
}
// round((a0 b0 - a1 b1) / 2^16) of the exact difference, clamped, as sum3.
LOCKSTEP_Q16_INLINE Q16 diff2(std::int32_t a0, std::int32_t b0, std::int32_t a1, std::int32_t b1) {
  std::int64_t s;
  if (!sub_overflow(std::int64_t{a0} * b0, std::int64_t{a1} * b1, &s)) [[likely]]
    return Q16::from_raw(round_saturate(s));
  return diff2_exact(a0, b0, a1, b1);
}
}  // namespace q16detail

// a.b: exact sum, one rounding (to nearest, ties to even).
LOCKSTEP_Q16_INLINE Q16 dot(const Vec3<Q16>& a, const Vec3<Q16>& b) {
  return q16detail::sum3(a.x.raw(), b.x.raw(), a.y.raw(), b.y.raw(), a.z.raw(), b.z.raw());
}
// eq 51: a x b, each component an exact difference of products, one rounding.
LOCKSTEP_Q16_INLINE Vec3<Q16> cross(const Vec3<Q16>& a, const Vec3<Q16>& b) {
  return {q16detail::diff2(a.y.raw(), b.z.raw(), a.z.raw(), b.y.raw()),
          q16detail::diff2(a.z.raw(), b.x.raw(), a.x.raw(), b.z.raw()),
          q16detail::diff2(a.x.raw(), b.y.raw(), a.y.raw(), b.x.raw())};
}
// Sum of squared raw components, exact in uint64 (3 * 2^62 < 2^64).
LS_HD inline std::uint64_t raw_length_sq(const Vec3<Q16>& a) {
  auto sq = [](Q16 v) {
    const std::int64_t r = v.raw();
    return static_cast<std::uint64_t>(r * r);
  };
  return sq(a.x) + sq(a.y) + sq(a.z);
}
// |a|^2 = round(sum R_i^2 / 2^16), to nearest, ties to even, clamped.
LS_HD inline Q16 length_sq(const Vec3<Q16>& a) {
  const std::uint64_t full = raw_length_sq(a), q = full >> 16, r = full & 0xFFFF;
  const std::uint64_t s = q + ((r > 0x8000 || (r == 0x8000 && (q & 1) != 0)) ? 1 : 0);
  return Q16::from_raw(q16detail::saturate(s > 0x7FFFFFFFull ? q16detail::kMax + 1
                                                             : static_cast<std::int64_t>(s)));
}
// |a| = round(sqrt(sum R_i^2)) exactly (one rounding, to nearest), clamped.
LS_HD inline Q16 length(const Vec3<Q16>& a) {
  const std::uint64_t r = q16detail::isqrt_round(raw_length_sq(a));
  return Q16::from_raw(q16detail::saturate(static_cast<std::int64_t>(r)));
}
// length(a) > limit, the same answer, without the root (and so without
// length's status flag, which the caller raises by forming length(a) where
// this says true): length(a) is round(sqrt(S)), S = sum R_i^2 exact, clamped
// to INT32_MAX. For a limit of raw L >= 0, round(sqrt(S)) > L exactly when
// sqrt(S) >= L + 1/2 (sqrt(S) is never a half-integer), i.e. S >= L^2 + L +
// 1/4, i.e. (S an integer) S > L (L + 1), exact in uint64 (L (L + 1) < 2^62).
// Where it is false, sqrt(S) < 2^31 and length(a) raises nothing. A negative
// limit is exceeded by every length. (At L = INT32_MAX, where length(a)
// itself overflows to INT32_MAX, it says true.)
LS_HD inline bool longer_than(const Vec3<Q16>& a, const Q16& limit) {
  if (limit.raw() < 0) return true;
  const auto l = static_cast<std::uint64_t>(limit.raw());
  return raw_length_sq(a) > l * (l + 1);
}
// a / |a| with L = floor(sqrt(sum R_i^2)) and n_i = floor(R_i * 2^16 / L): two
// floors; |n_i - R_i/sqrt(sum R^2)| < 1 + 2^16/L ulp, so each component is
// within 2 ulp of the exact unit vector for |a| >= 1 (measured worst 1.97) and
// within 257 ulp for |a| >= 2^-8 (measured 252: a tiny vector's length has few
// bits). |n_i| <= 2^16, so it never clamps. A zero vector raises
// kQ16NormalizeZero and returns zero.
LS_HD inline Vec3<Q16> normalize(const Vec3<Q16>& a) {
  const std::uint64_t len = q16detail::isqrt_round(raw_length_sq(a));
  if (len == 0) {
    q16detail::raise(kQ16NormalizeZero);
    return {};
  }
  const auto l = static_cast<std::int64_t>(len);
  auto div = [l](Q16 v) {
    return Q16::from_raw(q16detail::saturate(q16detail::round_div(std::int64_t{v.raw()} * 65536, l)));
  };
  return {div(a.x), div(a.y), div(a.z)};
}

// Whether |a| > 0 (length(a) > 0), and then unit = normalize(a): the same
// values (and status flags) as the two, from one square root: length(a) is
// the clamp of round(sqrt(sum R_i^2)), which is > 0 exactly when that root
// is, and normalize divides by the same root.
LS_HD inline bool direction_of(const Vec3<Q16>& a, Vec3<Q16>& unit) {
  const std::uint64_t len = q16detail::isqrt_round(raw_length_sq(a));
  if (q16detail::saturate(static_cast<std::int64_t>(len)) <= 0) return false;
  const auto l = static_cast<std::int64_t>(len);
  auto div = [l](Q16 v) {
    return Q16::from_raw(q16detail::saturate(q16detail::round_div(std::int64_t{v.raw()} * 65536, l)));
  };
  unit = {div(a.x), div(a.y), div(a.z)};
  return true;
}
// Hamilton product: each component an exact sum of 4 products, one floor.
LS_HD inline Quat<Q16> operator*(const Quat<Q16>& a, const Quat<Q16>& b) {
  Q16Accumulator w, x, y, z;
  w.add_product(a.w.raw(), b.w.raw()); w.sub_product(a.x.raw(), b.x.raw());
  w.sub_product(a.y.raw(), b.y.raw()); w.sub_product(a.z.raw(), b.z.raw());
  x.add_product(a.w.raw(), b.x.raw()); x.add_product(a.x.raw(), b.w.raw());
  x.add_product(a.y.raw(), b.z.raw()); x.sub_product(a.z.raw(), b.y.raw());
  y.add_product(a.w.raw(), b.y.raw()); y.sub_product(a.x.raw(), b.z.raw());
  y.add_product(a.y.raw(), b.w.raw()); y.add_product(a.z.raw(), b.x.raw());
  z.add_product(a.w.raw(), b.z.raw()); z.add_product(a.x.raw(), b.y.raw());
  z.sub_product(a.y.raw(), b.x.raw()); z.add_product(a.z.raw(), b.w.raw());
  return {w.result(), x.result(), y.result(), z.result()};
}
LS_HD inline Q16 quat_length_sq(const Quat<Q16>& q) {
  Q16Accumulator acc;
  acc.add_product(q.w.raw(), q.w.raw());
  acc.add_product(q.x.raw(), q.x.raw());
  acc.add_product(q.y.raw(), q.y.raw());
  acc.add_product(q.z.raw(), q.z.raw());
  return acc.result();
}
// eq 10: q / |q|, as for vectors: L = floor(sqrt(sum R_i^2)), c_i = floor(R_i *
// 2^16 / L). Components equal to INT32_MIN are first raised to -INT32_MAX (so
// the sum of squares fits uint64; normalisation is scale-free, and no other
// input is changed). Same bound as for vectors: < 1 + 2^16/L ulp per component,
// < 2 ulp for |q| >= 1 (measured worst 1.97). The zero quaternion raises
// kQ16NormalizeZero and returns the identity.
LS_HD inline Quat<Q16> normalize(const Quat<Q16>& q) {
  auto lift = [](Q16 v) { return v.raw() == INT32_MIN ? -std::int64_t{INT32_MAX} : std::int64_t{v.raw()}; };
  const std::int64_t c[4] = {lift(q.w), lift(q.x), lift(q.y), lift(q.z)};
  std::uint64_t s = 0;
  for (std::int64_t v : c) s += static_cast<std::uint64_t>(v * v);
  const std::uint64_t len = q16detail::isqrt_round(s);
  if (len == 0) {
    q16detail::raise(kQ16NormalizeZero);
    return {Q16::from_raw(Q16::kOneRaw), Q16{}, Q16{}, Q16{}};
  }
  const auto l = static_cast<std::int64_t>(len);
  auto div = [l](std::int64_t v) {
    return Q16::from_raw(q16detail::saturate(q16detail::round_div(v * 65536, l)));
  };
  return {div(c[0]), div(c[1]), div(c[2]), div(c[3])};
}

// Rotation matrix of q: every entry is an exact polynomial in the raw
// components (e.g. 1 - 2(y^2 + z^2) = (2^32 - 2 Ry^2 - 2 Rz^2) / 2^32), floored
// once: each entry is in (-1, 0] ulp of that polynomial P(q), for every q.
// Against the rotation matrix of q/|q| (what q stands for), P(q) - R(q/|q|) =
// (N - 1)(R(q/|q|) - I) with N = |q|^2, so the error is < 1 + 2|N - 1| on the
// diagonal and < 1 + |N - 1| off it. For q = normalize(p), |p| >= 1 (or q a
// correctly rounded unit quaternion), |N - 1| < 6.0002 ulp: < 13.0003 ulp
// diagonal, < 7.0002 ulp off-diagonal (measured worst 9.70 and 5.04).
LS_HD inline Mat3<Q16> rotation_matrix(const Quat<Q16>& q) {
  const std::int32_t w = q.w.raw(), x = q.x.raw(), y = q.y.raw(), z = q.z.raw();
  auto diag = [](std::int32_t a, std::int32_t b) {  // 1 - 2(a^2 + b^2)
    Q16Accumulator acc;
    acc.add_raw(Q16::kOneRaw);
    acc.sub_product(a, a); acc.sub_product(a, a);
    acc.sub_product(b, b); acc.sub_product(b, b);
    return acc.result();
  };
  auto off = [](std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t d, bool plus) {  // 2(ab +- cd)
    Q16Accumulator acc;
    acc.add_product(a, b); acc.add_product(a, b);
    if (plus) { acc.add_product(c, d); acc.add_product(c, d); }
    else { acc.sub_product(c, d); acc.sub_product(c, d); }
    return acc.result();
  };
  return {{{diag(y, z), off(x, y, w, z, false), off(x, z, w, y, true)},
           {off(x, y, w, z, true), diag(x, z), off(y, z, w, x, false)},
           {off(x, z, w, y, false), off(y, z, w, x, true), diag(x, y)}}};
}
LOCKSTEP_Q16_INLINE Vec3<Q16> operator*(const Mat3<Q16>& m, const Vec3<Q16>& v) {
  return {dot(m.row[0], v), dot(m.row[1], v), dot(m.row[2], v)};
}
// m^T v: column sums, exact, one floor each.
LOCKSTEP_Q16_INLINE Vec3<Q16> mat_transpose_mul(const Mat3<Q16>& m, const Vec3<Q16>& v) {
  auto col = [&](int i) {
    return q16detail::sum3(m.row[0][i].raw(), v.x.raw(), m.row[1][i].raw(), v.y.raw(), m.row[2][i].raw(), v.z.raw());
  };
  return {col(0), col(1), col(2)};
}
// q v q*, through the matrix: two floors per component. Against the exact
// P(q) v: < 1 + ||v||_1 ulp (||v||_1 in units; < 2.74 ulp for |v| <= 1).
// Against the exact rotation of v by q/|q|, for q as above (|N - 1| < 6.0002
// ulp): < 1 + ||v||_1 + 2|N - 1||v| ulp, i.e. < 14.8 ulp for |v| <= 1 (measured
// worst 6.2) and growing with |v| (measured (err - 1)/|v| <= 8.4).
LS_HD inline Vec3<Q16> rotate(const Quat<Q16>& q, const Vec3<Q16>& v) { return rotation_matrix(q) * v; }

}  // namespace lockstep
