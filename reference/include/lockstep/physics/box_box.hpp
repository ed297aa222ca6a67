// Oriented box-box contacts (docs/SPEC.md 2.4, eqs 100-106), host and device
// (LS_HD), generic over the number type: World<T>::narrow_phase and the GPU
// engine's kernels call box_box_manifold for one body pair. Separating axes
// (eqs 100-102) with a face axis preferred over an edge axis, then either the
// incident face clipped against the reference face (eqs 103-105) or one
// point between two edges (eq 106). Read from ODE's dBoxBox, Bullet's
// btBoxBoxDetector and Box2D v3's polygon clipping; written from the spec.
#pragma once
#include "lockstep/math/vec.hpp"

namespace lockstep {

// The most points of one box-box manifold (eq 105).
inline constexpr int kBoxManifoldPoints = 4;

// Feature ids (eq 96's warm-start key) of box-box points:
//   face contact: ((ref_is_b * 6 + ref_face) * 6 + inc_face) * 64 + clip_id,
//     ref_face/inc_face = 2 * axis + (sign > 0), clip_id < 36 (eq 104);
//   edge contact: kEdgeFeatureBase + (3 * i + j) * 16 + sign bits (eq 106).
inline constexpr int kEdgeFeatureBase = 1 << 13;

// A body pair's manifold: up to 4 points sharing one unit normal n from b
// towards a (as eqs 41-42), each with its own point (m), penetration (m;
// negative: a speculative gap, eq 97) and feature id.
template <class T>
struct BoxManifold {
  int count = 0;
  Vec3<T> n{};
  Vec3<T> point[kBoxManifoldPoints];
  T penetration[kBoxManifoldPoints];
  int feature[kBoxManifoldPoints];
};

// The tolerances of eqs 101-102 and 104: fixed numbers, the same for every
// number type so that every engine picks the same axis.
template <class T>
struct BoxBoxTolerances {
  T rel;       // 0.05: a face axis wins unless the other separates by 5 % more
  T abs_;      // 0.0005 m: ... and by half a millimetre more
  T edge_min;  // 1/64: edge pairs closer to parallel than |a x b| = 1/64 give no axis
  T clip_margin;  // 2^-10 m: eq 104's side planes are moved out by this for the clip
  static LS_HD BoxBoxTolerances make() {
    return {Num<T>::from_double(0.05), Num<T>::from_double(0.0005), Num<T>::from_double(1.0 / 64.0),
            Num<T>::from_double(1.0 / 1024.0)};
  }
};

// eq 107: a body's speculative reach (m): how far its surface may move in one
// step, (|v|_inf + min(3 |w|_inf |h|_inf, 64 m/s)) dt, |v|_inf capped at
// 64 m/s too (keeps Q16.16 in range: at most 2.2 m). Pairs within the
// contact tolerance plus both reaches are (speculative) contacts, so a cube
// falling onto a stack at 6 m/s is caught the frame before it would sink
// 10 cm into it (eq 97's target lets it close the gap and no more).
template <class T>
LS_HD T speculative_reach(const Vec3<T>& v, const Vec3<T>& w, const Vec3<T>& h, const T& dt) {
  const T cap = Num<T>::from_int(64);
  const T arm = max_abs(h) * Num<T>::from_int(3);      // >= the longest lever |r| of a point of the box
  const T spin = max_abs(w);
  const T corner = spin > cap / arm ? cap : spin * arm;  // cap / arm: no product beyond 64 is formed
  return (Num<T>::min(max_abs(v), cap) + corner) * dt;
}

// eqs 97, 107: the contact tolerance of a body's ground corners with the
// oriented-box model, from its growth g = tol/2 + r of the
// broadphase: the tolerance plus its reach, (g - tol/2) + tol, formed from g
// so that every engine that keeps g rounds it alike. A cube landing at 5 m/s
// is caught the frame before it would sink 8 cm into the ground.
template <class T>
LS_HD T immovable_tolerance(const T& growth, const T& half_tol, const T& tol) {
  return (growth - half_tol) + tol;
}

namespace box_detail {

// Column j of R: the world direction of the box's local axis j.
template <class T>
LS_HD Vec3<T> axis(const Mat3<T>& R, int j) { return {R.row[0][j], R.row[1][j], R.row[2][j]}; }

// eq 100: the separation of two boxes along a unit axis L (in any common
// frame): s = |d.L| - sum_i ha_i |A_i.L| - sum_j hb_j |B_j.L|, d = pb - pa.
// From the projections dL = d.L, pa_i = A_i.L and pb_j = B_j.L.
template <class T>
LS_HD_INLINE T separation_of(const T& dL, const T pa[3], const Vec3<T>& ha, const T pb[3], const Vec3<T>& hb) {
  T s = Num<T>::abs(dL);
  for (int i = 0; i < 3; ++i) s = s - ha[i] * Num<T>::abs(pa[i]);
  for (int j = 0; j < 3; ++j) s = s - hb[j] * Num<T>::abs(pb[j]);
  return s;
}
template <class T>
LS_HD T separation(const Vec3<T>& d, const Vec3<T>& L, const Vec3<T> A[3], const Vec3<T>& ha, const Vec3<T> B[3],
                   const Vec3<T>& hb) {
  const T pa[3] = {dot(A[0], L), dot(A[1], L), dot(A[2], L)};
  const T pb[3] = {dot(B[0], L), dot(B[1], L), dot(B[2], L)};
  return separation_of(dot(d, L), pa, ha, pb, hb);
}

// eqs 101-102: candidate wins over the best so far when it separates by more
// than the preference margin rel |best| + abs.
template <class T>
LS_HD bool beats(const T& candidate, const T& best, const BoxBoxTolerances<T>& tol) {
  return candidate > best + tol.rel * Num<T>::abs(best) + tol.abs_;
}

// A vertex of the clip polygon (eq 104) in the reference box's frame, its
// feature id, and the id of the polygon edge that leaves it (0-3: incident
// face edge, 4-7: along reference side plane s - 4).
template <class T>
struct ClipVertex {
  Vec3<T> x;
  int id;
  int edge;
};

// eq 104: one Sutherland-Hodgman pass: keeps the part of the polygon with
// sgn * x[a] <= h (side plane s = 2 * (a index) + (sgn > 0)). New points on
// an incident edge e get 4 + 4e + s; on a side-plane edge s0, 20 + 4 s0 + s
// (a corner of the reference face).
template <class T>
LS_HD int clip_side(const ClipVertex<T>* in, int n, ClipVertex<T>* out, int a, const T& sgn, const T& h, int s) {
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const ClipVertex<T>& c = in[k];
    const ClipVertex<T>& d = in[(k + 1) % n];
    const T dc = sgn * c.x[a] - h, dd = sgn * d.x[a] - h;  // > 0: outside
    const bool cin = !(dc > T{}), din = !(dd > T{});
    if (cin) out[m++] = c;
    if (cin != din) {
      // The crossing point x = c + (d - c) t, t = dc / (dc - dd) in [0, 1].
      const T t = dc / (dc - dd);
      ClipVertex<T> p;
      p.x = c.x + (d.x - c.x) * t;
      p.x[a] = sgn * h;  // exactly on the plane
      p.id = c.edge < 4 ? 4 + 4 * c.edge + s : 20 + 4 * (c.edge - 4) + s;
      p.edge = cin ? 4 + s : c.edge;  // leaving: along the plane; entering: along c's edge
      out[m++] = p;
    }
  }
  return m;
}

// eqs 103-105: the face contact of reference box (pr, Rr, hr) face (axis k,
// outward sign sk, towards the incident box) against incident box
// (pi, Ri, hi). Writes up to 4 points into m (point, penetration, feature);
// n_sign turns the reference face's normal into the manifold normal (b -> a).
template <class T>
LS_HD void face_contact(const Vec3<T>& pr, const Mat3<T>& Rr, const Vec3<T>& hr, int k, const T& sk,
                        const Vec3<T>& pi, const Mat3<T>& Ri, const Vec3<T>& hi, int ref_is_b, const T& tol,
                        const T& margin, BoxManifold<T>& m) {
  const T one = Num<T>::from_int(1);
  const Vec3<T> nr = axis(Rr, k) * sk;  // the reference face's outward normal (world)
  // eq 103: the incident face: the face of the incident box whose outward
  // normal is most anti-parallel to nr (largest |axis . nr|, lowest axis on ties).
  int f = 0;
  T best = Num<T>::abs(dot(axis(Ri, 0), nr));
  for (int j = 1; j < 3; ++j) {
    const T dj = Num<T>::abs(dot(axis(Ri, j), nr));
    if (dj > best) { best = dj; f = j; }
  }
  const T sf = dot(axis(Ri, f), nr) > T{} ? -one : one;  // outward incident normal opposes nr
  const int u = f == 0 ? 1 : 0, v = f == 2 ? 1 : 2;      // the incident face's two in-plane axes
  // Its 4 corners, counter-clockwise in (u, v), in the reference box's frame.
  ClipVertex<T> poly[8], tmp[8];
  const T su[4] = {one, -one, -one, one}, sv[4] = {one, one, -one, -one};
  for (int c = 0; c < 4; ++c) {
    Vec3<T> local{};
    local[f] = hi[f] * sf;
    local[u] = hi[u] * su[c];
    local[v] = hi[v] * sv[c];
    const Vec3<T> world = pi + Ri * local;
    poly[c].x = mat_transpose_mul(Rr, world - pr);
    poly[c].id = c;
    poly[c].edge = c;
  }
  // eq 104: clip against the reference face's 4 side planes, each moved out
  // by the clip margin (BoxBoxTolerances), then clamp what is kept onto the face: an
  // incident corner within the margin of a side plane stays that corner
  // (same feature id, so the warm start of eq 96 finds it), whichever side
  // of the plane rounding put it. Two boxes of one width stacked edge on edge
  // otherwise traded corners for clip points with each ulp of drift.
  const int a1 = k == 0 ? 1 : 0, a2 = k == 2 ? 1 : 2;
  int n = 4;
  // Side plane s (0-3): axis a1, + and -, then a2, + and -; from poly to tmp
  // and back, so that poly holds the result (one call in a loop: a device
  // inlines each call).
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int s = 0; s < 4; ++s) {
    const int a = s < 2 ? a1 : a2;
    n = clip_side((s & 1) == 0 ? poly : tmp, n, (s & 1) == 0 ? tmp : poly, a, (s & 1) == 0 ? one : -one,
                  hr[a] + margin, s);
  }
  for (int c = 0; c < n; ++c) {
    poly[c].x[a1] = Num<T>::min(Num<T>::max(poly[c].x[a1], -hr[a1]), hr[a1]);
    poly[c].x[a2] = Num<T>::min(Num<T>::max(poly[c].x[a2], -hr[a2]), hr[a2]);
  }
  // Depth below the reference face; points within the tolerance are kept.
  T depth[8];
  int keep[8];
  int kept = 0;
  for (int c = 0; c < n; ++c) {
    const T dpt = hr[k] - sk * poly[c].x[k];
    if (!(dpt > -tol)) continue;
    depth[kept] = dpt;
    keep[kept++] = c;
  }
  if (kept == 0) return;
  // eq 105: at most 4 points: the deepest (first on ties), the farthest from
  // it (L1 in the face plane), then the largest signed area on each side of
  // that diagonal (coordinates divided by the face's larger half extent).
  int pick[4];
  int picked = 0;
  if (kept <= 4) {
    for (int c = 0; c < kept; ++c) pick[picked++] = c;
  } else {
    int i0 = 0;
    for (int c = 1; c < kept; ++c)
      if (depth[c] > depth[i0]) i0 = c;
    const Vec3<T>& x0 = poly[keep[i0]].x;
    int i1 = -1;
    T far{};
    for (int c = 0; c < kept; ++c) {
      const Vec3<T>& x = poly[keep[c]].x;
      const T l1 = Num<T>::abs(x[a1] - x0[a1]) + Num<T>::abs(x[a2] - x0[a2]);
      if (i1 < 0 || l1 > far) { far = l1; i1 = c; }
    }
    const T scale = one / Num<T>::max(hr[a1], hr[a2]);
    const Vec3<T>& x1 = poly[keep[i1]].x;
    const T e1 = (x1[a1] - x0[a1]) * scale, e2 = (x1[a2] - x0[a2]) * scale;
    int i2 = -1, i3 = -1;
    T hi_area{}, lo_area{};
    for (int c = 0; c < kept; ++c) {
      const Vec3<T>& x = poly[keep[c]].x;
      const T area = e1 * ((x[a2] - x0[a2]) * scale) - e2 * ((x[a1] - x0[a1]) * scale);
      if (area > hi_area) { hi_area = area; i2 = c; }
      if (area < lo_area) { lo_area = area; i3 = c; }
    }
    pick[picked++] = i0;
    if (i1 != i0) pick[picked++] = i1;
    if (i2 >= 0) pick[picked++] = i2;
    if (i3 >= 0) pick[picked++] = i3;
  }
  const int face_key = ((ref_is_b * 6 + 2 * k + (sk > T{} ? 1 : 0)) * 6 + 2 * f + (sf > T{} ? 1 : 0)) * 64;
  const T half = Num<T>::from_double(0.5);
  for (int c = 0; c < picked; ++c) {
    const ClipVertex<T>& p = poly[keep[pick[c]]];
    Vec3<T> mid = p.x;
    mid[k] = mid[k] + sk * (depth[pick[c]] * half);  // halfway to the reference face
    m.point[m.count] = pr + Rr * mid;
    m.penetration[m.count] = depth[pick[c]];
    m.feature[m.count] = face_key + p.id;
    ++m.count;
  }
}

