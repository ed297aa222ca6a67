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

}  // namespace lockstep
