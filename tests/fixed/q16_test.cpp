// Scalar Q16.16 operations against exact arithmetic (tests/fixed/exact.hpp).
// Every property clears the status word, runs one operation and asserts both
// the raw result (the stated rounding of the exact value, then the clamp) and
// the exact set of flags raised.
#include <cmath>
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "exact.hpp"
#include "gen.hpp"
#include "lockstep/fixed/q16.hpp"
#include "prop.hpp"

namespace {

using lockstep::Q16;
using lockstep_test::Expect;
using lockstep_test::kMax32;
using lockstep_test::kMin32;
namespace lt = lockstep_test;
namespace lg = lockstep_test::gen;

Q16 R(std::int32_t raw) { return Q16::from_raw(raw); }

// Runs f with a clear status word; returns its raw result and the flags raised.
template <class F>
Expect run(F&& f) {
  lockstep::q16_clear_status();
  const Q16 r = f();
  return {r.raw(), lockstep::q16_take_status()};
}

#define LS_EXPECT_SAME(got, want)                 \
  do {                                            \
    const Expect g_ = (got), w_ = (want);         \
    RC_ASSERT(g_.raw == w_.raw);                  \
    RC_ASSERT(g_.flags == w_.flags);              \
  } while (0)

// ---- Properties ------------------------------------------------------------

LS_PROP(Q16Prop, RawRoundTrip) {
  const std::int32_t r = *lg::raw();
  LS_EXPECT_SAME(run([&] { return R(r); }), (Expect{r, 0}));
  // to_double is exact, and from_double of it returns the same raw value.
  RC_ASSERT(lt::exact_double(R(r).to_double()) == lt::Rat(r, 65536));
  LS_EXPECT_SAME(run([&] { return Q16::from_double(R(r).to_double()); }), (Expect{r, 0}));
}

LS_PROP(Q16Prop, FromInt) {
  const std::int64_t i = *lg::any_int();
  LS_EXPECT_SAME(run([&] { return Q16::from_int(i); }), lt::ref_from_int(i));
}

LS_PROP(Q16Prop, FromDouble) {
  const double x = *lg::any_double();
  LS_EXPECT_SAME(run([&] { return Q16::from_double(x); }), lt::ref_from_double(x));
}

LS_PROP(Q16Prop, Add) {
  const std::int32_t a = *lg::raw(), b = *lg::raw();
  LS_EXPECT_SAME(run([&] { return R(a) + R(b); }), lt::ref_add(a, b));
  LS_EXPECT_SAME(run([&] { Q16 x = R(a); x += R(b); return x; }), lt::ref_add(a, b));
}

LS_PROP(Q16Prop, Sub) {
  const std::int32_t a = *lg::raw(), b = *lg::raw();
  LS_EXPECT_SAME(run([&] { return R(a) - R(b); }), lt::ref_sub(a, b));
  LS_EXPECT_SAME(run([&] { Q16 x = R(a); x -= R(b); return x; }), lt::ref_sub(a, b));
}

LS_PROP(Q16Prop, Negate) {
  const std::int32_t a = *lg::raw();
  LS_EXPECT_SAME(run([&] { return -R(a); }), lt::ref_neg(a));
}

LS_PROP(Q16Prop, Mul) {
  const auto [a, b] = *lg::mul_pair();
  LS_EXPECT_SAME(run([&] { return R(a) * R(b); }), lt::ref_mul(a, b));
  LS_EXPECT_SAME(run([&] { Q16 x = R(a); x *= R(b); return x; }), lt::ref_mul(a, b));
  LS_EXPECT_SAME(run([&] { return R(b) * R(a); }), lt::ref_mul(a, b));  // commutative
}

LS_PROP(Q16Prop, Div) {
  const auto [a, b] = *lg::div_pair();
  LS_EXPECT_SAME(run([&] { return R(a) / R(b); }), lt::ref_div(a, b));
  LS_EXPECT_SAME(run([&] { Q16 x = R(a); x /= R(b); return x; }), lt::ref_div(a, b));
}

LS_PROP(Q16Prop, DivByZero) {
  const std::int32_t a = *lg::raw();
  LS_EXPECT_SAME(run([&] { return R(a) / R(0); }),
                 (Expect{a >= 0 ? kMax32 : kMin32, lockstep::kQ16DivByZero}));
}

LS_PROP(Q16Prop, Abs) {
  const std::int32_t a = *lg::raw();
  LS_EXPECT_SAME(run([&] { return lockstep::abs(R(a)); }), lt::ref_abs(a));
}

LS_PROP(Q16Prop, MinMax) {
  const std::int32_t a = *lg::raw();
  const std::int32_t b = *rc::gen::weightedOneOf<std::int32_t>({{8, lg::raw()}, {2, rc::gen::just(a)}});
  LS_EXPECT_SAME(run([&] { return lockstep::min(R(a), R(b)); }), (Expect{std::min(a, b), 0}));
  LS_EXPECT_SAME(run([&] { return lockstep::max(R(a), R(b)); }), (Expect{std::max(a, b), 0}));
}

LS_PROP(Q16Prop, Compare) {
  const std::int32_t a = *lg::raw();
  const std::int32_t b = *rc::gen::weightedOneOf<std::int32_t>(
      {{6, lg::raw()}, {2, rc::gen::just(a)}, {2, rc::gen::just(lg::sat32(std::int64_t{a} + 1))}});
  lockstep::q16_clear_status();
  RC_ASSERT((R(a) == R(b)) == (a == b));
  RC_ASSERT((R(a) != R(b)) == (a != b));
  RC_ASSERT((R(a) < R(b)) == (a < b));
  RC_ASSERT((R(a) <= R(b)) == (a <= b));
  RC_ASSERT((R(a) > R(b)) == (a > b));
  RC_ASSERT((R(a) >= R(b)) == (a >= b));
  RC_ASSERT((R(a) <=> R(b)) == (a <=> b));
  RC_ASSERT(lockstep::q16_take_status() == 0u);
}

LS_PROP(Q16Prop, Sqrt) {
  const std::int32_t a = *lg::sqrt_raw();
  LS_EXPECT_SAME(run([&] { return lockstep::sqrt(R(a)); }), lt::ref_sqrt(a));
}

LS_PROP(Q16Prop, Reciprocal) {
  const std::int32_t a = *lg::reciprocal_raw();
  LS_EXPECT_SAME(run([&] { return lockstep::reciprocal(R(a)); }), lt::ref_reciprocal(a));
}

LS_PROP(Q16Prop, FloorToInt) {
  const std::int32_t a = *lg::raw();
  lockstep::q16_clear_status();
  RC_ASSERT(lockstep::floor_to_int(R(a)) == lt::ref_floor_to_int(a));
  RC_ASSERT(lockstep::q16_take_status() == 0u);
}

// Flags are sticky: an operation only ever ORs into the word.
LS_PROP(Q16Prop, FlagsAreSticky) {
  const auto [a, b] = *lg::mul_pair();
  const auto before = static_cast<std::uint32_t>(*lg::uniform(0, 31));
  lockstep::q16_status_word = before;
  (void)(R(a) * R(b));
  RC_ASSERT(lockstep::q16_status() == (before | lt::ref_mul(a, b).flags));
}

// The sign rule that stands for the overflow builtins where a compiler has
// none (a CUDA device): the wrapped result and whether the exact int32 sum or
// difference (exact in int64) and the exact int64 one (exact in cpp_int)
// leave the type.
LS_PROP(Q16Prop, OverflowBySignRule) {
  namespace d = lockstep::q16detail;
  const std::int32_t a = *lg::raw(), b = *lg::raw();
  std::int32_t s32 = 0;
  const std::int64_t sum = std::int64_t{a} + b, diff = std::int64_t{a} - b;
  RC_ASSERT((d::add_overflow_by_sign<std::int32_t, std::uint32_t>(a, b, &s32) == (sum != static_cast<std::int32_t>(sum))));
  RC_ASSERT(s32 == lg::wrap32(static_cast<std::uint64_t>(sum)));
  RC_ASSERT((d::sub_overflow_by_sign<std::int32_t, std::uint32_t>(a, b, &s32) == (diff != static_cast<std::int32_t>(diff))));
  RC_ASSERT(s32 == lg::wrap32(static_cast<std::uint64_t>(diff)));
  // int64: products of raw values (as sum3 and diff2 add them) and edges.
  const std::int64_t x = *rc::gen::oneOf(rc::gen::just(std::int64_t{a} * b), lg::uniform(INT64_MIN, INT64_MAX),
                                          rc::gen::element(INT64_MIN, INT64_MIN + 1, std::int64_t{-1}, std::int64_t{0},
                                                           INT64_MAX - 1, INT64_MAX));
  const std::int64_t y = *rc::gen::oneOf(rc::gen::just(std::int64_t{b} * a - 1), lg::uniform(INT64_MIN, INT64_MAX),
                                          rc::gen::element(INT64_MIN, std::int64_t{-1}, std::int64_t{0}, std::int64_t{1},
                                                           INT64_MAX));
  const lt::Int xs = lt::Int(x) + y, xd = lt::Int(x) - y, two64 = lt::pow2(64);
  const auto wrap64 = [&](lt::Int v) {  // v modulo 2^64, as int64
    v = ((v % two64) + two64) % two64;
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(v));
  };
  const auto fits64 = [](const lt::Int& v) { return v >= INT64_MIN && v <= INT64_MAX; };
  std::int64_t s64 = 0;
  RC_ASSERT((d::add_overflow_by_sign<std::int64_t, std::uint64_t>(x, y, &s64) == !fits64(xs)));
  RC_ASSERT(s64 == wrap64(xs));
  RC_ASSERT((d::sub_overflow_by_sign<std::int64_t, std::uint64_t>(x, y, &s64) == !fits64(xd)));
  RC_ASSERT(s64 == wrap64(xd));
}

