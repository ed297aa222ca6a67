#include "lockstep/fixed/q16.hpp"

#include <cmath>

namespace lockstep {

const char* q16_flag_name(std::uint32_t flags) {
  if (flags & kQ16Invalid) return "invalid conversion (NaN)";
  if (flags & kQ16DivByZero) return "division by zero";
  if (flags & kQ16SqrtNegative) return "square root of a negative value";
  if (flags & kQ16NormalizeZero) return "normalisation of a zero vector";
  if (flags & kQ16Overflow) return "Q16.16 overflow (|x| >= 32768)";
  return "ok";
}

Q16 Q16::from_double(double x) {
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

}  // namespace lockstep
