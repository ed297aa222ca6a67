// The number types every engine test runs on, and their tolerances in one
// place (MuJoCo style).
#pragma once
#include <gtest/gtest.h>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/math/num_mp.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/world.hpp"

namespace lockstep::test {

using EngineTypes = ::testing::Types<Q16, float, double, Mp>;

template <class T>
struct Tol;
// Free fall against the closed form: relative error allowed.
template <> struct Tol<double> { static constexpr double kFreeFallRel = 1e-12; static constexpr double kPosition = 1e-9; };
template <> struct Tol<Mp> { static constexpr double kFreeFallRel = 1e-15; static constexpr double kPosition = 1e-9; };
template <> struct Tol<float> { static constexpr double kFreeFallRel = 2e-5; static constexpr double kPosition = 1e-3; };
// Q16: the free-fall bound is derived in docs/SPEC.md Appendix C (one-sided,
// in ulps); kPosition is for agreement checks.
template <> struct Tol<Q16> { static constexpr double kFreeFallRel = 0; static constexpr double kPosition = 2e-3; };

template <class T>
double d(const T& x) { return Num<T>::to_double(x); }

// A unit cube (half extent 0.5 m, 1 kg) at position p.
inline BodyDesc unit_cube(double x, double y, double z) {
  BodyDesc b;
  b.position = {x, y, z};
  return b;
}

// All effects off except those named by the test.
inline Scene bare_scene() {
  Scene s;
  s.effects = Effects{false, false, false, false, false, false, false, false, false};
  s.ground.present = false;
  return s;
}

}  // namespace lockstep::test