// A device's rounding of an exact int64 (round_shift16_fits) against
// round_shift16_any and saturate: the same int32 wherever it says it fits,
// and it says so exactly where saturate does not clamp.
LS_PROP(Q16Prop, RoundShift16FitsAsSaturate) {
  namespace d = lockstep::q16detail;
  const std::int32_t a = *lg::raw(), b = *lg::raw();
  const std::int64_t s = *rc::gen::oneOf(
      rc::gen::just(std::int64_t{a} * b), lg::uniform(INT64_MIN, INT64_MAX),
      lg::uniform(-(std::int64_t{1} << 48), std::int64_t{1} << 48),  // around the int32 range of the result
      rc::gen::element(INT64_MIN, INT64_MIN + 1, INT64_MAX - 0x8000, INT64_MAX, std::int64_t{0x7FFF8000} * 65536 - 1,
                       std::int64_t{0x7FFF8000} * 65536, -(std::int64_t{1} << 47) - 0x8001,
                       -(std::int64_t{1} << 47) - 0x8000, std::int64_t{0x8000}, std::int64_t{0x18000}));
  const std::int64_t want = d::round_shift16_any(s);
  const bool fits = want >= INT32_MIN && want <= INT32_MAX;
  std::int32_t r = 0;
  RC_ASSERT(d::round_shift16_fits(s, &r) == fits);
  if (fits) RC_ASSERT(std::int64_t{r} == want);
  lockstep::q16_clear_status();
  RC_ASSERT(d::round_saturate(s) == d::saturate(want));
  RC_ASSERT(lockstep::q16_take_status() == (fits ? 0u : std::uint32_t{lockstep::kQ16Overflow}));
}

