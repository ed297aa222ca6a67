// Q16.16 vector, quaternion and matrix operations against exact arithmetic.
//
//  * One-rounding ops (dot, cross, length_sq, length, quaternion product,
//    quat_length_sq, rotation_matrix, Mat3*Vec3, mat_transpose_mul): the result
//    is floor(exact) then the clamp, bit for bit, with the exact flags.
//  * normalize(Vec3), normalize(Quat), rotate: bit for bit against the rule
//    written in q16_vec.hpp / fixed/README.md, and within the stated ulp bound
//    (1 ulp = 2^-16) of the exact mathematical value for inputs in the stated
//    ranges.
//  * Q16VecMeasure prints the worst errors seen over random inputs (the numbers
//    quoted in q16_vec.hpp and fixed/README.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "exact.hpp"
#include "gen.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "prop.hpp"

namespace {

using lockstep::Mat3;
using lockstep::Q16;
using lockstep::Quat;
using lockstep::Vec3;
using lockstep_test::Expect;
using lockstep_test::Expect3;
using lockstep_test::Expect4;
using lockstep_test::Expect9;
using lockstep_test::Int;
using lockstep_test::kMax32;
using lockstep_test::kMin32;
using lockstep_test::Rat;
namespace lt = lockstep_test;
namespace lg = lockstep_test::gen;

using V3 = Vec3<Q16>;
using Q4 = Quat<Q16>;
using M3 = Mat3<Q16>;

Q16 R(std::int32_t raw) { return Q16::from_raw(raw); }
V3 v3(std::int32_t x, std::int32_t y, std::int32_t z) { return {R(x), R(y), R(z)}; }
Q4 q4(std::int32_t w, std::int32_t x, std::int32_t y, std::int32_t z) { return {R(w), R(x), R(y), R(z)}; }

// Proven bounds, in ulps (see q16_vec.hpp and fixed/README.md).
// |N - 1| < 6 + 9/2^16 ulp for q = normalize(p) with |p| >= 1, or q a correctly
// rounded unit quaternion (N = |q|^2).
// |N - 1| of a unit-ish quaternion (fixed/README.md, "Derivations"): with
// |d| < u/2 and |e_i| <= 1/2, |N - 1| < u + 2u(1 + u/2) + u^2 < 3.0002 u.
const Rat kUnitishN(3 * 65536 + 9, 65536);                   // ulps
const Rat kRotDiagBound = Rat(1, 2) + 2 * kUnitishN;         // 6.5003 ulp
const Rat kRotOffBound = Rat(1, 2) + kUnitishN;              // 3.5002 ulp
const Rat kRotateUnitVBound = Rat(74, 10);                   // |v| <= 1: 1/2 + sqrt(3)/2 + 2*3.0002 < 7.4
const Rat kRotatePerL1 = Rat(1, 2) + 2 * kUnitishN;          // 1/2 + 6.5004 * ||v||_1

// ---- Generators --------------------------------------------------------------

rc::Gen<std::int32_t> comp_in(std::int64_t mag) { return rc::gen::map(lg::uniform(-mag, mag), [](std::int64_t v) { return static_cast<std::int32_t>(v); }); }

// Components of one shared random magnitude 2^e (so that all three matter).
rc::Gen<V3> vec_scaled() {
  return rc::gen::exec([] {
    const std::int64_t mag = (std::int64_t{1} << *lg::uniform(0, 31)) - 1;
    return v3(*comp_in(mag), *comp_in(mag), *comp_in(mag));
  });
}
rc::Gen<V3> vec_any() {
  return rc::gen::weightedOneOf<V3>({{4, rc::gen::exec([] { return v3(*lg::raw(), *lg::raw(), *lg::raw()); })},
                                     {4, vec_scaled()},
                                     {2, rc::gen::exec([] { return v3(*lg::edge_raw(), *lg::edge_raw(), *lg::edge_raw()); })}});
}
// One dominant component (|c| near 2^e) and two small ones: the worst case of normalise.
V3 axis_dominated(std::int64_t e) {
  const std::int64_t big = *lg::uniform(std::int64_t{1} << (e - 1), std::int64_t{1} << e);
  const std::int64_t small = std::int64_t{1} << *lg::uniform(0, e / 2 + 2);
  std::int32_t c[3] = {static_cast<std::int32_t>(*rc::gen::arbitrary<bool>() ? big : -big), *comp_in(small), *comp_in(small)};
  const auto k = static_cast<int>(*lg::uniform(0, 2));
  return v3(c[k], c[(k + 1) % 3], c[(k + 2) % 3]);
}
// |v| in [2^lo, 2^hi] units, i.e. L = floor(sqrt(sum R^2)) in [2^(lo+16), 2^(hi+16)].
rc::Gen<V3> vec_length_in(int lo, int hi) {
  auto g = rc::gen::exec([lo, hi] {
    const std::int64_t e = *lg::uniform(lo + 16, hi + 16);
    if (*lg::uniform(0, 2) == 0) return axis_dominated(e);
    const std::int64_t mag = std::int64_t{1} << e;
    return v3(*comp_in(mag), *comp_in(mag), *comp_in(mag));
  });
  return rc::gen::suchThat(g, [lo, hi](const V3& v) {
    const Int l = lt::isqrt(lt::raw_sum_sq(v));
    return l >= lt::pow2(static_cast<unsigned>(lo + 16)) && l <= lt::pow2(static_cast<unsigned>(hi + 16));
  });
}
rc::Gen<Q4> quat_any() {
  return rc::gen::weightedOneOf<Q4>(
      {{4, rc::gen::exec([] { return q4(*lg::raw(), *lg::raw(), *lg::raw(), *lg::raw()); })},
       {4, rc::gen::exec([] {
          const std::int64_t mag = (std::int64_t{1} << *lg::uniform(0, 31)) - 1;
          return q4(*comp_in(mag), *comp_in(mag), *comp_in(mag), *comp_in(mag));
        })},
       {2, rc::gen::exec([] { return q4(*lg::edge_raw(), *lg::edge_raw(), *lg::edge_raw(), *lg::edge_raw()); })}});
}
// |q| in [2^lo, 2^hi] units.
rc::Gen<Q4> quat_length_in(int lo, int hi) {
  auto g = rc::gen::exec([lo, hi] {
    const std::int64_t e = *lg::uniform(lo + 16, hi + 16);
    if (*lg::uniform(0, 2) == 0) {
      const V3 a = axis_dominated(e);
      const std::int32_t s = *comp_in(std::int64_t{1} << (e / 2 + 2));
      return q4(a.x.raw(), a.y.raw(), a.z.raw(), s);
    }
    const std::int64_t mag = std::int64_t{1} << e;
    return q4(*comp_in(mag), *comp_in(mag), *comp_in(mag), *comp_in(mag));
  });
  return rc::gen::suchThat(g, [lo, hi](const Q4& q) {
    const Int l = lt::isqrt(lt::raw_sum_sq(q));
    return l >= lt::pow2(static_cast<unsigned>(lo + 16)) && l <= lt::pow2(static_cast<unsigned>(hi + 16));
  });
}
// Unit-ish quaternions: normalize(p) for |p| in [1, 2^14], or the correct
// rounding of a unit quaternion computed in double.
rc::Gen<Q4> quat_unitish() {
  auto from_normalize = rc::gen::map(quat_length_in(0, 14), [](const Q4& p) {
    const Q4 q = lockstep::normalize(p);
    lockstep::q16_clear_status();
    return q;
  });
  auto rounded = rc::gen::exec([] {
    double c[4];
    double n = 0;
    do {
      n = 0;
      for (double& x : c) {
        x = std::ldexp(static_cast<double>(*lg::uniform(-(std::int64_t{1} << 40), std::int64_t{1} << 40)), -40);
        n += x * x;
      }
    } while (n < 1e-6);
    n = std::sqrt(n);
    const Q4 q{Q16::from_double(c[0] / n), Q16::from_double(c[1] / n), Q16::from_double(c[2] / n), Q16::from_double(c[3] / n)};
    lockstep::q16_clear_status();
    return q;
  });
  return rc::gen::weightedOneOf<Q4>({{7, from_normalize}, {3, rounded}});
}
rc::Gen<M3> mat_any() {
  return rc::gen::exec([] {
    M3 m;
    const bool scaled = *rc::gen::arbitrary<bool>();
    for (auto& row : m.row) row = scaled ? *vec_scaled() : *vec_any();
    return m;
  });
}

// ---- Assertion helpers -------------------------------------------------------

template <class F>
auto run(F&& f) {
  lockstep::q16_clear_status();
  auto r = f();
  return std::pair{r, lockstep::q16_take_status()};
}
void assert_same(const std::pair<Q16, std::uint32_t>& got, const Expect& want) {
  RC_ASSERT(got.first.raw() == want.raw);
  RC_ASSERT(got.second == want.flags);
}
void assert_same(const std::pair<V3, std::uint32_t>& got, const Expect3& want) {
  for (int i = 0; i < 3; ++i) RC_ASSERT(got.first[i].raw() == want.c[i].raw);
  RC_ASSERT(got.second == want.flags());
}
void assert_same(const std::pair<Q4, std::uint32_t>& got, const Expect4& want) {
  const Q4& q = got.first;
  const Q16 c[4] = {q.w, q.x, q.y, q.z};
  for (int i = 0; i < 4; ++i) RC_ASSERT(c[i].raw() == want.c[i].raw);
  RC_ASSERT(got.second == want.flags());
}
void assert_same(const std::pair<M3, std::uint32_t>& got, const Expect9& want) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) RC_ASSERT(got.first.row[i][j].raw() == want.m[i][j].raw);
  RC_ASSERT(got.second == want.flags());
}
Rat abs_rat(const Rat& r) { return r < 0 ? Rat(-r) : r; }
// sum |v_j| in units (||v||_1).
Rat l1_units(const V3& v) {
  return Rat(abs(lt::I(v.x)) + abs(lt::I(v.y)) + abs(lt::I(v.z)), 65536);
}

