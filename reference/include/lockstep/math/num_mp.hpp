// Num<Mp>: the high-precision truth, a Boost.Multiprecision binary float with
// a 113-bit significand (about 34 decimal digits, IEEE quad layout).
#pragma once
#include <boost/multiprecision/cpp_bin_float.hpp>

#include "lockstep/math/num.hpp"

namespace lockstep {

using Mp = boost::multiprecision::number<
    boost::multiprecision::cpp_bin_float<113, boost::multiprecision::digit_base_2, void, std::int16_t, -16382, 16383>,
    boost::multiprecision::et_off>;

template <>
struct Num<Mp> {
  static constexpr bool kExact = false;
  static constexpr const char* kName = "mp";
  static Mp from_double(double x) { return Mp(x); }
  static Mp from_raw_q16(std::int32_t raw) { return Mp(raw) / 65536; }
  static Mp from_int(int i) { return Mp(i); }
  static double to_double(const Mp& x) { return x.convert_to<double>(); }
  static Mp sqrt(const Mp& x) { return boost::multiprecision::sqrt(x); }
  static Mp abs(const Mp& x) { return boost::multiprecision::abs(x); }
  static Mp min(const Mp& a, const Mp& b) { return b < a ? b : a; }
  static Mp max(const Mp& a, const Mp& b) { return a < b ? b : a; }
  static int floor_int(const Mp& x) { return boost::multiprecision::floor(x).convert_to<int>(); }
  static bool finite(const Mp& x) { return boost::multiprecision::isfinite(x); }
  static std::uint32_t take_faults() { return 0; }
};

}  // namespace lockstep
