// Num<T>: what the physics needs of a number type beyond + - * / and <.
// Specialised for float and double here, for Q16 in lockstep/fixed/q16_num.hpp
// and for Boost.Multiprecision in lockstep/math/num_mp.hpp (reference/include).
// Lives in fixed/include so that fixed/ includes nothing from reference/.
#pragma once
#include <cmath>
#include <cstdint>

#include "lockstep/hd.hpp"

namespace lockstep {

template <class T>
struct Num;

template <class F>
struct NumFloat {
  static constexpr bool kExact = false;
  // Decimal constants (Appendix A) and scene values enter through double.
  static LS_HD F from_double(double x) { return static_cast<F>(x); }
  static LS_HD F from_raw_q16(std::int32_t raw) { return static_cast<F>(static_cast<double>(raw) / 65536.0); }
  static LS_HD F from_int(int i) { return static_cast<F>(i); }
  static LS_HD double to_double(F x) { return static_cast<double>(x); }
  static LS_HD F sqrt(F x) { return std::sqrt(x); }
  static LS_HD F abs(F x) { return std::fabs(x); }
  static LS_HD F min(F a, F b) { return b < a ? b : a; }
  static LS_HD F max(F a, F b) { return a < b ? b : a; }
  static LS_HD int floor_int(F x) { return static_cast<int>(std::floor(x)); }
  static LS_HD bool finite(F x) { return std::isfinite(x); }
  // Numeric faults since the last call: none for IEEE types (non-finite
  // results are caught by the engine's finite() checks).
  static std::uint32_t take_faults() { return 0; }
};

template <> struct Num<float> : NumFloat<float> { static constexpr const char* kName = "float"; };
template <> struct Num<double> : NumFloat<double> { static constexpr const char* kName = "double"; };

template <class T> LS_HD T num(double x) { return Num<T>::from_double(x); }

}  // namespace lockstep