// ---- One-rounding operations: bit for bit ----------------------------------

LS_PROP(Q16VecProp, Accumulator) {
  const auto n = *lg::uniform(0, 24);
  lockstep::Q16Accumulator a;
  Int sum = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    const auto kind = *lg::uniform(0, 2);
    const std::int32_t x = *lg::raw(), y = *lg::raw();
    if (kind == 0) { a.add_product(x, y); sum += Int(x) * y; }
    else if (kind == 1) { a.sub_product(x, y); sum -= Int(x) * y; }
    else { a.add_raw(x); sum += Int(x) * 65536; }
  }
  RC_ASSERT(Int(a.round_result()) == lt::round_div_even(sum, 65536));
  assert_same(run([&] { return a.result(); }), lt::acc(sum));
}

LS_PROP(Q16VecProp, Dot) {
  const V3 a = *vec_any(), b = *vec_any();
  assert_same(run([&] { return lockstep::dot(a, b); }), lt::ref_dot(a, b));
  assert_same(run([&] { return lockstep::dot(b, a); }), lt::ref_dot(a, b));
}

LS_PROP(Q16VecProp, Cross) {
  const V3 a = *vec_any(), b = *vec_any();
  assert_same(run([&] { return lockstep::cross(a, b); }), lt::ref_cross(a, b));
}

