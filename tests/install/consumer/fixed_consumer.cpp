// Q16.16 from an installed lockstep::fixed: a product that is a tie (eq 21,
// to nearest, ties to even), a division and an exact dot product. Prints the
// raw results.
#include <cstdio>

#include "lockstep/fixed/q16_vec.hpp"

int main() {
  using lockstep::Q16;
  const Q16 tie_product = Q16::from_raw(3) * Q16::from_raw(0x8000);  // 1.5 ulp: a tie, to even: 2
  const Q16 quotient = Q16::from_int(-3) / Q16::from_int(3);         // -1.0
  const lockstep::Vec3<Q16> a{Q16::from_double(0.5), Q16::from_int(1), Q16{}};
  const Q16 d = lockstep::dot(a, a);  // 0.25 + 1 = 1.25
  std::printf("%d %d %d\n", tie_product.raw(), quotient.raw(), d.raw());
  return 0;
}
