// Q16.16 fixed-point number: the one value type of lockstep's bit-exact engine.
//
// Rules (fixed/README.md states them for porters; every rule below is tested
// against exact arithmetic in tests/fixed/):
//   value      x = R / 2^16, R an int32 (source eq 20).
//   rounding   every operation that drops bits (product, division, square
//              root, the exact accumulators of q16_vec.hpp) rounds to
//              nearest, ties to even (docs/SPEC.md Fix 11 on eqs 21/23/24:
//              the source's floor biased every product half an ulp towards
//              minus infinity, and the physics showed it). Ties to even is
//              unbiased and sign-symmetric, round(-x) = -round(x), so a scene
//              and its mirror image give mirrored bits; it is also eq 22's
//              rule. The one floor left is floor_to_int (a grid cell, eq 26).
//   conversion from double rounds to nearest, ties to even (eq 22), the IEEE
//              default and Python's round(); the product x * 2^16 is exact.
//   overflow   never wraps and is never undefined: the exact result is clamped
//              to [INT32_MIN, INT32_MAX] and a sticky flag is raised in
//              q16_status(); the engine reads it and reports body, frame and
//              quantity.
#pragma once
#include <cmath>
#include <compare>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "lockstep/hd.hpp"

// Forced inlining of the hot Q16 primitives (GCC and clang; others inline at
// will). Every operation is host and device code (LS_HD): the GPU engine's
// gpu-fixed pipeline runs them in CUDA kernels (docs/GPU.md "gpu-fixed").
#if defined(__CUDACC__)
#define LOCKSTEP_Q16_INLINE __host__ __device__ __forceinline__
#elif defined(__GNUC__) || defined(__clang__)
#define LOCKSTEP_Q16_INLINE inline __attribute__((always_inline))
#define LOCKSTEP_Q16_OVERFLOW_BUILTINS 1  // __builtin_add/sub_overflow: the exact sum and whether it fits
#else
#define LOCKSTEP_Q16_INLINE inline
#endif

