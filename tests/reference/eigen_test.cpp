// lockstep/eigen.hpp: a body's state, a scene's poses and the Appendix B
// queries to and from Eigen types, on Q16 and double (issue 16).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "engine_types.hpp"
#include "fixed/prop.hpp"
#include "lockstep/eigen.hpp"
#include "lockstep/physics/aabb.hpp"

namespace lockstep::test {
namespace {

template <class T>
class EigenHeader : public ::testing::Test {};
using HeaderTypes = ::testing::Types<Q16, double>;
TYPED_TEST_SUITE(EigenHeader, HeaderTypes);

template <class T>
double pos_tol() { return std::is_same_v<T, Q16> ? 1e-4 : 1e-12; }

// Four cubes, three of them turned (45 degrees about y, 30 about a skew
// axis, 180 about x), set from Eigen poses; the world stepped 20 frames so
// that the states are the engine's, not the scene's.
template <class T>
World<T> turned_world() {
  Scene s;
  const Eigen::Isometry3d poses[4] = {
      Eigen::Translation3d(0, 0.5, 0) * Eigen::Isometry3d::Identity(),
      Eigen::Translation3d(3, 0.5, 0) * Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()),
      Eigen::Translation3d(6, 2, 0.5) * Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d(1, 2, 3).normalized()),
      Eigen::Translation3d(-3, 1, 1) * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())};
  for (const Eigen::Isometry3d& p : poses) {
    BodyDesc b;
    b.half_extents = {0.5, 0.3, 0.2};
    eigen::set_pose(b, p);
    s.bodies.push_back(b);
  }
  World<T> w(s);
  for (int f = 0; f < 20; ++f) w.step();
  return w;
}

// The quaternion's components keep their names: Eigen stores (x, y, z, w)
// but Quaterniond(w, x, y, z) and q.w() are lockstep's w.
TEST(EigenHeaderConversion, QuaternionComponentsKeepTheirNames) {
  const Eigen::Quaterniond e = eigen::to_eigen(Quat<double>{0.1, 0.2, 0.3, 0.4});
  EXPECT_EQ(e.w(), 0.1);
  EXPECT_EQ(e.x(), 0.2);
  EXPECT_EQ(e.y(), 0.3);
  EXPECT_EQ(e.z(), 0.4);
  const Quat<Q16> q = eigen::to_quat<Q16>(Eigen::Quaterniond(0.5, -0.5, 0.25, 1.0 / 65536));
  EXPECT_EQ(q.w.raw(), 32768);
  EXPECT_EQ(q.x.raw(), -32768);
  EXPECT_EQ(q.y.raw(), 16384);
  EXPECT_EQ(q.z.raw(), 1);
}

// Q16 and double vectors and quaternions go to Eigen and back bit for bit
// (every Q16 is a double); a Q16 matrix's entries are exact doubles.
TEST(EigenHeaderConversion, RoundTripIsExact) {
  lockstep_test::check_prop([] {
    auto raw = [] { return Q16::from_raw(*rc::gen::arbitrary<std::int32_t>()); };
    const Vec3<Q16> v{raw(), raw(), raw()};
    const Quat<Q16> q{raw(), raw(), raw(), raw()};
    RC_ASSERT(eigen::to_vec3<Q16>(eigen::to_eigen(v)) == v);
    RC_ASSERT(eigen::to_quat<Q16>(eigen::to_eigen(q)) == q);
    const Vec3<double> d{*rc::gen::arbitrary<double>(), 1.0 / 3, -0.0};
    if (std::isfinite(d.x)) RC_ASSERT(eigen::to_vec3<double>(eigen::to_eigen(d)) == d);
    const Mat3<Q16> m{{v, {q.w, q.x, q.y}, {q.z, v.y, v.x}}};
    const Eigen::Matrix3d e = eigen::to_eigen(m);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) RC_ASSERT(e(i, j) * 65536 == m.row[i][j].raw());
  }, 2000);
}