LS_PROP(Q16VecProp, LengthSq) {
  const V3 a = *vec_any();
  assert_same(run([&] { return lockstep::length_sq(a); }), lt::ref_length_sq(a));
  RC_ASSERT(Int(lockstep::raw_length_sq(a)) == lt::raw_sum_sq(a));
}

LS_PROP(Q16VecProp, Length) {
  const V3 a = *vec_any();
  assert_same(run([&] { return lockstep::length(a); }), lt::ref_length(a));
}

LS_PROP(Q16VecProp, QuatMul) {
  const Q4 a = *quat_any(), b = *rc::gen::weightedOneOf<Q4>({{7, quat_any()}, {3, quat_unitish()}});
  assert_same(run([&] { return a * b; }), lt::ref_quat_mul(a, b));
}

LS_PROP(Q16VecProp, QuatLengthSq) {
  const Q4 q = *quat_any();
  assert_same(run([&] { return lockstep::quat_length_sq(q); }), lt::ref_quat_length_sq(q));
}

LS_PROP(Q16VecProp, MatVec) {
  const M3 m = *mat_any();
  const V3 v = *vec_any();
  assert_same(run([&] { return m * v; }), lt::ref_mat_vec(m, v));
}

LS_PROP(Q16VecProp, MatTransposeVec) {
  const M3 m = *mat_any();
  const V3 v = *vec_any();
  assert_same(run([&] { return lockstep::mat_transpose_mul(m, v); }), lt::ref_mat_transpose_vec(m, v));
}

// Every entry is floor(exact polynomial in the raw components), for any q.
LS_PROP(Q16VecProp, RotationMatrixRule) {
  const Q4 q = *rc::gen::weightedOneOf<Q4>({{5, quat_any()}, {5, quat_unitish()}});
  assert_same(run([&] { return lockstep::rotation_matrix(q); }), lt::ref_rotation_matrix(q));
}

// ---- Two-rounding operations: the rule bit for bit, then the ulp bound ------

LS_PROP(Q16VecProp, NormalizeRule) {
  const V3 a = *rc::gen::weightedOneOf<V3>({{8, vec_any()}, {2, rc::gen::just(V3{})}});
  assert_same(run([&] { return lockstep::normalize(a); }), lt::ref_normalize(a));
}

// |n_i - exact_i| < 1/2 + 2^15/L ulp (L = round(|a| * 2^16), |L - |a| 2^16| < 1/2,
// and n_i rounded once more): < 1 ulp for |a| >= 1, < 128.5 ulp for |a| >= 2^-8.
LS_PROP(Q16VecProp, NormalizeBound) {
  const V3 a = *rc::gen::weightedOneOf<V3>({{5, vec_length_in(0, 14)}, {5, vec_length_in(-8, 0)}});
  const V3 n = lockstep::normalize(a);
  const Int s = lt::raw_sum_sq(a), l = lt::isqrt_round(s);
  const Rat bound = Rat(1, 2) + Rat(32768, l);
  for (int i = 0; i < 3; ++i) {
    RC_ASSERT(lt::within_over_sqrt(Int(n[i].raw()), bound, lt::I(a[i]) * 65536, s));
    if (l >= 65536) RC_ASSERT(lt::within_over_sqrt(Int(n[i].raw()), Rat(1), lt::I(a[i]) * 65536, s));
    RC_ASSERT(n[i].raw() >= -65536);
    RC_ASSERT(n[i].raw() <= 65536);
  }
}