namespace lockstep {

// Sticky status flags raised by Q16 operations (bitwise OR).
enum Q16Flag : std::uint32_t {
  kQ16Ok = 0,
  kQ16Overflow = 1u << 0,      // result clamped to INT32_MIN or INT32_MAX
  kQ16DivByZero = 1u << 1,     // x / 0: result is +max for x >= 0, min for x < 0
  kQ16SqrtNegative = 1u << 2,  // sqrt(x < 0): result 0
  kQ16NormalizeZero = 1u << 3, // normalise of a zero vector/quaternion
  kQ16Invalid = 1u << 4,       // conversion from NaN: result 0
};

// The calling thread's sticky flags. Operations only ever OR into it.
inline constinit thread_local std::uint32_t q16_status_word = 0;
#if defined(__CUDACC__)
// On a CUDA device there is no thread_local: each thread of a block has its
// own word in this block-shared array, at threadIdx.x (the GPU engine's
// kernels run at most kQ16DeviceThreads threads per block). A kernel reads
// and clears its thread's word after each element (gpu/src/kernel_support.hpp).
inline constexpr int kQ16DeviceThreads = 256;
static __shared__ std::uint32_t q16_device_words[kQ16DeviceThreads];
#endif
// The calling thread's word: q16_status_word on the host, its shared word on a device.
LS_HD inline std::uint32_t& q16_status_ref() {
#if defined(__CUDA_ARCH__)
  return q16_device_words[threadIdx.x];
#else
  return q16_status_word;
#endif
}
LS_HD inline std::uint32_t q16_status() { return q16_status_ref(); }
LS_HD inline void q16_clear_status() { q16_status_ref() = 0; }
// Returns the flags raised since the last call and clears them.
LS_HD inline std::uint32_t q16_take_status() {
  std::uint32_t& w = q16_status_ref();
  const std::uint32_t s = w;
  w = 0;
  return s;
}
const char* q16_flag_name(std::uint32_t flags);

namespace q16detail {
constexpr std::int64_t kMax = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t kMin = std::numeric_limits<std::int32_t>::min();
LS_HD inline void raise(std::uint32_t f) { q16_status_ref() |= f; }
// The rare paths of the operations, out of line: the exact sums' (sum3_exact,
// diff2_exact) on a CUDA device too, where an inlined copy in every product
// sum made the solver's kernels spill; the clamp (a few instructions) stays
// inline there, as a call in every operation cost the contact kernel more
// (docs/GPU.md "gpu-fixed").
#if defined(__CUDACC__)
#define LOCKSTEP_Q16_COLD __noinline__
#define LOCKSTEP_Q16_COLD_CLAMP
#elif defined(__GNUC__) || defined(__clang__)
#define LOCKSTEP_Q16_COLD [[gnu::cold, gnu::noinline]]
#define LOCKSTEP_Q16_COLD_CLAMP [[gnu::cold, gnu::noinline]]
#else
#define LOCKSTEP_Q16_COLD
#define LOCKSTEP_Q16_COLD_CLAMP
#endif
// The clamp of an int64 outside int32 (the rare path of saturate).
LOCKSTEP_Q16_COLD_CLAMP LS_HD inline std::int32_t clamp_out_of_range(std::int64_t v) {
  raise(kQ16Overflow);
  return static_cast<std::int32_t>(v > kMax ? kMax : kMin);
}
// Clamp an exact int64 result into int32, raising kQ16Overflow when it clamps.
// One test: v is in [kMin, kMax] exactly when v - kMin (modulo 2^64) <= 2^32 - 1.
LOCKSTEP_Q16_INLINE std::int32_t saturate(std::int64_t v) {
  if (static_cast<std::uint64_t>(v) - static_cast<std::uint64_t>(kMin) > 0xFFFFFFFFull) [[unlikely]]
    return clamp_out_of_range(v);
  return static_cast<std::int32_t>(v);
}
// The wrapped sum or difference of two int32 or two int64 values and whether
// the exact one overflows: GCC's and clang's builtins on a host, else the
// sign rule (the sum of x and y overflows exactly when its sign differs from
// both of theirs, the difference x - y when x's and y's signs differ and
// the result's differs from x's), in unsigned arithmetic, which wraps
// (C++20: the conversion back is modulo 2^N). The same answers either way;
// on a CUDA device the rule is a few 32-bit logic operations where the
// 64-bit sum and range test took more (docs/GPU.md "gpu-fixed").
template <class I, class U>
LOCKSTEP_Q16_INLINE bool add_overflow_by_sign(I x, I y, I* s) {
  const U u = static_cast<U>(static_cast<U>(x) + static_cast<U>(y));
  *s = static_cast<I>(u);
  return static_cast<I>((static_cast<U>(x) ^ u) & (static_cast<U>(y) ^ u)) < 0;
}
template <class I, class U>
LOCKSTEP_Q16_INLINE bool sub_overflow_by_sign(I x, I y, I* s) {
  const U u = static_cast<U>(static_cast<U>(x) - static_cast<U>(y));
  *s = static_cast<I>(u);
  return static_cast<I>((static_cast<U>(x) ^ static_cast<U>(y)) & (static_cast<U>(x) ^ u)) < 0;
}
// I: int32_t or int64_t.
#if defined(LOCKSTEP_Q16_OVERFLOW_BUILTINS)
template <class I>
LOCKSTEP_Q16_INLINE bool add_overflow(I x, I y, I* s) { return __builtin_add_overflow(x, y, s); }
template <class I>
LOCKSTEP_Q16_INLINE bool sub_overflow(I x, I y, I* s) { return __builtin_sub_overflow(x, y, s); }
#else
template <class I>
LOCKSTEP_Q16_INLINE bool add_overflow(I x, I y, I* s) {
  return add_overflow_by_sign<I, std::make_unsigned_t<I>>(x, y, s);
}
template <class I>
LOCKSTEP_Q16_INLINE bool sub_overflow(I x, I y, I* s) {
  return sub_overflow_by_sign<I, std::make_unsigned_t<I>>(x, y, s);
}
#endif
// round(s / 2^16) to nearest, ties to even, for every int64 s (no
// intermediate can overflow): with q = floor(s / 2^16) and the dropped bits
// r = s & 0xFFFF, +1 when r > 2^15, or r = 2^15 and q is odd.
LOCKSTEP_Q16_INLINE std::int64_t round_shift16_any(std::int64_t s) {
  const std::int64_t q = s >> 16;
  return q + (((s & 0xFFFF) + 0x7FFF + (q & 1)) >> 16);
}
// saturate(round_shift16_any(s)) in 32-bit words, when it does not clamp:
// t = s + 2^15 - 1 + (bit 16 of s) in unsigned arithmetic (it wraps only
// where the result cannot fit), r the low word of t >> 16 (the rounding of
// round_shift16), and the result fits in int32 exactly when t's bits 47-63
// are all equal: (high word of t) >> 15 is 0 or -1. Returns false where
// saturate would clamp (r is then not the result). A CUDA device's form of
// the products' and sums' rounding (two 32-bit tests instead of a 64-bit
// shift, add and range test); tested against round_shift16_any on a host.
LOCKSTEP_Q16_INLINE bool round_shift16_fits(std::int64_t s, std::int32_t* r) {
  const std::uint64_t u = static_cast<std::uint64_t>(s);
  const std::uint64_t t = u + 0x7FFF + ((u >> 16) & 1);
  *r = static_cast<std::int32_t>(static_cast<std::uint32_t>(t >> 16));
  const auto high = static_cast<std::int32_t>(static_cast<std::uint32_t>(t >> 32));
  return static_cast<std::uint32_t>((high >> 15) + 1) <= 1u;
}
// saturate(round_shift16_any(s)): on a CUDA device through
// round_shift16_fits, elsewhere directly; the same value.
LOCKSTEP_Q16_INLINE std::int32_t round_saturate(std::int64_t s) {
#if defined(__CUDA_ARCH__)
  std::int32_t r;
  if (round_shift16_fits(s, &r)) [[likely]] return r;
  return clamp_out_of_range(round_shift16_any(s));
#else
  return saturate(round_shift16_any(s));
#endif
}
// floor(n / d) for d != 0, exact in int64 (C++ '/' truncates toward zero).
LS_HD constexpr std::int64_t floor_div(std::int64_t n, std::int64_t d) {
  std::int64_t q = n / d;
  if ((n % d != 0) && ((n < 0) != (d < 0))) --q;
  return q;
}
// round(p / 2^16) to nearest, ties to even, exact for |p| <= 2^62: with the
// floor q = p >> 16 (arithmetic shift) and the dropped bits r = p & 0xFFFF
// (two's complement: p = q 2^16 + r, 0 <= r < 2^16), the result is q + 1 when
// r > 2^15, or r = 2^15 and q is odd; branch-free, that is
// (p + 2^15 - 1 + (q & 1)) >> 16.
LS_HD constexpr std::int64_t round_shift16(std::int64_t p) {
  return (p + 0x7FFF + ((p >> 16) & 1)) >> 16;
}
// round(n / d) to nearest, ties to even, d != 0, exact in int64 for
// |n|, |d| < 2^62. Ties to even is sign-symmetric (round(-x) = -round(x)), so
// it is computed on |n| / |d| with one unsigned division: the quotient q and
// remainder r, up when 2r > |d|, or 2r = |d| and q is odd; then the sign.
LS_HD constexpr std::int64_t round_div(std::int64_t n, std::int64_t d) {
  const bool negative = (n < 0) != (d < 0);
  const std::uint64_t un = n < 0 ? 0 - static_cast<std::uint64_t>(n) : static_cast<std::uint64_t>(n);
  const std::uint64_t ud = d < 0 ? 0 - static_cast<std::uint64_t>(d) : static_cast<std::uint64_t>(d);
  std::uint64_t q = un / ud;
  const std::uint64_t twice = 2 * (un - q * ud);
  q += (twice > ud || (twice == ud && (q & 1) != 0)) ? 1 : 0;
  return negative ? -static_cast<std::int64_t>(q) : static_cast<std::int64_t>(q);
}
// floor(sqrt(n)), exact. The double square root (correctly rounded by IEEE
// 754, but n itself may round on conversion) is only a first guess; the
// integer corrections make r the unique value with r^2 <= n < (r + 1)^2,
// tested with products that cannot overflow: r <= 2^32 - 1, so r^2 < 2^64,
// and (r + 1)^2 is formed only for r < 2^32 - 1 ((2^32)^2 > n always).
LOCKSTEP_Q16_INLINE std::uint64_t isqrt(std::uint64_t n) {
  auto r = static_cast<std::uint64_t>(std::sqrt(static_cast<double>(n)));
  if (r > 0xFFFFFFFFull) r = 0xFFFFFFFFull;  // floor(sqrt(2^64 - 1))
  while (r * r > n) --r;
  while (r < 0xFFFFFFFFull && (r + 1) * (r + 1) <= n) ++r;
  return r;
}
// round(sqrt(n)) to nearest: r = floor(sqrt(n)), up when n - r^2 > r, i.e.
// n >= (r + 1/2)^2 + 1/4; sqrt(n) is never r + 1/2 exactly (no ties).
LOCKSTEP_Q16_INLINE std::uint64_t isqrt_round(std::uint64_t n) {
  const std::uint64_t r = isqrt(n);
  return n - r * r > r ? r + 1 : r;
}
}  // namespace q16detail

class Q16 {
 public:
  static constexpr int kFracBits = 16;
  static constexpr std::int32_t kOneRaw = 65536;  // 1.0