// ---- Explicit edge tests -----------------------------------------------------

const std::int32_t kGrid[] = {kMin32,     kMin32 + 1, -65537, -65536, -65535, -32768, -2, -1, 0, 1, 2,
                              32768,      65535,      65536,  65537,  kMax32 - 1, kMax32};

void expect_same(const Expect& got, const Expect& want, const char* op, std::int32_t a, std::int32_t b) {
  EXPECT_EQ(got.raw, want.raw) << op << "(" << a << ", " << b << ")";
  EXPECT_EQ(got.flags, want.flags) << op << "(" << a << ", " << b << ")";
}

// Every operator on every pair of edge operands (INT32_MIN, INT32_MAX, -1, 0,
// +-1.0 and their neighbours).
TEST(Q16Edge, EveryOpOnEdgeGrid) {
  for (std::int32_t a : kGrid) {
    expect_same(run([&] { return -R(a); }), lt::ref_neg(a), "neg", a, 0);
    expect_same(run([&] { return lockstep::abs(R(a)); }), lt::ref_abs(a), "abs", a, 0);
    expect_same(run([&] { return lockstep::sqrt(R(a)); }), lt::ref_sqrt(a), "sqrt", a, 0);
    expect_same(run([&] { return lockstep::reciprocal(R(a)); }), lt::ref_reciprocal(a), "reciprocal", a, 0);
    EXPECT_EQ(lockstep::floor_to_int(R(a)), lt::ref_floor_to_int(a)) << a;
    expect_same(run([&] { return Q16::from_double(R(a).to_double()); }), (Expect{a, 0}), "from_double", a, 0);
    for (std::int32_t b : kGrid) {
      expect_same(run([&] { return R(a) + R(b); }), lt::ref_add(a, b), "add", a, b);
      expect_same(run([&] { return R(a) - R(b); }), lt::ref_sub(a, b), "sub", a, b);
      expect_same(run([&] { return R(a) * R(b); }), lt::ref_mul(a, b), "mul", a, b);
      expect_same(run([&] { return R(a) / R(b); }), lt::ref_div(a, b), "div", a, b);
      expect_same(run([&] { return lockstep::min(R(a), R(b)); }), (Expect{std::min(a, b), 0}), "min", a, b);
      expect_same(run([&] { return lockstep::max(R(a), R(b)); }), (Expect{std::max(a, b), 0}), "max", a, b);
      EXPECT_EQ(R(a) < R(b), a < b);
      EXPECT_EQ(R(a) == R(b), a == b);
    }
  }
}