// direction_of (eq 57's sliding test and direction from one square root):
// the same answer, unit vector and status flags as length(a) > 0 followed by
// normalize(a), for any vector: zero, tiny (length of a few raw units), and
// huge ones whose length clamps with kQ16Overflow.
LS_PROP(Q16VecProp, DirectionOfIsLengthThenNormalize) {
  const V3 a = *rc::gen::weightedOneOf<V3>({{6, vec_any()},
                                            {2, vec_length_in(-8, 0)},
                                            {1, rc::gen::just(V3{})},
                                            {1, rc::gen::just(v3(kMin32, kMax32, kMin32))}});
  lockstep::q16_clear_status();
  V3 unit = v3(7, -7, 7);  // untouched when there is no direction
  const bool got = lockstep::direction_of(a, unit);
  const std::uint32_t got_flags = lockstep::q16_take_status();
  V3 want_unit = v3(7, -7, 7);
  const bool want = lockstep::length(a) > Q16{};
  if (want) want_unit = lockstep::normalize(a);
  const std::uint32_t want_flags = lockstep::q16_take_status();
  RC_ASSERT(got == want);
  RC_ASSERT(unit == want_unit);
  RC_ASSERT(got_flags == want_flags);
}

// longer_than (eq 95's cone test without the root): the same answer as
// length(a) > limit and as the exact round(sqrt(sum R^2)) > L, with no status
// flag, for any vector and any limit below INT32_MAX raw, limits next to the
// length (one raw unit either side) and negative limits; at INT32_MAX, where
// length(a) itself clamps with kQ16Overflow, it says true.
LS_PROP(Q16VecProp, LongerThanIsLengthAbove) {
  const V3 a = *rc::gen::weightedOneOf<V3>({{6, vec_any()},
                                            {2, vec_length_in(-8, 0)},
                                            {1, rc::gen::just(V3{})},
                                            {1, rc::gen::just(v3(kMin32, kMax32, kMin32))}});
  const Int exact = lt::isqrt_round(lt::raw_sum_sq(a));  // round(sqrt(S)), unclamped
  const std::int64_t near = std::min<std::int64_t>(static_cast<std::int64_t>(exact), kMax32 - 1);
  const auto offset = *rc::gen::inRange<std::int64_t>(-1, 2);
  const std::int32_t l = *rc::gen::weightedOneOf<std::int32_t>(
      {{4, rc::gen::inRange<std::int32_t>(kMin32, kMax32)},
       {4, rc::gen::just(static_cast<std::int32_t>(std::clamp<std::int64_t>(near + offset, kMin32, kMax32 - 1)))},
       {1, rc::gen::just(kMax32)}});
  lockstep::q16_clear_status();
  const bool got = lockstep::longer_than(a, R(l));
  RC_ASSERT(lockstep::q16_take_status() == 0u);
  if (l == kMax32) {
    RC_ASSERT(got == (exact > Int(kMax32)));
    return;
  }
  RC_ASSERT(got == (exact > Int(l)));
  RC_ASSERT(got == (lockstep::length(a) > R(l)));
  lockstep::q16_clear_status();
}

LS_PROP(Q16VecProp, QuatNormalizeRule) {
  const Q4 q = *rc::gen::weightedOneOf<Q4>({{8, quat_any()}, {2, rc::gen::just(Q4{})}});
  assert_same(run([&] { return lockstep::normalize(q); }), lt::ref_normalize(q));
}

LS_PROP(Q16VecProp, QuatNormalizeBound) {
  const Q4 q = *rc::gen::weightedOneOf<Q4>({{5, quat_length_in(0, 14)}, {5, quat_length_in(-8, 0)}});
  const Q4 n = lockstep::normalize(q);
  const Int s = lt::raw_sum_sq(q), l = lt::isqrt_round(s);
  const Rat bound = Rat(1, 2) + Rat(32768, l);
  const Q16 in[4] = {q.w, q.x, q.y, q.z}, out[4] = {n.w, n.x, n.y, n.z};
  for (int i = 0; i < 4; ++i) {
    RC_ASSERT(lt::within_over_sqrt(Int(out[i].raw()), bound, lt::I(in[i]) * 65536, s));
    if (l >= 65536) RC_ASSERT(lt::within_over_sqrt(Int(out[i].raw()), Rat(1), lt::I(in[i]) * 65536, s));
  }
}

// For a unit-ish q, each entry against the rotation matrix of q/|q|:
//   M_ij - Rhat_ij = (M_ij - P_ij) + (N - 1)(Rhat - I)_ij, with M - P in [-1/2, 1/2] ulp
// (one rounding to nearest), so |error| <= 1/2 + 2|N - 1| (diagonal), <= 1/2 + |N - 1|
// (off-diagonal).
LS_PROP(Q16VecProp, RotationMatrixUnitish) {
  const Q4 q = *quat_unitish();
  const M3 m = lockstep::rotation_matrix(q);
  const Int n = lt::raw_sum_sq(q);
  const Rat n_minus_1 = Rat(n - lt::pow2(32), lt::pow2(32));  // N - 1, unitless
  RC_ASSERT(abs_rat(n_minus_1) * 65536 < kUnitishN);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Rat rhat = lt::true_rotation_raw(q, i, j);  // raw units
      const Rat err = Rat(m.row[i][j].raw()) - rhat;    // ulps
      const Rat drift = n_minus_1 * (rhat - (i == j ? Rat(65536) : Rat(0)));
      RC_ASSERT(abs_rat(err - drift) <= Rat(1, 2));
      RC_ASSERT(abs_rat(err) < (i == j ? kRotDiagBound : kRotOffBound));
    }
  }
}