  constexpr Q16() = default;
  // The value raw / 2^16, bit for bit.
  static LS_HD constexpr Q16 from_raw(std::int32_t raw) { Q16 q; q.raw_ = raw; return q; }
  // An integer: exact when |i| <= 32767, otherwise clamped with kQ16Overflow.
  static LS_HD Q16 from_int(std::int64_t i) {
    if (i > 32767) return from_raw(q16detail::saturate(q16detail::kMax + 1));
    if (i < -32768) return from_raw(q16detail::saturate(q16detail::kMin - 1));
    return from_raw(static_cast<std::int32_t>(i * kOneRaw));
  }
  // eq 22: R = round(x * 2^16), to nearest, ties to even. NaN -> 0 with
  // kQ16Invalid; out of range (or +-inf) -> clamped with kQ16Overflow.
  // Inline: a constant (0.5, 1/64) folds at compile time.
  static LS_HD Q16 from_double(double x);

  LS_HD constexpr std::int32_t raw() const { return raw_; }
  // Exact: every Q16 value is a double.
  LS_HD constexpr double to_double() const { return static_cast<double>(raw_) / 65536.0; }
  LS_HD constexpr float to_float() const { return static_cast<float>(to_double()); }

  // The comparisons by name (host and device code; <=> alone would go
  // through std::strong_ordering, host code), and <=> for the rest.
  friend LS_HD constexpr bool operator==(Q16 a, Q16 b) { return a.raw_ == b.raw_; }
  friend LS_HD constexpr bool operator!=(Q16 a, Q16 b) { return a.raw_ != b.raw_; }
  friend LS_HD constexpr bool operator<(Q16 a, Q16 b) { return a.raw_ < b.raw_; }
  friend LS_HD constexpr bool operator>(Q16 a, Q16 b) { return a.raw_ > b.raw_; }
  friend LS_HD constexpr bool operator<=(Q16 a, Q16 b) { return a.raw_ <= b.raw_; }
  friend LS_HD constexpr bool operator>=(Q16 a, Q16 b) { return a.raw_ >= b.raw_; }
  friend constexpr auto operator<=>(Q16 a, Q16 b) { return a.raw_ <=> b.raw_; }

