// The per-element functions that World<T> and the GPU engine share
// (reference/include/lockstep/physics/{solver,narrow,body_step}.hpp): the
// properties World's loops rely on when they call them.
#include <gtest/gtest.h>
#include <cstdint>
#include <type_traits>
#include <vector>
#include <rapidcheck/gtest.h>

#include "engine_types.hpp"
#include "lockstep/physics/body_step.hpp"
#include "lockstep/physics/narrow.hpp"
#include "lockstep/fixed/q16_num.hpp"
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

// The still side (kStillSide, solve_manifold_rows' kImmovableB): in Q16.16
// an immovable side's terms are exact zeros, so a visit that leaves them out
// gives the bits of the full visit, and the same status flags. Generated:
// a tilted box of any mass, size and velocity, sunk at any depth into the
// ground (some corners no contact), its corners' states warm-started from
// any impulses, friction on or off, several passes, rows formed once (as
// World<T> and gpu-fixed do); the flags raised, overflow included, must
// match too (huge speeds saturate on purpose now and then).
RC_GTEST_PROP(SharedStepsProp, StillSideGivesTheFullVisitsBitsInQ16, ()) {
  using T = Q16;
  auto num = [](double lo, double hi) {
    return Num<T>::from_double(lo + (hi - lo) * *rc::gen::inRange(0, 1 << 20) / static_cast<double>(1 << 20));
  };
  auto v3 = [&](double lo, double hi) { return Vec3<T>{num(lo, hi), num(lo, hi), num(lo, hi)}; };
  const Params<T> P = Params<T>::from(Constants{});
  const double speed = *rc::gen::element(3.0, 30.0, 3000.0);
  const Vec3<T> half = v3(0.05, 2.0);
  const T inv_mass = num(0.01, 20.0);
  const Vec3<T> axis = v3(-1, 1);
  const Quat<T> q = normalize(Quat<T>{num(0.2, 1.0), axis.x, axis.y, axis.z});
  const BodyView<T> start = dynamic_view(v3(-speed, speed), v3(-speed, speed), inv_mass, rotation_matrix(q),
                                         box_inverse_inertia(half, inv_mass, Num<T>::from_int(3)));
  const BodyView<T> ground = immovable_view<T>();
  const T ground_y = num(-0.5, 0.5) + half.y;
  const Vec3<T> p{T{}, T{}, T{}};
  const Vec3<T> up{T{}, Num<T>::from_int(1), T{}};
  const bool friction = *rc::gen::arbitrary<bool>();
  // The 8 corners (eq 84): a contact when within 2 cm of the plane.
  Vec3<T> r1[8];
  T depth[8];
  bool contact[8];
  ContactState<T> states[8];
  ContactRows<T> rows[8];
  Num<T>::take_faults();
  for (int k = 0; k < 8; ++k) {
    Vec3<T> corner;
    depth[k] = ground_corner_depth(p, start.R, half, k, ground_y, corner);
    r1[k] = corner - p;
    contact[k] = depth[k] > -Num<T>::from_double(0.02);
    SolveCounts prep;
    states[k] = prepare_contact(start, r1[k], ground, Vec3<T>{}, up, num(0, 0.5), num(0, 1), num(0, 0.5), num(0, 1), true,
                                friction, P, prep);
    states[k].j_n = num(0, 3);
    states[k].j_t = *rc::gen::arbitrary<bool>() ? v3(-1, 1) : Vec3<T>{};
    rows[k] = contact_rows(start, r1[k], ground, Vec3<T>{}, up, states[k].k_n);
  }
  Num<T>::take_faults();
  auto run = [&](auto still) {
    constexpr bool kStill = decltype(still)::value;
    BodyView<T> A = start, B = ground;
    ContactState<T> st[8];
    for (int k = 0; k < 8; ++k) st[k] = states[k];
    auto point = [&](int k, Vec3<T>& a, Vec3<T>& b, Vec3<T>& n, T& pen) {
      a = r1[k], b = Vec3<T>{}, n = up, pen = depth[k];
      return contact[k];
    };
    auto row = [&](int k) -> const ContactRows<T>& { return rows[k]; };
    auto load = [&](int k) { return st[k]; };
    auto store = [&](int k, const ContactState<T>& c) { st[k] = c; };
    SolveCounts counts;
    std::uint32_t flags = 0;
    for (int pass = 0; pass < 4; ++pass) {
      solve_manifold_rows<8, false, kStill>(A, B, point, row, load, store, friction, true, Num<T>::from_int(1), P,
                                            counts);
      flags |= Num<T>::take_faults();
    }
    std::vector<std::int64_t> bits;
    for (int a = 0; a < 3; ++a)
      for (const T& x : {A.v[a], A.w[a], B.v[a], B.w[a]}) bits.push_back(x.raw());
    for (const ContactState<T>& c : st)
      for (const T& x : {c.j_n, c.j_t.x, c.j_t.y, c.j_t.z}) bits.push_back(x.raw());
    for (const std::uint32_t x : {flags, counts.solver_contacts, counts.normal_impulses, counts.friction_steps,
                                  counts.shortened_steps})
      bits.push_back(x);
    return bits;
  };
  const std::vector<std::int64_t> full = run(std::false_type{}), still = run(std::true_type{});
  RC_ASSERT(full == still);
  int contacts = 0;
  for (bool c : contact) contacts += c ? 1 : 0;
  RC_TAG(full[full.size() - 5] != 0 ? "flags raised" : "no flags", contacts == 0 ? "no contact" : contacts == 1 ? "1 point" : "2-8 points");
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
