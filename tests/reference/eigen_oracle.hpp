// The independent oracle of lockstep's math layer (issue 16): Eigen's
// Quaternion, AngleAxis and Matrix3 instantiated on a 160-bit
// Boost.Multiprecision float (Eigen takes it through the NumTraits of
// boost/multiprecision/eigen.hpp), the inputs that stress lockstep's math
// (random unit quaternions with 180-degree turns, 45-degree ties and tiny
// angles; boxes), and each number type's rounding model, so that every test
// states its bound in ulps (1 ulp = the type's epsilon: 2^-16 for Q16.16,
// 2^-23 float, 2^-52 double, 2^-112 mp).
//
// The oracle shares no code with lockstep: every lockstep value enters it
// exactly (a Q16, float, double or 113-bit mp number is exact in 160 bits),
// and it computes with Eigen's own formulas (Hamilton product, the
// quaternion-to-matrix conversion, Rodrigues' formula of AngleAxis, the
// cofactor inverse of a Matrix3) at 160 bits, whose own error (< 2^-150 on
// these magnitudes) is below every bound by 30 bits and more.
#pragma once
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <boost/multiprecision/eigen.hpp>
#include <Eigen/Geometry>

#include <rapidcheck.h>

#include <cmath>
#include <type_traits>

#include "engine_types.hpp"

namespace lockstep::test::oracle {

using O = boost::multiprecision::number<
    boost::multiprecision::cpp_bin_float<160, boost::multiprecision::digit_base_2>, boost::multiprecision::et_off>;
using V3 = Eigen::Matrix<O, 3, 1>;
using M3 = Eigen::Matrix<O, 3, 3>;
using Q = Eigen::Quaternion<O>;
using AA = Eigen::AngleAxis<O>;

// A lockstep number, exactly.
template <class T>
O exact(const T& x) {
  if constexpr (std::is_same_v<T, Mp>) return O(x);
  else return O(Num<T>::to_double(x));
}
template <class T>
V3 exact(const Vec3<T>& v) { return V3(exact(v.x), exact(v.y), exact(v.z)); }
template <class T>
Q exact(const Quat<T>& q) { return Q(exact(q.w), exact(q.x), exact(q.y), exact(q.z)); }
template <class T>
M3 exact(const Mat3<T>& m) {
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = exact(m.row[i][j]);
  return r;
}

// An oracle value rounded into T (the inputs lockstep is given).
template <class T>
T round_to(const O& x) {
  if constexpr (std::is_same_v<T, Mp>) return Mp(x);
  else return Num<T>::from_double(x.convert_to<double>());
}
template <class T>
Vec3<T> round_to(const V3& v) { return {round_to<T>(v.x()), round_to<T>(v.y()), round_to<T>(v.z())}; }
template <class T>
Quat<T> round_to(const Q& q) { return {round_to<T>(q.w()), round_to<T>(q.x()), round_to<T>(q.y()), round_to<T>(q.z())}; }

inline double dbl(const O& x) { return x.convert_to<double>(); }
inline double norm1(const V3& v) { return dbl(abs(v.x()) + abs(v.y()) + abs(v.z())); }

// The rounding model of T. Floating types (float, double, mp: binary, round
// to nearest) follow the standard model fl(a op b) = (a op b)(1 + d),
// |d| <= u = eps/2, and sums of n products have the gamma_n = n u / (1 - n u)
// bound; Q16 follows fixed/README.md: every operation (every accumulator
// component) rounds once, to nearest: an absolute error <= 1/2 ulp.
template <class T>
struct Model {
  static constexpr bool kFixed = std::is_same_v<T, Q16>;
  static double eps() {
    if constexpr (std::is_same_v<T, Q16>) return std::ldexp(1.0, -16);
    else if constexpr (std::is_same_v<T, float>) return std::ldexp(1.0, -23);
    else if constexpr (std::is_same_v<T, double>) return std::ldexp(1.0, -52);
    else return std::ldexp(1.0, -112);
  }
  // gamma_n in units of eps (n u / (1 - n u) / eps), for the floating types.
  static double gamma(int n) { return n * 0.5 / (1 - n * 0.5 * eps()); }
  // The oracle's own error allowance (absolute, per unit of magnitude).
  static double oracle() { return std::ldexp(1.0, -140); }
};

// Random reals from integers, so that rapidcheck shrinks towards 0 / lo.
inline double real(double lo, double hi) { return lo + (hi - lo) * *rc::gen::inRange(0, 1000001) / 1e6; }
inline double log_uniform(double lo, double hi) { return std::exp(real(std::log(lo), std::log(hi))); }

// An axis: random, a coordinate axis, or a face / space diagonal, each with
// either sign.
inline V3 gen_axis() {
  V3 a;
  switch (*rc::gen::inRange(0, 4)) {
    case 0: {
      do a = V3(O(real(-1, 1)), O(real(-1, 1)), O(real(-1, 1)));
      while (a.norm() < O(0.1));
      break;
    }
    case 1: a = V3::Unit(*rc::gen::inRange(0, 3)); break;
    case 2: {
      const int k = *rc::gen::inRange(0, 3);
      a = V3::Ones();
      a[k] = O(0);
      break;
    }
    default: a = V3::Ones(); break;
  }
  for (int i = 0; i < 3; ++i)
    if (*rc::gen::arbitrary<bool>()) a[i] = -a[i];
  return a.normalized();
}

// A rotation, as the exact angle and axis: uniform angles; 180-degree turns
// (w near 0); multiples of 45 degrees (the ties of eqs 40, 65 and 100-103);
// tiny angles (q near the identity, down to below Q16's resolution); the
// identity. Each perturbed by 0 or a tiny angle.
inline AA gen_rotation() {
  const O pi = boost::math::constants::pi<O>();
  const O nudge = *rc::gen::arbitrary<bool>() ? O(0) : O(log_uniform(1e-9, 1e-3)) * (*rc::gen::arbitrary<bool>() ? 1 : -1);
  O angle;
  switch (*rc::gen::inRange(0, 5)) {
    case 0: angle = O(real(-M_PI, M_PI)); break;
    case 1: angle = pi + nudge; break;
    case 2: angle = pi / 4 * *rc::gen::inRange(-7, 8) + nudge; break;
    case 3: angle = O(log_uniform(1e-9, 1e-2)) * (*rc::gen::arbitrary<bool>() ? 1 : -1); break;
    default: angle = nudge; break;
  }
  return AA(angle, gen_axis());
}

// The exact unit quaternion of a rotation, with either sign (q and -q are
// the same rotation; lockstep must not care).
inline Q gen_unit_quaternion(const AA& r) {
  Q q(r);
  if (*rc::gen::arbitrary<bool>()) q.coeffs() = -q.coeffs();
  return q;
}

// A vector with components in [-s, s], or along an axis, or tiny.
inline V3 gen_vector(double s) {
  switch (*rc::gen::inRange(0, 3)) {
    case 0: return V3(O(real(-s, s)), O(real(-s, s)), O(real(-s, s)));
    case 1: return gen_axis() * O(real(-s, s));
    default: return gen_axis() * O(log_uniform(1e-3, 1));
  }
}

// Maximum absolute difference between a lockstep vector and the oracle.
template <class T>
V3 diff(const Vec3<T>& got, const V3& want) { return exact(got) - want; }

}  // namespace lockstep::test::oracle