// The same edges with the expected values written out (independent of exact.hpp).
TEST(Q16Edge, LiteralValues) {
  using lockstep::kQ16DivByZero;
  using lockstep::kQ16Overflow;
  using lockstep::kQ16SqrtNegative;
  struct Case {
    const char* what;
    Expect got, want;
  };
  const Case cases[] = {
      // abs / negate of INT32_MIN clamp to INT32_MAX.
      {"abs(MIN)", run([] { return lockstep::abs(R(kMin32)); }), {kMax32, kQ16Overflow}},
      {"-MIN", run([] { return -R(kMin32); }), {kMax32, kQ16Overflow}},
      {"-MAX", run([] { return -R(kMax32); }), {kMin32 + 1, 0}},
      {"abs(-1)", run([] { return lockstep::abs(R(-1)); }), {1, 0}},
      // add/sub clamp.
      {"MAX+1", run([] { return R(kMax32) + R(1); }), {kMax32, kQ16Overflow}},
      {"MIN-1", run([] { return R(kMin32) - R(1); }), {kMin32, kQ16Overflow}},
      {"MIN+MIN", run([] { return R(kMin32) + R(kMin32); }), {kMin32, kQ16Overflow}},
      {"0-MIN", run([] { return R(0) - R(kMin32); }), {kMax32, kQ16Overflow}},
      {"-1-MAX", run([] { return R(-1) - R(kMax32); }), {kMin32, 0}},
      // mul: to nearest, ties to even (Fix 11); clamps.
      {"-1r*1r", run([] { return R(-1) * R(1); }), {0, 0}},  // -2^-16 ulp rounds to 0
      {"-1r*-1r", run([] { return R(-1) * R(-1); }), {0, 0}},
      {"-1r*0.5", run([] { return R(-1) * R(32768); }), {0, 0}},  // -1/2 ulp: a tie, to even
      {"1r*0.5", run([] { return R(1) * R(32768); }), {0, 0}},
      {"MIN*1", run([] { return R(kMin32) * R(65536); }), {kMin32, 0}},
      {"MIN*-1", run([] { return R(kMin32) * R(-65536); }), {kMax32, kQ16Overflow}},
      {"MAX*-1", run([] { return R(kMax32) * R(-65536); }), {-kMax32, 0}},
      {"MIN*MIN", run([] { return R(kMin32) * R(kMin32); }), {kMax32, kQ16Overflow}},
      {"MIN*MAX", run([] { return R(kMin32) * R(kMax32); }), {kMin32, kQ16Overflow}},
      {"MAX*MAX", run([] { return R(kMax32) * R(kMax32); }), {kMax32, kQ16Overflow}},
      {"MIN*-1r", run([] { return R(kMin32) * R(-1); }), {32768, 0}},
      {"MAX*-1r", run([] { return R(kMax32) * R(-1); }), {-32768, 0}},
      // div: to nearest, ties to even; clamps; by zero.
      {"1/0", run([] { return R(65536) / R(0); }), {kMax32, kQ16DivByZero}},
      {"-1r/0", run([] { return R(-1) / R(0); }), {kMin32, kQ16DivByZero}},
      {"0/0", run([] { return R(0) / R(0); }), {kMax32, kQ16DivByZero}},
      {"MIN/0", run([] { return R(kMin32) / R(0); }), {kMin32, kQ16DivByZero}},
      {"MAX/0", run([] { return R(kMax32) / R(0); }), {kMax32, kQ16DivByZero}},
      {"recip(0)", run([] { return lockstep::reciprocal(R(0)); }), {kMax32, kQ16DivByZero}},
      {"MIN/-1", run([] { return R(kMin32) / R(-65536); }), {kMax32, kQ16Overflow}},
      {"MIN/1", run([] { return R(kMin32) / R(65536); }), {kMin32, 0}},
      {"MIN/MIN", run([] { return R(kMin32) / R(kMin32); }), {65536, 0}},
      {"MAX/MIN", run([] { return R(kMax32) / R(kMin32); }), {-65536, 0}},
      {"MIN/MAX", run([] { return R(kMin32) / R(kMax32); }), {-65536, 0}},
      {"-1r/2", run([] { return R(-1) / R(131072); }), {0, 0}},  // a tie, to even
      {"1r/-2", run([] { return R(1) / R(-131072); }), {0, 0}},  // sign-symmetric
      {"1r/2", run([] { return R(1) / R(131072); }), {0, 0}},
      {"1/-1r", run([] { return R(65536) / R(-1); }), {kMin32, kQ16Overflow}},
      {"-0.5/1r", run([] { return R(-32768) / R(1); }), {kMin32, 0}},
      {"recip(-1r)", run([] { return lockstep::reciprocal(R(-1)); }), {kMin32, kQ16Overflow}},
      {"recip(MIN)", run([] { return lockstep::reciprocal(R(kMin32)); }), {-2, 0}},
      {"recip(MAX)", run([] { return lockstep::reciprocal(R(kMax32)); }), {2, 0}},
      {"recip(3r)", run([] { return lockstep::reciprocal(R(3)); }), {1431655765, 0}},
      {"recip(-3r)", run([] { return lockstep::reciprocal(R(-3)); }), {-1431655765, 0}},  // = -recip(3r)
      // sqrt: the exact root of R*2^16 to nearest; negative gives 0.
      {"sqrt(-1r)", run([] { return lockstep::sqrt(R(-1)); }), {0, kQ16SqrtNegative}},
      {"sqrt(MIN)", run([] { return lockstep::sqrt(R(kMin32)); }), {0, kQ16SqrtNegative}},
      {"sqrt(MAX)", run([] { return lockstep::sqrt(R(kMax32)); }), {11863283, 0}},
      {"sqrt(0)", run([] { return lockstep::sqrt(R(0)); }), {0, 0}},
      {"sqrt(1r)", run([] { return lockstep::sqrt(R(1)); }), {256, 0}},
      {"sqrt(2)", run([] { return lockstep::sqrt(R(131072)); }), {92682, 0}},  // 92681.9
      {"sqrt(4)", run([] { return lockstep::sqrt(R(262144)); }), {131072, 0}},
      // from_int.
      {"int(32767)", run([] { return Q16::from_int(32767); }), {32767 * 65536, 0}},
      {"int(32768)", run([] { return Q16::from_int(32768); }), {kMax32, kQ16Overflow}},
      {"int(-32768)", run([] { return Q16::from_int(-32768); }), {kMin32, 0}},
      {"int(-32769)", run([] { return Q16::from_int(-32769); }), {kMin32, kQ16Overflow}},
      {"int(INT64_MAX)", run([] { return Q16::from_int(std::numeric_limits<std::int64_t>::max()); }), {kMax32, kQ16Overflow}},
      {"int(INT64_MIN)", run([] { return Q16::from_int(std::numeric_limits<std::int64_t>::min()); }), {kMin32, kQ16Overflow}},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(c.got.raw, c.want.raw) << c.what;
    EXPECT_EQ(c.got.flags, c.want.flags) << c.what;
  }
  EXPECT_EQ(lockstep::floor_to_int(R(kMin32)), -32768);
  EXPECT_EQ(lockstep::floor_to_int(R(kMax32)), 32767);
  EXPECT_EQ(lockstep::floor_to_int(R(-1)), -1);
  EXPECT_EQ(lockstep::floor_to_int(R(65535)), 0);
  EXPECT_EQ(lockstep::floor_to_int(R(-65536)), -1);
  EXPECT_EQ(lockstep::floor_to_int(R(-65537)), -2);
}

