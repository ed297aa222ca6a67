// Part 2 of docs/SPEC.md: bounding boxes, grid cells and the AABB narrowphase.
#pragma once
#include "lockstep/math/vec.hpp"

namespace lockstep {

// eq 31: aabb_half_i = sum_j |R_ij| h_j (the AABB of the rotated box).
template <class T>
LS_HD Vec3<T> rotated_half_extents(const Mat3<T>& R, const Vec3<T>& h) {
  Vec3<T> out;
  for (int i = 0; i < 3; ++i) {
    const Vec3<T>& r = R.row[i];
    out[i] = dot(Vec3<T>{Num<T>::abs(r.x), Num<T>::abs(r.y), Num<T>::abs(r.z)}, h);
  }
  return out;
}

// eq 26: cell = floor(x / cell_size), with 1/cell_size precomputed.
template <class T>
LS_HD int cell_coord(const T& x, const T& inv_cell_size) { return Num<T>::floor_int(x * inv_cell_size); }

template <class T>
struct Overlap {
  bool hit = false;
  int axis = 0;      // eq 40
  T penetration{};   // eq 43
  Vec3<T> normal{};  // eqs 41-42: from body 2 towards body 1
};

// eqs 38-43: AABB against AABB, centres p and half extents h. Ties in eq 40
// take the lowest axis; sign(0) in eq 41 is +1.
template <class T>
LS_HD Overlap<T> aabb_overlap(const Vec3<T>& p1, const Vec3<T>& h1, const Vec3<T>& p2, const Vec3<T>& h2) {
  Overlap<T> o;
  const Vec3<T> delta = p1 - p2;
  Vec3<T> overlap;
  for (int i = 0; i < 3; ++i) {
    overlap[i] = h1[i] + h2[i] - Num<T>::abs(delta[i]);  // eq 38
    if (!(overlap[i] > T{})) return o;                    // eq 39
  }
  int axis = 0;  // eq 40
  if (overlap[1] < overlap[axis]) axis = 1;
  if (overlap[2] < overlap[axis]) axis = 2;
  o.hit = true;
  o.axis = axis;
  o.penetration = overlap[axis];  // eq 43
  const T one = Num<T>::from_int(1);
  o.normal[axis] = delta[axis] < T{} ? -one : one;  // eqs 41-42
  return o;
}

// eq 85 (the source's "manifold midpoint" (47)): the centre of the
// intersection of the two AABBs, lo + (hi - lo)/2: the source's (lo + hi)/2
// overflows Q16.16 beyond |x| = 16384 m; in Q16.16 both floor to the same raw
// value, (hi - lo) >= 0 never overflows for boxes within range.
template <class T>
LS_HD Vec3<T> aabb_contact_point(const Vec3<T>& p1, const Vec3<T>& h1, const Vec3<T>& p2, const Vec3<T>& h2,
                                 const T& half) {
  Vec3<T> c;
  for (int i = 0; i < 3; ++i) {
    const T lo = Num<T>::max(p1[i] - h1[i], p2[i] - h2[i]);
    const T hi = Num<T>::min(p1[i] + h1[i], p2[i] + h2[i]);
    c[i] = lo + (hi - lo) * half;
  }
  return c;
}

// The k-th corner of a box (k = 0..7; bit 0 -> x, bit 1 -> y, bit 2 -> z; a
// set bit takes +h): p + R (+-hx, +-hy, +-hz). Used by eq 84 and eq 93.
template <class T>
LS_HD Vec3<T> box_corner(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& h, int k) {
  const Vec3<T> local{(k & 1) ? h.x : -h.x, (k & 2) ? h.y : -h.y, (k & 4) ? h.z : -h.z};
  return p + R * local;
}

}  // namespace lockstep