  // Exact sum, clamped: the int32 sum, and the clamp of the exact int64 sum
  // only when that does not fit (q16detail::add_overflow); the same value.
  friend LOCKSTEP_Q16_INLINE Q16 operator+(Q16 a, Q16 b) {
    std::int32_t r;
    if (q16detail::add_overflow(a.raw_, b.raw_, &r)) [[unlikely]]
      return from_raw(q16detail::clamp_out_of_range(std::int64_t{a.raw_} + b.raw_));
    return from_raw(r);
  }
  friend LOCKSTEP_Q16_INLINE Q16 operator-(Q16 a, Q16 b) {
    std::int32_t r;
    if (q16detail::sub_overflow(a.raw_, b.raw_, &r)) [[unlikely]]
      return from_raw(q16detail::clamp_out_of_range(std::int64_t{a.raw_} - b.raw_));
    return from_raw(r);
  }
  // -INT32_MIN clamps to INT32_MAX (kQ16Overflow).
  friend LOCKSTEP_Q16_INLINE Q16 operator-(Q16 a) { return Q16{} - a; }
  // eq 21 (Fix 11): round(Ra * Rb / 2^16), to nearest, ties to even: exact
  // int64 product, round_shift16, clamp.
  friend LOCKSTEP_Q16_INLINE Q16 operator*(Q16 a, Q16 b) {
#if defined(__CUDA_ARCH__)
    return from_raw(q16detail::round_saturate(std::int64_t{a.raw_} * b.raw_));
#else
    return from_raw(q16detail::saturate(q16detail::round_shift16(std::int64_t{a.raw_} * b.raw_)));
#endif
  }
  // round(Ra * 2^16 / Rb), to nearest, ties to even, exact in int64, clamped
  // (eq 24, Fix 11). Division by zero: kQ16DivByZero,
  // result INT32_MAX for a >= 0 and INT32_MIN for a < 0.
  friend LOCKSTEP_Q16_INLINE Q16 operator/(Q16 a, Q16 b) {
    if (b.raw_ == 0) {
      q16detail::raise(kQ16DivByZero);
      return from_raw(a.raw_ >= 0 ? static_cast<std::int32_t>(q16detail::kMax)
                                  : static_cast<std::int32_t>(q16detail::kMin));
    }
    return from_raw(q16detail::saturate(
        q16detail::round_div(std::int64_t{a.raw_} * kOneRaw, b.raw_)));
  }
  LS_HD Q16& operator+=(Q16 b) { return *this = *this + b; }
  LS_HD Q16& operator-=(Q16 b) { return *this = *this - b; }
  LS_HD Q16& operator*=(Q16 b) { return *this = *this * b; }
  LS_HD Q16& operator/=(Q16 b) { return *this = *this / b; }