LS_PROP(Q16VecProp, RotateRule) {
  const Q4 q = *rc::gen::weightedOneOf<Q4>({{5, quat_any()}, {5, quat_unitish()}});
  const V3 v = *vec_any();
  assert_same(run([&] { return lockstep::rotate(q, v); }), lt::ref_rotate(q, v));
}

// rotate(q, v) against the exact P(q) v (P the exact polynomial matrix):
// |error| <= 1/2 + ||v||_1 / 2 ulp (the matrix entries, then the product, each
// rounded to nearest); against the exact rotation by q/|q| for unit-ish q:
// |error| < 1/2 + ||v||_1 / 2 + 2|N-1| |v| <= 1/2 + 6.5004 ||v||_1, and < 7.4 ulp for |v| <= 1.
LS_PROP(Q16VecProp, RotateUnitish) {
  const Q4 q = *quat_unitish();
  const bool unit_v = *rc::gen::arbitrary<bool>();
  const V3 v = unit_v ? *vec_length_in(-8, 0) : *vec_length_in(0, 13);
  const V3 r = lockstep::rotate(q, v);
  const Rat l1 = l1_units(v);
  for (int i = 0; i < 3; ++i) {
    Int poly = 0;
    Rat exact = 0;
    for (int j = 0; j < 3; ++j) {
      poly += lt::rot_poly_scaled(q, i, j) * lt::I(v[j]);
      exact += lt::true_rotation_raw(q, i, j) * Rat(lt::I(v[j]), 65536);
    }
    const Rat err_poly = Rat(r[i].raw()) - Rat(poly, lt::pow2(32));
    RC_ASSERT(abs_rat(err_poly) <= Rat(1, 2) + l1 / 2);
    const Rat err = abs_rat(Rat(r[i].raw()) - exact);
    RC_ASSERT(err < Rat(1, 2) + kRotatePerL1 * l1);
    if (unit_v) RC_ASSERT(err < kRotateUnitVBound);
  }
}

// ---- Explicit edge tests -----------------------------------------------------

template <class T>
std::pair<T, std::uint32_t> run_t(T v) {
  return {v, lockstep::q16_take_status()};
}

TEST(Q16VecEdge, NormalizeZero) {
  lockstep::q16_clear_status();
  const V3 z = lockstep::normalize(V3{});
  EXPECT_EQ(lockstep::q16_take_status(), lockstep::kQ16NormalizeZero);
  EXPECT_EQ(z, V3{});
  const Q4 id = lockstep::normalize(Q4{});
  EXPECT_EQ(lockstep::q16_take_status(), lockstep::kQ16NormalizeZero);
  EXPECT_EQ(id, q4(65536, 0, 0, 0));
}

TEST(Q16VecEdge, NormalizeLiterals) {
  lockstep::q16_clear_status();
  // Tiny vectors: L = round(sqrt(S)) is a small integer, the error is up to 2^15/L ulp.
  EXPECT_EQ(lockstep::normalize(v3(1, 0, 0)), v3(65536, 0, 0));
  EXPECT_EQ(lockstep::normalize(v3(-1, 0, 0)), v3(-65536, 0, 0));
  EXPECT_EQ(lockstep::normalize(v3(1, 1, 0)), v3(65536, 65536, 0));   // S = 2, L = 1
  EXPECT_EQ(lockstep::normalize(v3(-1, 1, 1)), v3(-32768, 32768, 32768));  // S = 3, L = 2
  EXPECT_EQ(lockstep::normalize(v3(0, 3, 4)), v3(0, 39322, 52429));   // 3/5, 4/5 rounded
  EXPECT_EQ(lockstep::normalize(v3(0, -3 << 16, 4 << 16)), v3(0, -39322, 52429));  // sign-symmetric
  // INT32_MIN components need no lift for vectors (3 * 2^62 < 2^64).
  EXPECT_EQ(lockstep::normalize(v3(kMin32, 0, 0)), v3(-65536, 0, 0));
  EXPECT_EQ(lockstep::normalize(v3(kMin32, kMin32, kMin32)), v3(-37837, -37837, -37837));
  EXPECT_EQ(lockstep::normalize(v3(kMax32, kMax32, kMax32)), v3(37837, 37837, 37837));
  // Quaternions: INT32_MIN is lifted to -INT32_MAX first (4 * 2^62 = 2^64).
  EXPECT_EQ(lockstep::normalize(q4(kMin32, 0, 0, 0)), q4(-65536, 0, 0, 0));
  EXPECT_EQ(lockstep::normalize(q4(kMin32, kMin32, kMin32, kMin32)), q4(-32768, -32768, -32768, -32768));
  EXPECT_EQ(lockstep::normalize(q4(kMax32, kMax32, kMax32, kMax32)), q4(32768, 32768, 32768, 32768));
  EXPECT_EQ(lockstep::normalize(q4(kMin32, kMax32, 0, 0)), q4(-46341, 46341, 0, 0));
  EXPECT_EQ(lockstep::normalize(q4(kMin32, kMin32 + 1, kMax32, 0)), q4(-37837, -37837, 37837, 0));
  EXPECT_EQ(lockstep::normalize(q4(0, 0, 0, 1)), q4(0, 0, 0, 65536));
  EXPECT_EQ(lockstep::q16_take_status(), 0u);
}

