// lockstep Q16 against libfixmath's fix16 (the same Q16.16 representation),
// over random raw inputs from the generators of gen.hpp (uniform, log-uniform,
// edges, and inputs on rounding boundaries), with a fixed seed so that the
// counts printed here and quoted in fixed/README.md are reproducible.
//
// Every input pair is classified. Bit-for-bit agreement is required wherever
// the two rules agree; every mismatch must fall into a documented category:
//   ties differ          both round to nearest; on an exact tie libfixmath
//                        rounds away from zero, lockstep to even (Fix 11);
//   overflow sentinel    libfixmath returns fix16_overflow = 0x80000000,
//                        lockstep clamps (and raises kQ16Overflow);
//   division by zero     libfixmath returns fix16_minimum = 0x80000000,
//                        lockstep INT32_MAX for a >= 0, INT32_MIN for a < 0;
//   sqrt negative        libfixmath returns -sqrt(-x), lockstep 0;
//   not correctly rounded  libfixmath's div/sqrt result is not the nearest
//                        (it is the other neighbour of the exact value).
// An unexplained mismatch fails the test.
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <libfixmath/fix16.h>

#include "exact.hpp"
#include "gen.hpp"
#include "lockstep/fixed/q16.hpp"

namespace {

using lockstep::Q16;
using lockstep_test::Int;
using lockstep_test::kMax32;
using lockstep_test::kMin32;
namespace lt = lockstep_test;
namespace lg = lockstep_test::gen;

constexpr int kSamples = 200000;

// Draws values from a RapidCheck generator outside a property, deterministically.
template <class T>
class Draw {
 public:
  Draw(rc::Gen<T> g, std::uint64_t seed) : gen_(std::move(g)), random_(seed) {}
  T operator()() { return gen_(random_.split(), rc::kNominalSize).value(); }

