// lockstep/eigen.hpp: lockstep's bodies, scenes and queries in the types an
// Eigen user already has (Eigen::Vector3d, Quaterniond, Isometry3d,
// AlignedBox3d). Optional and header-only: include it only where Eigen 3.3 or
// later is found (find_package(Eigen3) and link Eigen3::Eigen next to
// lockstep::reference); nothing else in lockstep includes it, and lockstep
// itself neither needs nor finds Eigen. The engines keep their own Vec3,
// Quat and Mat3 of the number type T; these functions convert at the
// boundary, through double, as Appendix B's queries do:
//
//  * lockstep -> Eigen is exact for Q16, float and double (every value is a
//    double); mp rounds to double.
//  * Eigen -> lockstep rounds each double to T (Q16: to nearest, ties to
//    even, eq 22). A value that is not finite, or outside Q16.16's range for
//    World<Q16>, throws std::invalid_argument naming the field and the value,
//    instead of becoming a saturated or NaN state.
//
// Conventions: Quaterniond(w, x, y, z) is lockstep's w + xi + yj + zk
// (Hamilton, active: v' = q v q*); a body's pose maps body coordinates to
// world ones, x_world = pose * x_body, with the box spanning [-h, h] in body
// coordinates.
#pragma once
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "lockstep/scene.hpp"
#include "lockstep/world.hpp"

namespace lockstep::eigen {

// ---- lockstep -> Eigen --------------------------------------------------------

template <class T>
Eigen::Vector3d to_eigen(const Vec3<T>& v) {
  return {Num<T>::to_double(v.x), Num<T>::to_double(v.y), Num<T>::to_double(v.z)};
}
template <class T>
Eigen::Quaterniond to_eigen(const Quat<T>& q) {
  return {Num<T>::to_double(q.w), Num<T>::to_double(q.x), Num<T>::to_double(q.y), Num<T>::to_double(q.z)};
}
template <class T>
Eigen::Matrix3d to_eigen(const Mat3<T>& m) {
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = Num<T>::to_double(m.row[i][j]);
  return r;
}
inline Eigen::Vector3d to_eigen(const Vec3d& v) { return {v.x, v.y, v.z}; }
inline Eigen::Quaterniond to_eigen(const Quatd& q) { return {q.w, q.x, q.y, q.z}; }

// ---- Eigen -> lockstep --------------------------------------------------------

namespace detail {

// `value` checked for T: finite, and within Q16.16's range for Q16 (a larger
// value would saturate). `where` names the field, e.g. "raycast: origin.y".
template <class T>
T number(double value, const std::string& where) {
  if (!std::isfinite(value))
    throw std::invalid_argument("lockstep::eigen::" + where + " = " + std::to_string(value) +
                                " is not finite; pass a finite number");
  if constexpr (Num<T>::kExact) {
    if (!(value >= -32768.0 && value < 32768.0))
      throw std::invalid_argument("lockstep::eigen::" + where + " = " + std::to_string(value) +
                                  " is outside the range of Q16.16, [-32768, 32768); scale the scene "
                                  "or use World<double>");
  }
  return Num<T>::from_double(value);
}

inline const char* axis_name(int i) { return i == 0 ? ".x" : (i == 1 ? ".y" : ".z"); }

// A pose's rotation, checked: orthonormal to 1e-9 and not a reflection.
inline Eigen::Quaterniond rotation_of(const Eigen::Isometry3d& pose, const std::string& where) {
  const Eigen::Matrix3d R = pose.linear();
  const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double det = R.determinant();
  if (!std::isfinite(off) || off > 1e-9 || det < 0)
    throw std::invalid_argument("lockstep::eigen::" + where + ".linear() is not a rotation (max |R^T R - I| = " +
                                std::to_string(off) + ", det = " + std::to_string(det) +
                                "); build the pose from a unit quaternion or an AngleAxis, without scale, "
                                "shear or reflection");
  for (int i = 0; i < 3; ++i) number<double>(pose.translation()[i], where + ".translation()" + axis_name(i));
  return Eigen::Quaterniond(R).normalized();
}

template <class T>
void check_body(const World<T>& world, int i, const char* where) {
  const int n = static_cast<int>(world.bodies().size());
  if (i < 0 || i >= n)
    throw std::out_of_range(std::string("lockstep::eigen::") + where + ": body " + std::to_string(i) +
                            " does not exist; the world has bodies 0 to " + std::to_string(n - 1));
}

}  // namespace detail

// An Eigen vector in T; `field` names it in the error (see the top).
template <class T>
Vec3<T> to_vec3(const Eigen::Vector3d& v, const std::string& field = "to_vec3: v") {
  return {detail::number<T>(v.x(), field + ".x"), detail::number<T>(v.y(), field + ".y"),
          detail::number<T>(v.z(), field + ".z")};
}
template <class T>
Quat<T> to_quat(const Eigen::Quaterniond& q, const std::string& field = "to_quat: q") {
  return {detail::number<T>(q.w(), field + ".w"), detail::number<T>(q.x(), field + ".x"),
          detail::number<T>(q.y(), field + ".y"), detail::number<T>(q.z(), field + ".z")};
}

// ---- A body's state ------------------------------------------------------------

// Appendix B's body_state, in Eigen types.
struct BodyState {
  Eigen::Vector3d position;          // p (m)
  Eigen::Quaterniond orientation;    // q (unit)
  Eigen::Vector3d velocity;          // v (m/s)
  Eigen::Vector3d angular_velocity;  // omega (rad/s, world frame)
  Eigen::Vector3d half_extents;      // h (m)
  bool is_static = false;
  bool asleep = false;
  int sleep_counter = 0;             // eq 78
  int sleep_frame = -1;              // the frame it last fell asleep (eq 80), -1 if never
};

template <class T>
BodyState state(const Body<T>& b) {
  BodyState s;
  s.position = to_eigen(b.p);
  s.orientation = to_eigen(b.q);
  s.velocity = to_eigen(b.v);
  s.angular_velocity = to_eigen(b.w);
  s.half_extents = to_eigen(b.half);
  s.is_static = b.is_static;
  s.asleep = b.asleep;
  s.sleep_counter = b.sleep_counter;
  s.sleep_frame = b.sleep_frame;
  return s;
}
template <class T>
BodyState state(const World<T>& world, int i) {
  detail::check_body(world, i, "state");
  return state(world.body(i));
}

// A body's pose: x_world = pose * x_body (its orientation normalised in
// double; lockstep keeps it unit to within a few ulps of T).
template <class T>
Eigen::Isometry3d pose(const Body<T>& b) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = to_eigen(b.q).normalized().toRotationMatrix();
  iso.translation() = to_eigen(b.p);
  return iso;
}
// Every body's pose, in body order.
template <class T>
std::vector<Eigen::Isometry3d> poses(const World<T>& world) {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(world.bodies().size());
  for (const Body<T>& b : world.bodies()) out.push_back(pose(b));
  return out;
}

