// Q16.16 from an installed lockstep::fixed: the floor of a product (eq 21),
// a floored division and an exact dot product. Prints the raw results.
#include <cstdio>

#include "lockstep/fixed/q16_vec.hpp"

int main() {
  using lockstep::Q16;
  const Q16 floor_product = Q16::from_raw(-1) * Q16::from_raw(1);  // -2^-32 floors to -1 ulp, not 0
  const Q16 quotient = Q16::from_int(-3) / Q16::from_int(3);         // -1.0
  const lockstep::Vec3<Q16> a{Q16::from_double(0.5), Q16::from_int(1), Q16{}};
  const Q16 d = lockstep::dot(a, a);  // 0.25 + 1 = 1.25
  std::printf("%d %d %d\n", floor_product.raw(), quotient.raw(), d.raw());
  return 0;
}
