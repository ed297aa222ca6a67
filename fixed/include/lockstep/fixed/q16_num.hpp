// Num<Q16>: the Q16.16 type seen through the engine's number-type interface.
#pragma once
#include "lockstep/fixed/q16.hpp"
#include "lockstep/math/num.hpp"

namespace lockstep {

template <>
struct Num<Q16> {
  static constexpr bool kExact = true;
  static constexpr const char* kName = "fixed";
  static LS_HD Q16 from_double(double x) { return Q16::from_double(x); }
  static LS_HD constexpr Q16 from_raw_q16(std::int32_t raw) { return Q16::from_raw(raw); }
  static LS_HD Q16 from_int(int i) { return Q16::from_int(i); }
  static LS_HD double to_double(Q16 x) { return x.to_double(); }
  static LS_HD Q16 sqrt(Q16 x) { return lockstep::sqrt(x); }
  static LS_HD Q16 abs(Q16 x) { return lockstep::abs(x); }
  static LS_HD Q16 min(Q16 a, Q16 b) { return lockstep::min(a, b); }
  static LS_HD Q16 max(Q16 a, Q16 b) { return lockstep::max(a, b); }
  static LS_HD int floor_int(Q16 x) { return floor_to_int(x); }
  static LS_HD bool finite(Q16) { return true; }
  static LS_HD std::uint32_t take_faults() { return q16_take_status(); }
};

}  // namespace lockstep

// Every translation unit that can instantiate a template on Q16 (they all
// need Num<Q16>) also sees the exact-accumulator overloads: with only the
// generic formulas of math/vec.hpp in view, an inline template such as
// Params<Q16>::from was instantiated with the generic length (rounded
// differently), and the linker kept whichever copy came first: a test binary
// ran a fixed engine whose support_fade differed by an ulp from the one the
// lockstep command runs (AgreementProp seed 7020). vec.hpp's generic
// versions of these operations now refuse Q16 at compile time.
#include "lockstep/fixed/q16_vec.hpp"