// Replaces body i's velocities (and wakes it), as World::set_velocity.
template <class T>
void set_velocity(World<T>& world, int i, const Eigen::Vector3d& v, const Eigen::Vector3d& omega) {
  detail::check_body(world, i, "set_velocity");
  world.set_velocity(i, to_vec3<T>(v, "set_velocity: v"), to_vec3<T>(omega, "set_velocity: omega"));
}

// ---- A scene's poses -----------------------------------------------------------

// A scene body's initial pose (its orientation normalised, as the loader
// does, eq 10).
inline Eigen::Isometry3d pose(const BodyDesc& b) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = to_eigen(b.orientation).normalized().toRotationMatrix();
  iso.translation() = to_eigen(b.position);
  return iso;
}
inline std::vector<Eigen::Isometry3d> poses(const Scene& scene) {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(scene.bodies.size());
  for (const BodyDesc& b : scene.bodies) out.push_back(pose(b));
  return out;
}
// Sets a scene body's initial position and orientation from a rigid pose;
// throws std::invalid_argument when pose.linear() is not a rotation.
inline void set_pose(BodyDesc& b, const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q = detail::rotation_of(pose, "set_pose: pose");
  b.position = {pose.translation().x(), pose.translation().y(), pose.translation().z()};
  b.orientation = {q.w(), q.x(), q.y(), q.z()};
}

// ---- Queries (docs/SPEC.md Appendix B) -----------------------------------------

struct RayHit {
  bool hit = false;
  int body = -2;                 // -1: the ground; -2: no hit
  double distance = 0;           // the ray parameter t, in units of |dir|
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // origin + dir * distance
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // the entry face's outward normal
};

template <class T>
RayHit to_eigen(const lockstep::RayHit<T>& h) {
  RayHit r;
  r.hit = h.hit;
  r.body = h.body;
  r.distance = Num<T>::to_double(h.distance);
  r.point = to_eigen(h.point);
  r.normal = to_eigen(h.normal);
  return r;
}

template <class T>
RayHit raycast(const World<T>& world, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
               double max_distance) {
  return to_eigen(world.raycast(to_vec3<T>(origin, "raycast: origin"), to_vec3<T>(dir, "raycast: dir"),
                                detail::number<T>(max_distance, "raycast: max_distance")));
}
// The bodies whose world AABB (eqs 29-31) overlaps `box` (closed), ascending.
template <class T>
std::vector<int> overlap(const World<T>& world, const Eigen::AlignedBox3d& box) {
  if (box.isEmpty())
    throw std::invalid_argument("lockstep::eigen::overlap: box is empty (min > max on some axis); pass a box "
                                "with min <= max, e.g. Eigen::AlignedBox3d(lo, hi)");
  return world.overlap_aabb(to_vec3<T>(box.min(), "overlap: box.min()"), to_vec3<T>(box.max(), "overlap: box.max()"));
}
// The bodies whose oriented box contains p (the surface counts), ascending.
template <class T>
std::vector<int> point_query(const World<T>& world, const Eigen::Vector3d& p) {
  return world.point_query(to_vec3<T>(p, "point_query: p"));
}

}  // namespace lockstep::eigen
