// Per-element contact generation (docs/SPEC.md 7.2 stage 3), host and device
// (LS_HD), generic over the number type: World<T>::narrow_phase
// (reference/src/narrow_phase.hpp) and the GPU engine's kernels
// (gpu/src/*_stages.hpp) call these same functions for one ground corner, one
// body pair and one SDF sample.
#pragma once
#include "lockstep/math/vec.hpp"
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/sdf.hpp"

namespace lockstep {

// Eq 84 for one corner k (0-7) of a box at p with rotation R and half extents
// h: writes the corner and returns its depth below the plane y = ground_y
// (> 0: below; a contact when > -contact_tolerance, eq 97).
template <class T>
LS_HD T ground_corner_depth(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& h, int k, const T& ground_y,
                            Vec3<T>& corner) {
  corner = box_corner(p, R, h, k);
  return ground_y - corner.y;
}

// A body-body contact (eqs 38-43, 85, 97) between bodies a < b.
template <class T>
struct PairContact {
  bool hit = false;
  Vec3<T> n{};       // eqs 41-42: unit normal from b towards a
  T penetration{};   // eq 43 less the tolerance (m; negative: a gap)
  Vec3<T> point{};   // eq 85 (m)
};

// The overlap test (eqs 38-43) runs on the AABBs (centres pa, pb, half
// extents ha, hb) grown by half_tol each, so that pairs up to the contact
// tolerance apart are speculative contacts (eq 97); the penetration is the
// grown overlap less `tol`, the sum of the two growths (World<T> passes
// half_tol + half_tol, which is contact_tolerance exactly in float); the
// point (eq 85) is that of the ungrown boxes.
template <class T>
LS_HD PairContact<T> pair_contact(const Vec3<T>& pa, const Vec3<T>& ha, const Vec3<T>& pb, const Vec3<T>& hb,
                                  const T& half_tol, const T& tol) {
  PairContact<T> c;
  const Vec3<T> grow{half_tol, half_tol, half_tol};
  const Overlap<T> o = aabb_overlap(pa, ha + grow, pb, hb + grow);  // eqs 38-43
  if (!o.hit) return c;
  c.hit = true;
  c.n = o.normal;
  c.penetration = o.penetration - tol;
  c.point = aabb_contact_point(pa, ha, pb, hb, Num<T>::from_double(0.5));  // eq 85
  return c;
}

// An SDF contact (eqs 32-37, 93, 97) of one sample point of a body.
template <class T>
struct SdfContact {
  bool hit = false;
  Vec3<T> n{};      // eq 36: unit outward normal of the volume
  Vec3<T> point{};  // eq 37: the sample projected onto the surface (m)
  T penetration{};  // eq 35 (m; negative: a gap)
};

// Eq 93's sample s of a box at p (rotation R, half extents `half`) against
// the volume g: s = 0-7 is corner s with radius 0, s = 8 the centre with
// radius min h. A contact when the sample lies inside the volume, closer than
// tol (the contact tolerance, eq 97) to the surface, with a non-zero gradient.
template <class T>
LS_HD SdfContact<T> sdf_sample_contact(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& half, const SdfGrid<T>& g,
                                       int s, const T& tol) {
  SdfContact<T> out;
  const Vec3<T> pt = s < 8 ? box_corner(p, R, half, s) : p;
  const T radius = s < 8 ? T{} : Num<T>::min(half.x, Num<T>::min(half.y, half.z));
  if (!sdf_contains(g, pt)) return out;
  const T dist = sdf_distance(g, pt);  // eq 33
  const T pen = radius - dist;         // eq 35
  if (!(pen > -tol)) return out;       // eq 97
  const Vec3<T> grad = sdf_gradient(g, pt);  // eq 34
  if (length(grad) == T{}) return out;
  out.hit = true;
  out.n = normalize(grad);        // eq 36
  out.point = pt - out.n * dist;  // eq 37
  out.penetration = pen;
  return out;
}

}  // namespace lockstep