// A body's pose maps its body-frame corners onto the engine's own world
// corners (eq 84's box_corner, through the engine's R): the pose's
// convention (x_world = pose * x_body, q not q*) and the component order.
TYPED_TEST(EigenHeader, PoseMapsBodyCornersToTheEnginesCorners) {
  using T = TypeParam;
  const World<T> w = turned_world<T>();
  const std::vector<Eigen::Isometry3d> poses = eigen::poses(w);
  ASSERT_EQ(poses.size(), w.bodies().size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Body<T>& b = w.body(static_cast<int>(i));
    const Eigen::Vector3d h = eigen::to_eigen(b.half);
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d local((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
      const Eigen::Vector3d want = eigen::to_eigen(box_corner(b.p, b.R, b.half, k));
      EXPECT_LT((poses[i] * local - want).cwiseAbs().maxCoeff(), 8 * pos_tol<T>()) << "body " << i << " corner " << k;
    }
    // The state is the engine's, component by component.
    const eigen::BodyState s = eigen::state(w, static_cast<int>(i));
    EXPECT_EQ(s.position, eigen::to_eigen(b.p));
    EXPECT_EQ(s.orientation.coeffs(), eigen::to_eigen(b.q).coeffs());
    EXPECT_EQ(s.velocity, eigen::to_eigen(b.v));
    EXPECT_EQ(s.angular_velocity, eigen::to_eigen(b.w));
    EXPECT_EQ(s.asleep, b.asleep);
    EXPECT_EQ(s.sleep_frame, b.sleep_frame);
  }
}

// A scene pose set from Eigen is the pose the world starts with.
TYPED_TEST(EigenHeader, ScenePoseRoundTrip) {
  using T = TypeParam;
  const Eigen::Isometry3d p = Eigen::Translation3d(1.25, 2.5, -3) *
                              Eigen::AngleAxisd(2.0, Eigen::Vector3d(-1, 0.5, 2).normalized());
  BodyDesc b;
  eigen::set_pose(b, p);
  EXPECT_LT((eigen::pose(b).matrix() - p.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  Scene s = bare_scene();
  s.bodies.push_back(b);
  EXPECT_LT((eigen::poses(s)[0].matrix() - p.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  const World<T> w(s);
  EXPECT_LT((eigen::pose(w.body(0)).matrix() - p.matrix()).cwiseAbs().maxCoeff(), 4 * pos_tol<T>());
}

// Velocities set from Eigen move the body as the engine's own set_velocity.
TYPED_TEST(EigenHeader, SetVelocityEqualsTheEngines) {
  using T = TypeParam;
  Scene s = bare_scene();
  s.bodies.push_back(unit_cube(0, 5, 0));
  World<T> a(s), b(s);
  eigen::set_velocity(a, 0, Eigen::Vector3d(1, 0.5, -2), Eigen::Vector3d(0, 3, 0.25));
  b.set_velocity(0, {Num<T>::from_double(1), Num<T>::from_double(0.5), Num<T>::from_double(-2)},
                 {T{}, Num<T>::from_double(3), Num<T>::from_double(0.25)});
  for (int f = 0; f < 10; ++f) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.state_hash(), b.state_hash());
}

// The queries through Eigen return what the engine's queries return, and
// the ray's hit point and normal are those of the turned boxes.
TYPED_TEST(EigenHeader, QueriesEqualTheEngines) {
  using T = TypeParam;
  const World<T> w = turned_world<T>();
  auto v = [](double x, double y, double z) { return Vec3<T>{Num<T>::from_double(x), Num<T>::from_double(y), Num<T>::from_double(z)}; };
  // Per body: straight down onto its centre, and slanting into it from the
  // side; then a ray onto the ground and one into the sky.
  std::vector<std::array<double, 6>> rays;
  for (const Eigen::Isometry3d& p : eigen::poses(w)) {
    const Eigen::Vector3d c = p.translation(), o = c + Eigen::Vector3d(-4, 1, 0.5), d = c - o;
    rays.push_back({c.x(), c.y() + 5, c.z(), 0, -1, 0});
    rays.push_back({o.x(), o.y(), o.z(), d.x(), d.y(), d.z()});
  }
  rays.push_back({10, 5, 10, 0, -1, 0});
  rays.push_back({0, 5, 0, 0, 1, 0});
  int body_hits = 0;
  for (std::size_t k = 0; k < rays.size(); ++k) {
    const std::array<double, 6>& r = rays[k];
    const eigen::RayHit got = eigen::raycast(w, Eigen::Vector3d(r[0], r[1], r[2]), Eigen::Vector3d(r[3], r[4], r[5]), 100);
    const RayHit<T> want = w.raycast(v(r[0], r[1], r[2]), v(r[3], r[4], r[5]), Num<T>::from_double(100));
    EXPECT_EQ(got.hit, want.hit);
    EXPECT_EQ(got.body, want.body);
    EXPECT_EQ(got.distance, Num<T>::to_double(want.distance));
    EXPECT_EQ(got.point, eigen::to_eigen(want.point));
    EXPECT_EQ(got.normal, eigen::to_eigen(want.normal));
    if (k < 2 * w.bodies().size() && k % 2 == 0) {
      EXPECT_EQ(got.body, static_cast<int>(k / 2));  // straight down onto body i hits body i
      ++body_hits;
    }
    if (got.hit && got.body >= 0) {
      // The hit point is on the box surface the normal names, in its frame.
      const Eigen::Isometry3d p = eigen::pose(w.body(got.body));
      const Eigen::Vector3d local = p.inverse() * got.point, n_local = p.linear().transpose() * got.normal;
      const Eigen::Vector3d h = eigen::to_eigen(w.body(got.body).half);
      int a = 0;
      n_local.cwiseAbs().maxCoeff(&a);
      EXPECT_NEAR(std::fabs(n_local[a]), 1.0, 1e-3);
      EXPECT_NEAR(local[a] * (n_local[a] > 0 ? 1 : -1), h[a], 1e-3);
    }
  }
  EXPECT_EQ(body_hits, 4);
  EXPECT_EQ(eigen::raycast(w, Eigen::Vector3d(10, 5, 10), Eigen::Vector3d(0, -1, 0), 100).body, -1);  // the ground
  EXPECT_FALSE(eigen::raycast(w, Eigen::Vector3d(0, 5, 0), Eigen::Vector3d(0, 1, 0), 100).hit);
  const Eigen::AlignedBox3d boxes[] = {{Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(3, 1, 1)},
                                       {Eigen::Vector3d(-10, -10, -10), Eigen::Vector3d(10, 10, 10)},
                                       {Eigen::Vector3d(1, 0, -1), Eigen::Vector3d(2.2, 1, 1)}};
  for (const Eigen::AlignedBox3d& b : boxes)
    EXPECT_EQ(eigen::overlap(w, b), w.overlap_aabb(eigen::to_vec3<T>(b.min()), eigen::to_vec3<T>(b.max())));
  for (std::size_t i = 0; i < w.bodies().size(); ++i) {
    // Each body's centre is in its own box; a point 0.35 m along its body x is
    // inside (h_x = 0.5) and along its body z is not (h_z = 0.2).
    const Eigen::Isometry3d p = eigen::pose(w.body(static_cast<int>(i)));
    const auto has = [&](const std::vector<int>& l) { return std::find(l.begin(), l.end(), static_cast<int>(i)) != l.end(); };
    EXPECT_TRUE(has(eigen::point_query(w, p.translation()))) << i;
    EXPECT_TRUE(has(eigen::point_query(w, p * Eigen::Vector3d(0.35, 0, 0)))) << i;
    EXPECT_FALSE(has(eigen::point_query(w, p * Eigen::Vector3d(0, 0, 0.35)))) << i;
    EXPECT_EQ(eigen::point_query(w, p * Eigen::Vector3d(0.35, 0, 0)),
              w.point_query(eigen::to_vec3<T>(p * Eigen::Vector3d(0.35, 0, 0))));
  }
}

// Bad input: a clear error naming the field, the value and the fix.
template <class E, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "(no error)";
}

TYPED_TEST(EigenHeader, BadInputNamesTheFieldTheValueAndTheFix) {
  using T = TypeParam;
  World<T> w = turned_world<T>();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::string msg = error_of<std::invalid_argument>(
      [&] { eigen::raycast(w, Eigen::Vector3d(0, nan, 0), Eigen::Vector3d(0, -1, 0), 10); });
  EXPECT_NE(msg.find("raycast: origin.y = nan is not finite"), std::string::npos) << msg;
  msg = error_of<std::invalid_argument>([&] { eigen::point_query(w, Eigen::Vector3d(0, 0, INFINITY)); });
  EXPECT_NE(msg.find("point_query: p.z = inf"), std::string::npos) << msg;
  msg = error_of<std::out_of_range>([&] { eigen::set_velocity(w, 4, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()); });
  EXPECT_NE(msg.find("set_velocity: body 4 does not exist; the world has bodies 0 to 3"), std::string::npos) << msg;
  msg = error_of<std::invalid_argument>([&] { eigen::overlap(w, Eigen::AlignedBox3d()); });
  EXPECT_NE(msg.find("overlap: box is empty"), std::string::npos) << msg;
  msg = error_of<std::invalid_argument>(
      [&] { eigen::raycast(w, Eigen::Vector3d(40000, 0, 0), Eigen::Vector3d(0, -1, 0), 10); });
  if constexpr (std::is_same_v<T, Q16>)
    EXPECT_NE(msg.find("raycast: origin.x = 40000.000000 is outside the range of Q16.16"), std::string::npos) << msg;
  else
    EXPECT_EQ(msg, "(no error)");
  // A pose with a scale or a reflection is not a rigid pose.
  BodyDesc b;
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 2;
  msg = error_of<std::invalid_argument>([&] { eigen::set_pose(b, scaled); });
  EXPECT_NE(msg.find("set_pose: pose.linear() is not a rotation"), std::string::npos) << msg;
  Eigen::Isometry3d mirrored = Eigen::Isometry3d::Identity();
  mirrored.linear()(0, 0) = -1;
  msg = error_of<std::invalid_argument>([&] { eigen::set_pose(b, mirrored); });
  EXPECT_NE(msg.find("det = -1"), std::string::npos) << msg;
  EXPECT_EQ(b.position.x, 0.0);  // untouched by the failed calls
}

}  // namespace
}  // namespace lockstep::test