// Edge components (INT32_MIN, INT32_MAX, -1, 0, 1 raw): every op bit for bit.
TEST(Q16VecEdge, EdgeGrid) {
  const std::int32_t e[] = {kMin32, -1, 0, 1, kMax32};
  std::vector<V3> vs;
  for (auto x : e) for (auto y : e) for (auto z : e) vs.push_back(v3(x, y, z));
  const auto check3 = [](const std::pair<V3, std::uint32_t>& got, const Expect3& want) {
    for (int i = 0; i < 3; ++i) EXPECT_EQ(got.first[i].raw(), want.c[i].raw);
    EXPECT_EQ(got.second, want.flags());
  };
  const auto check1 = [](const std::pair<Q16, std::uint32_t>& got, const Expect& want) {
    EXPECT_EQ(got.first.raw(), want.raw);
    EXPECT_EQ(got.second, want.flags);
  };
  for (const V3& a : vs) {
    check1(run([&] { return lockstep::length_sq(a); }), lt::ref_length_sq(a));
    check1(run([&] { return lockstep::length(a); }), lt::ref_length(a));
    check3(run([&] { return lockstep::normalize(a); }), lt::ref_normalize(a));
    for (const V3& b : vs) {
      check1(run([&] { return lockstep::dot(a, b); }), lt::ref_dot(a, b));
      check3(run([&] { return lockstep::cross(a, b); }), lt::ref_cross(a, b));
    }
    const M3 m{{a, V3{a.z, a.x, a.y}, V3{a.y, a.z, a.x}}};
    for (const V3& b : vs) {
      check3(run([&] { return m * b; }), lt::ref_mat_vec(m, b));
      check3(run([&] { return lockstep::mat_transpose_mul(m, b); }), lt::ref_mat_transpose_vec(m, b));
    }
  }
  const std::int32_t f[] = {kMin32, -1, 0, kMax32};
  std::vector<Q4> qs;
  for (auto w : f) for (auto x : f) for (auto y : f) for (auto z : f) qs.push_back(q4(w, x, y, z));
  for (const Q4& a : qs) {
    check1(run([&] { return lockstep::quat_length_sq(a); }), lt::ref_quat_length_sq(a));
    const auto n = run([&] { return lockstep::normalize(a); });
    const Expect4 want = lt::ref_normalize(a);
    EXPECT_EQ(n.first, q4(want.c[0].raw, want.c[1].raw, want.c[2].raw, want.c[3].raw));
    EXPECT_EQ(n.second, want.flags());
    const auto m = run([&] { return lockstep::rotation_matrix(a); });
    const Expect9 wm = lt::ref_rotation_matrix(a);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_EQ(m.first.row[i][j].raw(), wm.m[i][j].raw);
    EXPECT_EQ(m.second, wm.flags());
    check3(run([&] { return lockstep::rotate(a, vs[7]); }), lt::ref_rotate(a, vs[7]));
    for (const Q4& b : qs) {
      const auto p = run([&] { return a * b; });
      const Expect4 wp = lt::ref_quat_mul(a, b);
      EXPECT_EQ(p.first, q4(wp.c[0].raw, wp.c[1].raw, wp.c[2].raw, wp.c[3].raw));
      EXPECT_EQ(p.second, wp.flags());
    }
  }
}