TEST(Q16Edge, FromDoubleLiterals) {
  using lockstep::kQ16Invalid;
  using lockstep::kQ16Overflow;
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double dmin = std::numeric_limits<double>::denorm_min();
  struct Case {
    double x;
    Expect want;
  };
  const Case cases[] = {
      {0.0, {0, 0}}, {-0.0, {0, 0}}, {dmin, {0, 0}}, {-dmin, {0, 0}},
      {std::numeric_limits<double>::min(), {0, 0}}, {-std::numeric_limits<double>::min(), {0, 0}},
      {1.0, {65536, 0}}, {-1.0, {-65536, 0}},
      // Ties go to even.
      {0.5 / 65536, {0, 0}}, {1.5 / 65536, {2, 0}}, {2.5 / 65536, {2, 0}}, {3.5 / 65536, {4, 0}},
      {-0.5 / 65536, {0, 0}}, {-1.5 / 65536, {-2, 0}}, {-2.5 / 65536, {-2, 0}},
      {std::nextafter(0.5 / 65536, 1.0), {1, 0}}, {std::nextafter(-0.5 / 65536, -1.0), {-1, 0}},
      {std::nextafter(-0.5 / 65536, 0.0), {0, 0}},
      // Just below zero with bits far below 2^-16 (its fraction is not exact in the
      // floor-and-subtract algorithm; the result still is).
      {-0x1.fffffffffffffp-18, {0, 0}}, {-0x1.0000000000001p-17, {-1, 0}},
      // The range ends.
      {2147483647.0 / 65536, {kMax32, 0}}, {2147483647.25 / 65536, {kMax32, 0}},
      {2147483647.5 / 65536, {kMax32, kQ16Overflow}},  // tie -> 2^31 (even) -> clamped
      {std::nextafter(2147483647.5 / 65536, 0.0), {kMax32, 0}},
      {32768.0, {kMax32, kQ16Overflow}}, {-32768.0, {kMin32, 0}},
      {-2147483648.5 / 65536, {kMin32, 0}},  // tie -> -2^31 (even): in range
      {std::nextafter(-2147483648.5 / 65536, -inf), {kMin32, kQ16Overflow}},
      {-32769.0, {kMin32, kQ16Overflow}},
      {1e300, {kMax32, kQ16Overflow}}, {-1e300, {kMin32, kQ16Overflow}},
      {std::numeric_limits<double>::max(), {kMax32, kQ16Overflow}},
      {inf, {kMax32, kQ16Overflow}}, {-inf, {kMin32, kQ16Overflow}},
      {nan, {0, kQ16Invalid}}, {-nan, {0, kQ16Invalid}},
      {std::numeric_limits<double>::signaling_NaN(), {0, kQ16Invalid}},
  };
  for (const Case& c : cases) {
    const Expect got = run([&] { return Q16::from_double(c.x); });
    EXPECT_EQ(got.raw, c.want.raw) << std::hexfloat << c.x;
    EXPECT_EQ(got.flags, c.want.flags) << std::hexfloat << c.x;
    const Expect ref = lt::ref_from_double(c.x);  // the reference agrees
    EXPECT_EQ(ref.raw, c.want.raw) << std::hexfloat << c.x;
    EXPECT_EQ(ref.flags, c.want.flags) << std::hexfloat << c.x;
  }
}

TEST(Q16Edge, StatusWord) {
  lockstep::q16_clear_status();
  (void)(R(kMax32) + R(1));
  (void)(R(1) + R(1));  // an exact op leaves the flag set
  (void)lockstep::sqrt(R(-1));
  EXPECT_EQ(lockstep::q16_status(), lockstep::kQ16Overflow | lockstep::kQ16SqrtNegative);
  EXPECT_EQ(lockstep::q16_take_status(), lockstep::kQ16Overflow | lockstep::kQ16SqrtNegative);
  EXPECT_EQ(lockstep::q16_status(), 0u);
  EXPECT_STREQ(lockstep::q16_flag_name(0), "ok");
  EXPECT_STREQ(lockstep::q16_flag_name(lockstep::kQ16DivByZero), "division by zero");
  EXPECT_STREQ(lockstep::q16_flag_name(lockstep::kQ16Invalid | lockstep::kQ16Overflow), "invalid conversion (NaN)");
}

}  // namespace
