// Small geometric types, generic over the number type T (float, double,
// Boost.Multiprecision, Q16). The generic operations below are the plain
// formulas, evaluated left to right; Q16 overrides the ones that accumulate
// products (dot, cross, length, normalise, quaternion and matrix products) with
// exact-accumulator versions in fixed/include/lockstep/fixed/q16_vec.hpp,
// found by overload resolution (a non-template beats a template).
#pragma once
#include <type_traits>

#include "lockstep/hd.hpp"
#include "lockstep/math/num.hpp"

namespace lockstep {

class Q16;
// The generic formulas below that Q16 overrides refuse Q16: instantiated on
// it (the overloads not in view), they would round differently from the
// overloads, and an inline template instantiated both ways in two translation
// units would leave the linker to pick one (an ODR violation that changed
// the fixed engine's bits in one binary). lockstep/fixed/q16_num.hpp includes
// q16_vec.hpp, so code that has Num<Q16> has the overloads.
template <class T>
inline constexpr bool kGenericFormula = !std::is_same_v<T, Q16>;
#define LOCKSTEP_NOT_Q16(T) \
  static_assert(kGenericFormula<T>, "Q16 uses the overloads of lockstep/fixed/q16_vec.hpp: include it")

template <class T>
struct Vec3 {
  T x{}, y{}, z{};
  LS_HD T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  LS_HD const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  friend LS_HD bool operator==(const Vec3& a, const Vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
  }
};

// Quaternion w + xi + yj + zk (Hamilton convention).
template <class T>
struct Quat {
  T w{}, x{}, y{}, z{};
  friend LS_HD bool operator==(const Quat& a, const Quat& b) {
    return a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z;
  }
};

// Row-major 3x3 matrix: m[row][col].
template <class T>
struct Mat3 {
  Vec3<T> row[3];
};

template <class T> LS_HD Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> LS_HD Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> LS_HD Vec3<T> operator-(const Vec3<T>& a) { return {-a.x, -a.y, -a.z}; }
template <class T> LS_HD Vec3<T> operator*(const Vec3<T>& a, const T& s) { return {a.x * s, a.y * s, a.z * s}; }
template <class T> LS_HD Vec3<T> operator*(const T& s, const Vec3<T>& a) { return {a.x * s, a.y * s, a.z * s}; }
template <class T> LS_HD Vec3<T>& operator+=(Vec3<T>& a, const Vec3<T>& b) { a = a + b; return a; }
template <class T> LS_HD Vec3<T>& operator-=(Vec3<T>& a, const Vec3<T>& b) { a = a - b; return a; }
// Component-wise product.
template <class T> LS_HD Vec3<T> hadamard(const Vec3<T>& a, const Vec3<T>& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

template <class T> LS_HD T dot(const Vec3<T>& a, const Vec3<T>& b) {
  LOCKSTEP_NOT_Q16(T);
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
// eq 51: a x b.
template <class T> LS_HD Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  LOCKSTEP_NOT_Q16(T);
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T> LS_HD T length_sq(const Vec3<T>& a) {
  LOCKSTEP_NOT_Q16(T);
  return dot(a, a);
}
template <class T> LS_HD T length(const Vec3<T>& a) {
  LOCKSTEP_NOT_Q16(T);
  return Num<T>::sqrt(length_sq(a));
}
// The largest |component| (exact in every number type: no rounding).
template <class T> LS_HD_INLINE T max_abs(const Vec3<T>& a) {
  return Num<T>::max(Num<T>::abs(a.x), Num<T>::max(Num<T>::abs(a.y), Num<T>::abs(a.z)));
}
// a / |a|; a zero vector gives zero (Q16 raises kQ16NormalizeZero instead).
template <class T> LS_HD Vec3<T> normalize(const Vec3<T>& a) {
  LOCKSTEP_NOT_Q16(T);
  const T len = length(a);
  if (len == T(0)) return a;
  return {a.x / len, a.y / len, a.z / len};
}

// Whether |a| > limit, i.e. length(a) > limit, as written; Q16 decides it
// from the exact sum of squares without the square root.
template <class T> LS_HD bool longer_than(const Vec3<T>& a, const T& limit) {
  LOCKSTEP_NOT_Q16(T);
  return length(a) > limit;
}

// Whether |a| > 0, and then unit = normalize(a) (unit untouched otherwise):
// the two as written, which Q16 forms from one square root.
template <class T> LS_HD bool direction_of(const Vec3<T>& a, Vec3<T>& unit) {
  LOCKSTEP_NOT_Q16(T);
  if (!(length(a) > T(0))) return false;
  unit = normalize(a);
  return true;
}

// Hamilton product a * b.
template <class T> LS_HD Quat<T> operator*(const Quat<T>& a, const Quat<T>& b) {
  LOCKSTEP_NOT_Q16(T);
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
template <class T> LS_HD T quat_length_sq(const Quat<T>& q) {
  LOCKSTEP_NOT_Q16(T);
  return q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
}
// eq 10: q / |q|; the zero quaternion gives the identity (Q16 also raises kQ16NormalizeZero).
template <class T> LS_HD Quat<T> normalize(const Quat<T>& q) {
  LOCKSTEP_NOT_Q16(T);
  const T len = Num<T>::sqrt(quat_length_sq(q));
  if (len == T(0)) return {T(1), T(0), T(0), T(0)};
  return {q.w / len, q.x / len, q.y / len, q.z / len};
}

// Rotation matrix of a unit quaternion (eq 31 uses it as mat3_cast(q)).
template <class T> LS_HD Mat3<T> rotation_matrix(const Quat<T>& q) {
  LOCKSTEP_NOT_Q16(T);
  const T one(1), two(2);
  const T xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const T xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  const T wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  return {{{one - two * (yy + zz), two * (xy - wz), two * (xz + wy)},
           {two * (xy + wz), one - two * (xx + zz), two * (yz - wx)},
           {two * (xz - wy), two * (yz + wx), one - two * (xx + yy)}}};
}
template <class T> LS_HD Vec3<T> operator*(const Mat3<T>& m, const Vec3<T>& v) {
  LOCKSTEP_NOT_Q16(T);
  return {dot(m.row[0], v), dot(m.row[1], v), dot(m.row[2], v)};
}
template <class T> LS_HD Vec3<T> mat_transpose_mul(const Mat3<T>& m, const Vec3<T>& v) {
  LOCKSTEP_NOT_Q16(T);
  return m.row[0] * v.x + m.row[1] * v.y + m.row[2] * v.z;
}
// q v q*: v rotated by unit quaternion q, through its rotation matrix.
template <class T> LS_HD Vec3<T> rotate(const Quat<T>& q, const Vec3<T>& v) {
  LOCKSTEP_NOT_Q16(T);
  return rotation_matrix(q) * v;
}

}  // namespace lockstep