TEST(Q16VecEdge, OverflowLiterals) {
  using lockstep::kQ16Overflow;
  const V3 max3 = v3(kMax32, kMax32, kMax32), min3 = v3(kMin32, kMin32, kMin32);
  lockstep::q16_clear_status();
  EXPECT_EQ(lockstep::dot(max3, max3), R(kMax32));
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(lockstep::dot(min3, max3), R(kMin32));
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(lockstep::length(min3), R(kMax32));  // sqrt(3) * 2^15 units
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(lockstep::length(v3(kMin32, 0, 0)), R(kMax32));  // exactly 2^31 raw: one past the top
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(lockstep::length(v3(kMax32, 0, 0)), R(kMax32));
  EXPECT_EQ(lockstep::q16_take_status(), 0u);
  EXPECT_EQ(lockstep::length_sq(min3), R(kMax32));
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(lockstep::quat_length_sq(q4(kMin32, kMin32, kMin32, kMin32)), R(kMax32));
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(lockstep::cross(v3(kMax32, 0, 0), v3(0, kMax32, 0)), v3(0, 0, kMax32));
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  // Small values: to nearest (-2^-16 ulp rounds to 0), as for +2^-16.
  EXPECT_EQ(lockstep::dot(v3(-1, 0, 0), v3(1, 0, 0)), R(0));
  EXPECT_EQ(lockstep::cross(v3(0, 1, 0), v3(0, 0, -1)), v3(0, 0, 0));
  EXPECT_EQ(lockstep::q16_take_status(), 0u);
  // The identity and a half turn are exact.
  const M3 id = lockstep::rotation_matrix(q4(65536, 0, 0, 0));
  EXPECT_EQ(id.row[0], v3(65536, 0, 0));
  EXPECT_EQ(id.row[1], v3(0, 65536, 0));
  EXPECT_EQ(id.row[2], v3(0, 0, 65536));
  EXPECT_EQ(lockstep::rotate(q4(0, 0, 0, 65536), v3(65536, 2, -3)), v3(-65536, -2, -3));
  EXPECT_EQ(lockstep::rotate(q4(32768, 32768, 32768, 32768), v3(1, 2, 3)), v3(3, 1, 2));
  EXPECT_EQ(lockstep::q16_take_status(), 0u);
  // A huge quaternion overflows the matrix entries.
  (void)lockstep::rotation_matrix(q4(kMin32, 0, 0, 0));
  EXPECT_EQ(lockstep::q16_take_status(), 0u);  // 1 - 2*0: no overflow from w alone
  const M3 big = lockstep::rotation_matrix(q4(0, kMin32, 0, 0));
  EXPECT_EQ(lockstep::q16_take_status(), kQ16Overflow);
  EXPECT_EQ(big.row[1][1], R(kMin32));
  EXPECT_EQ(big.row[0][0], R(65536));
}

// ---- Measured worst cases (printed; the bounds above are asserted too) ------

struct Worst {
  long double v = 0;
  void see(long double e) { if (std::fabs(e) > v) v = std::fabs(e); }
};

