// The bit-exact engine from an installed lockstep::reference: the built-in
// drop scene on World<Q16>, 60 frames; prints the state hash (eq 92).
#include <cinttypes>
#include <cstdio>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/world.hpp"

int main() {
  const auto scene = lockstep::builtin_scene("drop");
  if (!scene) return 2;
  lockstep::World<lockstep::Q16> world(*scene);
  for (int f = 0; f < 60; ++f) world.step();
  std::printf("%016" PRIx64 "\n", world.state_hash());
  return 0;
}