 private:
  std::int32_t raw_ = 0;
};

LS_HD inline Q16 Q16::from_double(double x) {
  if (std::isnan(x)) {
    q16detail::raise(kQ16Invalid);
    return Q16{};
  }
  // x * 2^16 is exact (a power-of-two scale) unless it overflows to inf.
  const double scaled = x * 65536.0;
  if (scaled >= 2147483647.5) return from_raw(q16detail::saturate(q16detail::kMax + 1));
  if (scaled < -2147483648.5) return from_raw(q16detail::saturate(q16detail::kMin - 1));
  // Round to nearest, ties to even, with exact double operations only.
  const double fl = std::floor(scaled);
  // Exact, except for -0.5 < scaled < 0: there it is 1 + scaled, which may
  // round, but never below 0.5, so r becomes fl + 1 = 0 (frac > 0.5, or
  // frac == 0.5 with fl = -1 odd): the correct result. Tested in
  // tests/fixed/q16_test.cpp (FromDoubleLiterals, FromDouble).
  const double frac = scaled - fl;
  auto r = static_cast<std::int64_t>(fl);
  if (frac > 0.5 || (frac == 0.5 && (r & 1) != 0)) ++r;
  return from_raw(q16detail::saturate(r));
}

// |a|; abs(INT32_MIN raw) clamps to INT32_MAX with kQ16Overflow.
LS_HD inline Q16 abs(Q16 a) { return a.raw() < 0 ? -a : a; }
LS_HD constexpr Q16 min(Q16 a, Q16 b) { return b < a ? b : a; }
LS_HD constexpr Q16 max(Q16 a, Q16 b) { return a < b ? b : a; }
// round(sqrt(R * 2^16)): the exact square root, rounded to nearest (Fix 11;
// never a tie). sqrt(x < 0) = 0 with kQ16SqrtNegative. Never overflows
// (sqrt(2^47) < 2^24).
LS_HD inline Q16 sqrt(Q16 a) {
  if (a.raw() < 0) { q16detail::raise(kQ16SqrtNegative); return Q16{}; }
  return Q16::from_raw(static_cast<std::int32_t>(
      q16detail::isqrt_round(static_cast<std::uint64_t>(a.raw()) << 16)));
}
// 1 / a, same rule as division.
LS_HD inline Q16 reciprocal(Q16 a) { return Q16::from_raw(Q16::kOneRaw) / a; }
// floor(a): the largest integer <= a, as an int (exact, never overflows).
LS_HD constexpr std::int32_t floor_to_int(Q16 a) { return a.raw() >> 16; }

}  // namespace lockstep