TEST(Q16VecMeasure, WorstCases) {
  std::mt19937_64 rng(20261121);
  auto uni = [&](std::int64_t lo, std::int64_t hi) { return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng); };
  // LOCKSTEP_MEASURE_SAMPLES=N (environment) measures over more inputs.
  const char* env = std::getenv("LOCKSTEP_MEASURE_SAMPLES");
  const int samples = env != nullptr ? std::max(2, std::atoi(env)) : 40000;
  // Vectors / quaternions with |a| in [2^lo, 2^hi] units (half axis-dominated).
  auto comps = [&](int lo, int hi, int n, std::int64_t* out) {
    for (;;) {
      const std::int64_t e = uni(lo + 16, hi + 16);
      const bool axis = uni(0, 1) == 0;
      Int s = 0;
      for (int i = 0; i < n; ++i) {
        if (axis && i == 0) out[i] = (uni(0, 1) ? 1 : -1) * uni(std::int64_t{1} << (e - 1), std::int64_t{1} << e);
        else if (axis) out[i] = uni(-(std::int64_t{1} << (e / 2 + 2)), std::int64_t{1} << (e / 2 + 2));
        else out[i] = uni(-(std::int64_t{1} << e), std::int64_t{1} << e);
        s += Int(out[i]) * out[i];
      }
      const Int l = lt::isqrt(s);
      if (l >= lt::pow2(static_cast<unsigned>(lo + 16)) && l <= lt::pow2(static_cast<unsigned>(hi + 16))) return;
    }
  };
  Worst nv_big, nv_small, nv_small_ratio, nq_big, nq_small, nq_small_ratio, rot_diag, rot_off, rot_poly, rot_true_unit,
      rot_true_per_len;
  long double n1_lo = 0, n1_hi = 0;
  for (int it = 0; it < samples; ++it) {
    const bool big = (it & 1) == 0;
    std::int64_t c[4];
    comps(big ? 0 : -8, big ? 14 : 0, 3, c);
    const V3 a = v3(static_cast<std::int32_t>(c[0]), static_cast<std::int32_t>(c[1]), static_cast<std::int32_t>(c[2]));
    const V3 n = lockstep::normalize(a);
    const Int s = lt::raw_sum_sq(a), l = lt::isqrt_round(s);
    for (int i = 0; i < 3; ++i) {
      const long double e = lt::err_over_sqrt(Int(n[i].raw()), lt::I(a[i]) * 65536, s);
      (big ? nv_big : nv_small).see(e);
      if (!big) nv_small_ratio.see(e / (0.5L + 32768.0L / static_cast<long double>(l)));
    }
    comps(big ? 0 : -8, big ? 14 : 0, 4, c);
    const Q4 p = q4(static_cast<std::int32_t>(c[0]), static_cast<std::int32_t>(c[1]), static_cast<std::int32_t>(c[2]),
                    static_cast<std::int32_t>(c[3]));
    const Q4 q = lockstep::normalize(p);
    const Int sp = lt::raw_sum_sq(p), lp = lt::isqrt_round(sp);
    const Q16 in[4] = {p.w, p.x, p.y, p.z}, out[4] = {q.w, q.x, q.y, q.z};
    for (int i = 0; i < 4; ++i) {
      const long double e = lt::err_over_sqrt(Int(out[i].raw()), lt::I(in[i]) * 65536, sp);
      (big ? nq_big : nq_small).see(e);
      if (!big) nq_small_ratio.see(e / (0.5L + 32768.0L / static_cast<long double>(lp)));
    }
    if (!big) continue;
    // Rotation by the unit-ish q = normalize(p), |p| >= 1.
    const long double n1 = lt::to_ld(Rat(lt::raw_sum_sq(q) - lt::pow2(32), 65536));
    n1_lo = std::min(n1_lo, n1);
    n1_hi = std::max(n1_hi, n1);
    const M3 m = lockstep::rotation_matrix(q);
    Rat rh[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        rh[i][j] = lt::true_rotation_raw(q, i, j);
        (i == j ? rot_diag : rot_off).see(lt::to_ld(Rat(m.row[i][j].raw()) - rh[i][j]));
      }
    comps(it % 4 == 0 ? -8 : 0, it % 4 == 0 ? 0 : 13, 3, c);
    const V3 v = v3(static_cast<std::int32_t>(c[0]), static_cast<std::int32_t>(c[1]), static_cast<std::int32_t>(c[2]));
    const V3 r = lockstep::rotate(q, v);
    const long double vlen = std::sqrt(static_cast<long double>(lt::raw_sum_sq(v))) / 65536.0L;
    for (int i = 0; i < 3; ++i) {
      Rat exact = 0;
      Int poly = 0;
      for (int j = 0; j < 3; ++j) {
        exact += rh[i][j] * Rat(lt::I(v[j]), 65536);
        poly += lt::rot_poly_scaled(q, i, j) * lt::I(v[j]);
      }
      const long double e = lt::to_ld(Rat(r[i].raw()) - exact);
      if (it % 4 == 0) {
        rot_true_unit.see(e);
        rot_poly.see(lt::to_ld(Rat(r[i].raw()) - Rat(poly, lt::pow2(32))));
      } else {
        rot_true_per_len.see((std::fabs(e) - 0.5L) / vlen);
      }
    }
  }
  std::printf("worst |error| in ulps over %d samples per class:\n", samples / 2);
  std::printf("  normalize(Vec3)  |a| in [1, 2^14]      %.4Lf  (bound < 1)\n", nv_big.v);
  std::printf("  normalize(Vec3)  |a| in [2^-8, 1)      %.4Lf  (bound < 1/2 + 2^15/L; worst error/bound %.4Lf)\n",
              nv_small.v, nv_small_ratio.v);
  std::printf("  normalize(Quat)  |q| in [1, 2^14]      %.4Lf  (bound < 1)\n", nq_big.v);
  std::printf("  normalize(Quat)  |q| in [2^-8, 1)      %.4Lf  (bound < 1/2 + 2^15/L; worst error/bound %.4Lf)\n",
              nq_small.v, nq_small_ratio.v);
  std::printf("  |q|^2 - 1 of normalize(Quat), ulps    [%.4Lf, %.4Lf]  (bound |.| < 3.0002)\n", n1_lo, n1_hi);
  std::printf("  rotation_matrix diag vs R(q/|q|)       %.4Lf  (bound < 6.5003)\n", rot_diag.v);
  std::printf("  rotation_matrix off-diag vs R(q/|q|)   %.4Lf  (bound < 3.5002)\n", rot_off.v);
  std::printf("  rotate, |v| <= 1, vs exact P(q) v      %.4Lf  (bound <= 1/2 + ||v||_1 / 2 <= 1.367)\n", rot_poly.v);
  std::printf("  rotate, |v| <= 1, vs rotation q/|q|    %.4Lf  (bound < 7.4)\n", rot_true_unit.v);
  std::printf("  rotate, |v| in [1, 2^13]: (|err| - 1/2)/|v|  %.4Lf  (bound < 0.867 + 6.0004)\n", rot_true_per_len.v);
  EXPECT_LT(nv_big.v, 2);
  EXPECT_LT(nq_big.v, 2);
  EXPECT_LT(nv_small_ratio.v, 1);
  EXPECT_LT(nq_small_ratio.v, 1);
  EXPECT_LT(std::max(-n1_lo, n1_hi), 6.0002L);
  EXPECT_LT(rot_diag.v, 13.0003L);
  EXPECT_LT(rot_off.v, 7.0002L);
  EXPECT_LT(rot_poly.v, 2.733L);
  EXPECT_LT(rot_true_unit.v, 14.8L);
  EXPECT_LT(rot_true_per_len.v, 13.734L);
}

}  // namespace
