// docs/SPEC.md Appendix B: raycast, AABB overlap, point query, body state.
#include <gtest/gtest.h>

#include <cmath>

#include "engine_types.hpp"

namespace lockstep::test {
namespace {

template <class T>
class QueriesTest : public ::testing::Test {};
using QueryTypes = ::testing::Types<Q16, double>;
TYPED_TEST_SUITE(QueriesTest, QueryTypes);

template <class T>
Vec3<T> v3(double x, double y, double z) { return {Num<T>::from_double(x), Num<T>::from_double(y), Num<T>::from_double(z)}; }

// Three cubes on the x axis; the middle one turned 45 degrees about y.
Scene row_of_three() {
  Scene s;
  s.bodies.push_back(unit_cube(0, 0.5, 0));
  BodyDesc turned = unit_cube(3, 0.5, 0);
  turned.orientation = {0.9238795325112867, 0, 0.3826834323650898, 0};
  s.bodies.push_back(turned);
  s.bodies.push_back(unit_cube(6, 0.5, 0));
  return s;
}

TYPED_TEST(QueriesTest, RaycastHitsTheFirstBoxWithItsFaceNormal) {
  using T = TypeParam;
  World<T> w(row_of_three());
  const RayHit<T> hit = w.raycast(v3<T>(-5, 0.5, 0), v3<T>(1, 0, 0), Num<T>::from_double(100));
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.body, 0);
  EXPECT_NEAR(d(hit.distance), 4.5, 1e-4);
  EXPECT_NEAR(d(hit.normal.x), -1.0, 1e-4);
  // From between body 0 and 1: the turned cube's corner is sqrt(0.5) from its centre.
  const RayHit<T> h2 = w.raycast(v3<T>(1.0, 0.5, 0), v3<T>(1, 0, 0), Num<T>::from_double(100));
  ASSERT_TRUE(h2.hit);
  EXPECT_EQ(h2.body, 1);
  EXPECT_NEAR(d(h2.distance), 2.0 - std::sqrt(0.5), 1e-3);
}

TYPED_TEST(QueriesTest, RaycastDownHitsTheGroundAndRespectsMaxDistance) {
  using T = TypeParam;
  World<T> w(row_of_three());
  const RayHit<T> g = w.raycast(v3<T>(10, 5, 0), v3<T>(0, -1, 0), Num<T>::from_double(100));
  ASSERT_TRUE(g.hit);
  EXPECT_EQ(g.body, -1);
  EXPECT_NEAR(d(g.distance), 5.0, 1e-4);
  EXPECT_FALSE(w.raycast(v3<T>(10, 5, 0), v3<T>(0, -1, 0), Num<T>::from_double(4)).hit);
  EXPECT_FALSE(w.raycast(v3<T>(10, 5, 0), v3<T>(0, 1, 0), Num<T>::from_double(100)).hit);
}

TYPED_TEST(QueriesTest, OverlapAabbReturnsAscendingIndices) {
  using T = TypeParam;
  World<T> w(row_of_three());
  EXPECT_EQ(w.overlap_aabb(v3<T>(-1, 0, -1), v3<T>(3, 1, 1)), (std::vector<int>{0, 1}));
  EXPECT_EQ(w.overlap_aabb(v3<T>(1.0, 0, -1), v3<T>(2.2, 1, 1)), (std::vector<int>{}));  // the gap between 0 and 1
  // Body 1's AABB (eq 31) is 3 +- sqrt(0.5) in x, wider than the turned box.
  EXPECT_EQ(w.overlap_aabb(v3<T>(2.2, 0, -1), v3<T>(2.35, 1, 1)), (std::vector<int>{1}));
  EXPECT_EQ(w.overlap_aabb(v3<T>(-10, -10, -10), v3<T>(10, 10, 10)), (std::vector<int>{0, 1, 2}));
}

TYPED_TEST(QueriesTest, PointQueryUsesTheOrientedBox) {
  using T = TypeParam;
  World<T> w(row_of_three());
  EXPECT_EQ(w.point_query(v3<T>(0.4, 0.9, 0.4)), (std::vector<int>{0}));
  // Inside body 1's AABB (half sqrt(0.5) in x) but outside its turned box.
  EXPECT_EQ(w.point_query(v3<T>(3.6, 0.5, 0.3)), (std::vector<int>{}));
  EXPECT_EQ(w.point_query(v3<T>(3.6, 0.5, 0.0)), (std::vector<int>{1}));
}

TYPED_TEST(QueriesTest, BodyStateAndSleepState) {
  using T = TypeParam;
  Scene s;
  s.bodies.push_back(unit_cube(0, 0.5, 0));
  World<T> w(s);
  while (!w.body(0).asleep && w.frame() < 200) w.step();
  ASSERT_TRUE(w.body(0).asleep);
  EXPECT_EQ(w.body(0).sleep_frame, w.frame());
  EXPECT_GE(w.body(0).sleep_counter, s.constants.sleep_frames);
  w.wake(0);
  EXPECT_FALSE(w.body(0).asleep);
  EXPECT_EQ(w.body(0).sleep_counter, 0);
}

}  // namespace
}  // namespace lockstep::test