// x / den clamped to [-limit, limit], without forming a quotient beyond it
// (den > 0): the line parameters of eq 106.
template <class T>
LS_HD T clamped_ratio(const T& x, const T& den, const T& limit) {
  if (!(Num<T>::abs(x) < limit * den)) return x < T{} ? -limit : limit;
  return x / den;
}

}  // namespace box_detail

// eqs 100-106: the contact manifold of box a (centre pa, rotation Ra, half
// extents ha) and box b, a < b, with points up to `tol` (contact_tolerance,
// eq 97) apart. count = 0: separated by more than tol on some axis (eq 100).
template <class T>
LS_HD BoxManifold<T> box_box_manifold(const Vec3<T>& pa, const Mat3<T>& Ra, const Vec3<T>& ha, const Vec3<T>& pb,
                                      const Mat3<T>& Rb, const Vec3<T>& hb, const T& tol) {
  using namespace box_detail;
  const BoxBoxTolerances<T> pref = BoxBoxTolerances<T>::make();
  BoxManifold<T> m;
  const T one = Num<T>::from_int(1);
  const Vec3<T> A[3] = {axis(Ra, 0), axis(Ra, 1), axis(Ra, 2)};
  const Vec3<T> B[3] = {axis(Rb, 0), axis(Rb, 1), axis(Rb, 2)};
  const Vec3<T> d = pb - pa;
  // eq 100 on the 3 face axes of a, the 3 of b and the 9 edge pairs, in that
  // order; any axis separating by more than tol ends the test.
  T sa{}, sb{}, se{};
  int ia = -1, ib = -1, ie = -1;
  Vec3<T> le{};
  // The face axes share their projections (dot is symmetric, exactly in
  // every number type): A_k.A_i, B_j.A_i and B_k.B_j are each formed once, in
  // the order the axes need them.
  T AA[3][3], AB[3][3], BB[3][3];  // AA[i][k] = A_k.A_i, AB[i][j] = B_j.A_i, BB[j][k] = B_k.B_j
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) AA[i][k] = k < i ? AA[k][i] : dot(A[k], A[i]);
    for (int j = 0; j < 3; ++j) AB[i][j] = dot(B[j], A[i]);
    const T s = separation_of(dot(d, A[i]), AA[i], ha, AB[i], hb);
    if (s > tol) return m;
    if (ia < 0 || s > sa) { sa = s; ia = i; }
  }
  for (int j = 0; j < 3; ++j) {
    const T on_a[3] = {AB[0][j], AB[1][j], AB[2][j]};
    for (int k = 0; k < 3; ++k) BB[j][k] = k < j ? BB[k][j] : dot(B[k], B[j]);
    const T s = separation_of(dot(d, B[j]), on_a, ha, BB[j], hb);
    if (s > tol) return m;
    if (ib < 0 || s > sb) { sb = s; ib = j; }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vec3<T> c = cross(A[i], B[j]);
      const T len = length(c);
      if (!(len > pref.edge_min)) continue;  // near-parallel edges: the face axes decide
      const Vec3<T> L = c * (one / len);
      const T s = separation(d, L, A, ha, B, hb);
      if (s > tol) return m;
      if (ie < 0 || s > se) { se = s; ie = 3 * i + j; le = L; }
    }
  // eq 101: a's face unless b's separates by the margin more; eq 102: an
  // edge pair only if it separates by the margin more than that face.
  const bool face_b = beats(sb, sa, pref);
  const T sf = face_b ? sb : sa;
  if (ie >= 0 && beats(se, sf, pref)) {
    // eq 106: the two edges nearest each other, one point midway between
    // their closest points; depth -se along the edge axis.
    const int i = ie / 3, j = ie % 3;
    m.n = dot(d, le) > T{} ? -le : le;  // from b towards a
    Vec3<T> ea = pa, eb = pb;
    int bits = 0;
    for (int k = 0; k < 3; ++k) {
      if (k != i) {
        const bool pos = dot(A[k], m.n) < T{};  // a's edge on the side facing b (-n)
        ea += A[k] * (pos ? ha[k] : -ha[k]);
        bits = bits * 2 + (pos ? 1 : 0);
      }
      if (k != j) {
        const bool pos = dot(B[k], m.n) > T{};  // b's edge on the side facing a (+n)
        eb += B[k] * (pos ? hb[k] : -hb[k]);
        bits = bits * 2 + (pos ? 1 : 0);
      }
    }
    const Vec3<T> p = eb - ea;
    const T uab = dot(A[i], B[j]);
    const T q1 = dot(A[i], p), q2 = -dot(B[j], p);
    const T cl = length(cross(A[i], B[j]));
    const T den = cl * cl;  // 1 - (A_i . B_j)^2 >= edge_min^2
    const T ta = clamped_ratio(q1 + uab * q2, den, ha[i]);
    const T tb = clamped_ratio(uab * q1 + q2, den, hb[j]);
    const T half = Num<T>::from_double(0.5);
    m.point[0] = ea + A[i] * ta + ((eb + B[j] * tb) - (ea + A[i] * ta)) * half;
    m.penetration[0] = -se;
    m.feature[0] = kEdgeFeatureBase + ie * 16 + bits;
    m.count = 1;
    return m;
  }
  // eqs 103-105: the reference face is the winning face, facing the other
  // box (the sides picked before one call: a device inlines each call).
  T sk;
  if (!face_b) {
    sk = dot(d, A[ia]) < T{} ? -one : one;  // towards b; d.A = 0 takes +
    m.n = A[ia] * (-sk);
  } else {
    sk = dot(d, B[ib]) > T{} ? -one : one;  // towards a (-d); d.B = 0 takes +
    m.n = B[ib] * sk;
  }
  face_contact(face_b ? pb : pa, face_b ? Rb : Ra, face_b ? hb : ha, face_b ? ib : ia, sk, face_b ? pa : pb,
               face_b ? Ra : Rb, face_b ? ha : hb, face_b ? 1 : 0, tol, pref.clip_margin, m);
  return m;
}

}  // namespace lockstep
