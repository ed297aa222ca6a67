// The per-element functions that World<T> and the GPU engine share
// (reference/include/lockstep/physics/{solver,narrow,body_step}.hpp): the
// properties World's loops rely on when they call them.
#include <gtest/gtest.h>

#include "engine_types.hpp"
#include "lockstep/physics/body_step.hpp"
#include "lockstep/physics/narrow.hpp"
#include "lockstep/physics/solver.hpp"

namespace lockstep::test {
namespace {

template <class T>
class SharedSteps : public ::testing::Test {};
TYPED_TEST_SUITE(SharedSteps, EngineTypes);

template <class T>
Vec3<T> vec(double x, double y, double z) {
  return {Num<T>::from_double(x), Num<T>::from_double(y), Num<T>::from_double(z)};
}

// A tilted unit cube (1 kg) falling onto the ground, as the solver sees it.
template <class T>
BodyView<T> falling_cube() {
  const T one = Num<T>::from_int(1);
  const Vec3<T> half = vec<T>(0.5, 0.5, 0.5);
  const Quat<T> q = normalize(Quat<T>{one, Num<T>::from_double(0.1), T{}, Num<T>::from_double(0.2)});
  return dynamic_view(vec<T>(0.3, -2.0, 0.1), vec<T>(0.5, 0.0, -1.0), one, rotation_matrix(q),
                      box_inverse_inertia(half, one, Num<T>::from_int(3)));
}

// Eq 99 with one point is no split: a manifold of one ground corner gives
// the bits of a single contact visit with unscaled effective masses, which is
// how World<T> visits a body pair.
TYPED_TEST(SharedSteps, OnePointManifoldIsOneContactVisit) {
  using T = TypeParam;
  const Params<T> P = Params<T>::from(Constants{});
  const Vec3<T> r1 = vec<T>(-0.5, -0.6, 0.4), n = vec<T>(0, 1, 0);
  const T penetration = Num<T>::from_double(0.004);
  const BodyView<T> ground = immovable_view<T>();
  SolveCounts prep;
  const ContactState<T> start = prepare_contact(falling_cube<T>(), r1, ground, Vec3<T>{}, n, Num<T>::from_double(0.2),
                                                Num<T>::from_double(0.5), Num<T>::from_double(0.2),
                                                Num<T>::from_double(0.5), true, true, P, prep);
  ASSERT_TRUE(start.k_n > T{});

  BodyView<T> A1 = falling_cube<T>(), B1 = ground;
  ContactState<T> c1 = start;
  SolveCounts n1;
  BodyView<T> A2 = falling_cube<T>(), B2 = ground;
  ContactState<T> c2 = start;
  SolveCounts n2;
  auto point = [&](int k, Vec3<T>& r, Vec3<T>& r2, Vec3<T>& nn, T& pen) {
    if (k != 0) return false;
    r2 = Vec3<T>{};
    r = r1;
    nn = n;
    pen = penetration;
    return true;
  };
  auto load = [&](int) { return c2; };
  auto store = [&](int, const ContactState<T>& s) { c2 = s; };
  for (int it = 0; it < 4; ++it) {
    solve_contact(A1, r1, B1, Vec3<T>{}, n, penetration, c1, true, true, Num<T>::from_int(1), P, n1);
    solve_manifold<1>(A2, B2, point, load, store, true, true, P, n2);
  }
  EXPECT_GT(c1.j_n, T{});  // the contact did push
  EXPECT_GT(n1.friction_steps, 0u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(A1.v[a], A2.v[a]) << "axis " << a;
    EXPECT_EQ(A1.w[a], A2.w[a]) << "axis " << a;
    EXPECT_EQ(c1.j_t[a], c2.j_t[a]) << "axis " << a;
  }
  EXPECT_EQ(c1.j_n, c2.j_n);
  EXPECT_EQ(n1.solver_contacts, n2.solver_contacts);
  EXPECT_EQ(n1.normal_impulses, n2.normal_impulses);
  EXPECT_EQ(n1.friction_steps, n2.friction_steps);
}

// A manifold whose both sides are immovable (k_n = 0) is skipped before eq
// 99's sum m^-1 / k_n is formed: no visit is counted and, in Q16.16, no
// division by zero is raised (World<Q16> would stop the run on that fault).
TYPED_TEST(SharedSteps, ManifoldBetweenImmovableSidesIsSkippedWithoutAFault) {
  using T = TypeParam;
  const Params<T> P = Params<T>::from(Constants{});
  Num<T>::take_faults();
  BodyView<T> A = immovable_view<T>(), B = immovable_view<T>();
  ContactState<T> states[4];
  auto point = [&](int k, Vec3<T>& r, Vec3<T>& r2, Vec3<T>& n, T& pen) {
    r2 = Vec3<T>{};
    r = vec<T>(k & 1 ? 0.5 : -0.5, -0.5, k & 2 ? 0.5 : -0.5);
    n = vec<T>(0, 1, 0);
    pen = Num<T>::from_double(0.01);
    return true;
  };
  auto load = [&](int k) { return states[k]; };
  auto store = [&](int k, const ContactState<T>& s) { states[k] = s; };
  SolveCounts counts;
  solve_manifold<4>(A, B, point, load, store, true, true, P, counts);
  EXPECT_EQ(Num<T>::take_faults(), 0u);
  EXPECT_EQ(counts.solver_contacts, 0u);
  EXPECT_EQ(states[0].j_n, T{});
}

// Eq 84 through the shared corner function: a cube resting flat on the plane
// has its 4 bottom corners at depth 0 and its top corners 1 m above.
TYPED_TEST(SharedSteps, GroundCornerDepthsOfARestingCube) {
  using T = TypeParam;
  const Mat3<T> R = identity3<T>();
  int bottom = 0;
  for (int k = 0; k < 8; ++k) {
    Vec3<T> corner;
    const T depth = ground_corner_depth(vec<T>(0, 0.5, 0), R, vec<T>(0.5, 0.5, 0.5), k, T{}, corner);
    EXPECT_EQ(depth, -corner.y) << "corner " << k;
    if (depth == T{}) ++bottom;
    else EXPECT_EQ(depth, -Num<T>::from_int(1)) << "corner " << k;
  }
  EXPECT_EQ(bottom, 4);
}

// Eq 81 through the shared wake test (n from b up towards a): the velocity
// of a sleeping side counts as 0, so a sleeper's stale velocity wakes nothing.
TYPED_TEST(SharedSteps, WakeTestIgnoresASleepersVelocity) {
  using T = TypeParam;
  const Params<T> P = Params<T>::from(Constants{});
  const Vec3<T> n = vec<T>(0, 1, 0), down = vec<T>(0, -2, 0), up = vec<T>(0, 2, 0), still{};
  EXPECT_TRUE(wake_test(down, false, still, true, n, T{}, P));  // a falls onto sleeping b
  EXPECT_TRUE(wake_test(still, true, up, false, n, T{}, P));    // b rises into sleeping a
  EXPECT_FALSE(wake_test(still, false, up, true, n, T{}, P));   // sleeping b's stale velocity
  EXPECT_TRUE(wake_test(still, false, still, true, n, P.wake_penetration * Num<T>::from_int(2), P));  // deep
}

}  // namespace
}  // namespace lockstep::test