 private:
  rc::Gen<T> gen_;
  rc::Random random_;
};

struct Tally {
  std::map<std::string, long> n;
  long unexplained = 0;
  void add(const std::string& what) { ++n[what]; }
  void bad(const char* op, std::int32_t a, std::int32_t b, std::int32_t ours, std::int32_t theirs) {
    if (++unexplained <= 10)
      ADD_FAILURE() << op << "(" << a << ", " << b << "): lockstep " << ours << ", libfixmath " << theirs
                    << " (unexplained)";
  }
  void print(const char* op) const {
    std::printf("%-4s", op);
    for (const auto& [k, v] : n) std::printf("  %s=%ld", k.c_str(), v);
    std::printf("  unexplained=%ld\n", unexplained);
  }
  long get(const std::string& k) const {
    const auto it = n.find(k);
    return it == n.end() ? 0 : it->second;
  }
};

bool fits(const Int& v) { return v >= kMin32 && v <= kMax32; }

// Add and sub: exact in range; out of range libfixmath returns 0x80000000.
template <class Ours, class Theirs, class Exact>
Tally compare_addsub(const char* op, Ours ours_op, Theirs theirs_op, Exact exact_op) {
  Tally t;
  Draw<std::int32_t> a_gen(lg::raw(), 1), b_gen(lg::raw(), 2);
  for (int i = 0; i < kSamples; ++i) {
    const std::int32_t a = a_gen(), b = b_gen();
    const std::int32_t ours = ours_op(Q16::from_raw(a), Q16::from_raw(b)).raw();
    const std::int32_t theirs = theirs_op(a, b);
    const Int e = exact_op(Int(a), Int(b));
    if (!fits(e)) {
      if (theirs == kMin32) t.add("overflow_sentinel");
      else t.bad(op, a, b, ours, theirs);
    } else if (theirs == ours) {
      t.add("same");
    } else {
      t.bad(op, a, b, ours, theirs);
    }
  }
  return t;
}

TEST(LibfixmathCompare, AddSub) {
  const Tally add = compare_addsub(
      "add", [](Q16 a, Q16 b) { return a + b; }, [](std::int32_t a, std::int32_t b) { return fix16_add(a, b); },
      [](const Int& a, const Int& b) { return Int(a + b); });
  const Tally sub = compare_addsub(
      "sub", [](Q16 a, Q16 b) { return a - b; }, [](std::int32_t a, std::int32_t b) { return fix16_sub(a, b); },
      [](const Int& a, const Int& b) { return Int(a - b); });
  add.print("add");
  sub.print("sub");
  EXPECT_EQ(add.unexplained + sub.unexplained, 0);
  EXPECT_GT(add.get("overflow_sentinel"), 0);
  EXPECT_GT(sub.get("same"), 0);
}

TEST(LibfixmathCompare, Mul) {
  Tally t;
  Draw<std::pair<std::int32_t, std::int32_t>> pairs(lg::mul_pair(), 3);
  for (int i = 0; i < kSamples; ++i) {
    const auto [a, b] = pairs();
    const std::int32_t ours = (Q16::from_raw(a) * Q16::from_raw(b)).raw();
    const std::int32_t theirs = fix16_mul(a, b);
    const Int p = Int(a) * Int(b);
    const Int scale(65536);  // a named operand: a temporary trips GCC's -Wmaybe-uninitialized in cpp_int
    const Int re = lt::round_div_even(p, scale), rn = lt::round_half_away(p, scale);
    if (!fits(re) || !fits(rn)) {
      if (theirs == kMin32) t.add("overflow_sentinel");
      else t.bad("mul", a, b, ours, theirs);
    } else if (theirs == ours) {
      t.add(re == rn ? "same" : "same_their_rounding_wrong");
    } else if (Int(theirs) == rn) {
      t.add("ties_differ");  // re != rn only on an exact tie
    } else {
      t.bad("mul", a, b, ours, theirs);
    }
  }
  t.print("mul");
  EXPECT_EQ(t.unexplained, 0);
  EXPECT_EQ(t.get("same_their_rounding_wrong"), 0);  // fix16_mul is correctly rounded
  EXPECT_GT(t.get("ties_differ"), 0);                 // the generators hit ties
  EXPECT_GT(t.get("same"), t.get("ties_differ"));
  EXPECT_GT(t.get("overflow_sentinel"), 0);
}

TEST(LibfixmathCompare, Div) {
  Tally t;
  Draw<std::pair<std::int32_t, std::int32_t>> pairs(lg::div_pair(), 4);
  for (int i = 0; i < kSamples; ++i) {
    const auto [a, b] = pairs();
    const std::int32_t ours = (Q16::from_raw(a) / Q16::from_raw(b)).raw();
    const std::int32_t theirs = fix16_div(a, b);
    if (b == 0) {
      if (theirs == kMin32) t.add("division_by_zero");
      else t.bad("div", a, b, ours, theirs);
      continue;
    }
    const Int n = Int(a) * 65536;
    const Int re = lt::round_div_even(n, Int(b)), rn = lt::round_half_away(n, Int(b));
    if (!fits(re) || !fits(rn)) {
      if (theirs == kMin32) t.add("overflow_sentinel");
      else t.bad("div", a, b, ours, theirs);
    } else if (theirs == ours) {
      t.add(re == rn ? "same" : "same_their_rounding_wrong");
    } else if (Int(theirs) == rn) {
      t.add("ties_differ");
    } else if (Int(theirs) == re + 1 || Int(theirs) == re - 1) {
      t.add("not_correctly_rounded");  // the other neighbour of the exact quotient
    } else {
      t.bad("div", a, b, ours, theirs);
    }
  }
  t.print("div");
  EXPECT_EQ(t.unexplained, 0);
  EXPECT_GT(t.get("same"), 0);
  EXPECT_GT(t.get("division_by_zero"), 0);
  EXPECT_GT(t.get("overflow_sentinel"), 0);
}

TEST(LibfixmathCompare, Sqrt) {
  Tally t;
  Draw<std::int32_t> as(lg::sqrt_raw(), 5);
  for (int i = 0; i < kSamples; ++i) {
    const std::int32_t a = as();
    const std::int32_t ours = lockstep::sqrt(Q16::from_raw(a)).raw();
    const std::int32_t theirs = fix16_sqrt(a);
    const Int x = abs(Int(a)) * 65536;
    const Int fl = lt::isqrt(x);
    const Int rn = lt::isqrt_round(x);  // nearest (no ties for integers): both libraries' rule
    if (a < 0) {
      // -sqrt(-x): their own rounding of the root, negated.
      if (Int(theirs) == -fl || Int(theirs) == -rn) t.add("sqrt_negative");
      else t.bad("sqrt", a, 0, ours, theirs);
    } else if (theirs == ours) {
      t.add("same");
    } else if (Int(theirs) == rn + 1 || Int(theirs) == rn - 1) {
      t.add("not_correctly_rounded");
    } else {
      t.bad("sqrt", a, 0, ours, theirs);
    }
  }
  t.print("sqrt");
  EXPECT_EQ(t.unexplained, 0);
  EXPECT_GT(t.get("same"), 0);
  EXPECT_GT(t.get("sqrt_negative"), 0);
}

// The named edges, written out.
TEST(LibfixmathCompare, Literals) {
  EXPECT_EQ(fix16_add(kMax32, 1), kMin32);          // overflow sentinel; lockstep clamps to MAX
  EXPECT_EQ(fix16_mul(-1, 1), 0);                   // -2^-16 ulp rounds to nearest 0, in both
  EXPECT_EQ((Q16::from_raw(-1) * Q16::from_raw(1)).raw(), 0);
  EXPECT_EQ(fix16_mul(1, 0x8000), 1);               // exact 0.5 ulp: ties away from zero; lockstep 0 (even)
  EXPECT_EQ((Q16::from_raw(1) * Q16::from_raw(0x8000)).raw(), 0);
  EXPECT_EQ(fix16_mul(-1, 0x8000), -1);             // -0.5 ulp: away from zero; lockstep 0 (even)
  EXPECT_EQ((Q16::from_raw(-1) * Q16::from_raw(0x8000)).raw(), 0);
  EXPECT_EQ(fix16_mul(3, 0x8000), 2);               // 1.5 ulp: both 2
  EXPECT_EQ((Q16::from_raw(3) * Q16::from_raw(0x8000)).raw(), 2);
  EXPECT_EQ(fix16_div(fix16_one, 0), kMin32);       // lockstep INT32_MAX
  EXPECT_EQ(fix16_div(-fix16_one, 0), kMin32);      // lockstep INT32_MIN
  EXPECT_EQ(fix16_div(0, 0), kMin32);               // lockstep INT32_MAX
  EXPECT_EQ(fix16_sqrt(-4 * fix16_one), -2 * fix16_one);  // lockstep 0 + kQ16SqrtNegative
}

}  // namespace
