// physics/box_box.hpp (docs/SPEC.md eqs 100-106) against the Eigen oracle of
// eigen_oracle.hpp on Q16, float, double and mp (issue 16): the separating
// axes, the choice of face or edge, and the clipped face contact, checked by
// the geometry each must have, not by a second copy of the algorithm.
//
// The boxes are the ones lockstep is given: centre p, half extents h and
// the columns of its rounded rotation matrix R = rotation_matrix(q), taken
// exactly (the separation formula of eq 100 is exact for any parallelepiped,
// so the oracle's boxes are lockstep's and its bounds cover box_box's own
// arithmetic only; rotation_matrix is checked in eigen_math_oracle_test.cpp).
// In 160-bit Eigen the oracle computes:
//  * eq 100: s(L) on the 15 axes. Lockstep reports no contact only if some
//    axis separates by more than tol; it reports a contact only if none does.
//  * eqs 101-102: the winning face or edge is the rule's choice within the
//    rounding of s.
//  * eqs 103-105: the reference face faces the other box, the incident face
//    opposes it, and every manifold point p with penetration d lies d/2 below
//    the reference face (its distance to the face plane), inside the
//    reference face's side planes, with its incident point p - n_ref d/2 on
//    the incident face; the deepest point's depth is the maximum depth over
//    (incident face) ∩ (side planes), found by the oracle as a linear program
//    over the face's two parameters (the vertices of 8 half-planes), not by
//    clipping.
//  * eq 106: the edge pair's normal, depth -s and the midpoint of the closest
//    points of its two edge lines, which lie on the faces the normal names.
//
// Bound, stated in ulps of T: with S = norm1(pa) + norm1(pb) + 3 (sum ha +
// sum hb) + 1 m, a separation, depth or coordinate is within K eps S of the
// oracle, K = 4; an edge axis divides it by |A_i x B_j| >= 1/64 (its
// normalisation), an edge point by |A_i x B_j|^2 (eq 106's denominator). The
// worst seen over 20,000 cases per type is 0.1 of the bound (the test
// prints the worst of each check).
// A swapped normal, a reference face on the wrong side, a clip against the
// wrong plane or a point not halfway is an error of the size of the boxes.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "eigen_oracle.hpp"
#include "fixed/prop.hpp"
#include "lockstep/physics/box_box.hpp"

namespace lockstep::test {
namespace {

using namespace oracle;

constexpr int kBoxCases = 600;
constexpr double kK = 4;

// One exact box: centre, axes (the columns of lockstep's R) and half extents.
struct Box {
  V3 p, h;
  M3 R;
  V3 axis(int i) const { return R.col(i); }
};

// The pair, as lockstep sees it and as the oracle does.
template <class T>
struct Pair {
  Vec3<T> pa, ha, pb, hb;
  Mat3<T> Ra, Rb;
  T tol;
};

template <class T>
Pair<T> gen_pair() {
  Pair<T> c;
  auto gen_half = []() -> V3 {
    if (*rc::gen::arbitrary<bool>()) return V3::Constant(O(real(0.1, 2)));
    return V3(O(real(0.1, 2)), O(real(0.1, 2)), O(real(0.1, 2)));
  };
  const V3 ha = gen_half(), hb = gen_half();
  const AA ra = gen_rotation();
  const V3 pa(O(real(-10, 10)), O(real(-10, 10)), O(real(-10, 10)));
  AA rb;
  V3 d;
  switch (*rc::gen::inRange(0, 3)) {
    case 0: {  // anywhere near: faces, edges, corners, apart
      rb = gen_rotation();
      d = gen_axis() * (O(real(0, 1.3)) * (ha.norm() + hb.norm()));
      break;
    }
    case 1: {  // stacked on a face of a: b turned by multiples of 90 degrees (the 45-degree
               // and face ties of eqs 101-103), tilted a little, shifted, slightly apart or into it
      const M3 turn = (AA(O(0.5) * boost::math::constants::pi<O>() * *rc::gen::inRange(0, 4), V3::Unit(*rc::gen::inRange(0, 3))) *
                       AA(O(log_uniform(1e-6, 0.1)) * (*rc::gen::arbitrary<bool>() ? 1 : -1), gen_axis()))
                          .toRotationMatrix();
      const M3 Ra = ra.toRotationMatrix(), Rb = Ra * turn;
      rb = AA(Rb);
      const int k = *rc::gen::inRange(0, 3);
      const O sign = *rc::gen::arbitrary<bool>() ? O(1) : O(-1);
      const V3 n = Ra.col(k) * sign;
      O reach_b(0);
      for (int j = 0; j < 3; ++j) reach_b += hb[j] * abs(Rb.col(j).dot(n));
      d = n * (ha[k] + reach_b + O(real(-0.05, 0.02)));
      for (int j = 0; j < 3; ++j)
        if (j != k) d += Ra.col(j) * (ha[j] * O(real(-1, 1)));
      break;
    }
    default: {  // edge across edge, as BoxBoxTest.CrossedEdgesGiveOnePointBetweenTheEdges in a's frame:
                // a turned 45 degrees about z, b 45 degrees about x and above it, so that a's top
                // edge (along z) crosses b's bottom edge (along x); tilted and shifted a little
      const O q45 = boost::math::constants::pi<O>() / 4, r2 = boost::math::constants::root_two<O>();
      const M3 Ra0 = AA(q45, V3::UnitZ()).toRotationMatrix();
      const M3 Rb0 = (AA(q45, V3::UnitX()) * AA(O(log_uniform(1e-6, 0.05)), gen_axis())).toRotationMatrix();
      const V3 d0((O(real(-0.3, 0.3)) * hb.x()), (ha.x() + ha.y() + hb.y() + hb.z()) / r2 * O(real(0.97, 1.01)),
                  O(real(-0.3, 0.3)) * ha.z());
      const M3 to_world = ra.toRotationMatrix() * Ra0.transpose();
      rb = AA(to_world * Rb0);
      d = to_world * d0;
      break;
    }
  }
  c.pa = round_to<T>(pa);
  c.pb = round_to<T>(V3(pa + d));
  c.ha = round_to<T>(ha);
  c.hb = round_to<T>(hb);
  c.Ra = rotation_matrix(round_to<T>(gen_unit_quaternion(ra)));
  c.Rb = rotation_matrix(round_to<T>(gen_unit_quaternion(rb)));
  c.tol = round_to<T>(O(real(0.005, 0.05)));
  return c;
}

// eq 100: the separation of a and b along L (exact).
O separation(const Box& a, const Box& b, const V3& L) {
  O s = abs((b.p - a.p).dot(L));
  for (int i = 0; i < 3; ++i) s -= a.h[i] * abs(a.axis(i).dot(L)) + b.h[i] * abs(b.axis(i).dot(L));
  return s;
}
// eqs 101-102: the value the other must exceed to win over s.
O margin(const O& s) { return s + O(0.05) * abs(s) + O(0.0005); }

// The largest depth h_k - sigma x[k] (x in the reference frame, R^T (X - p))
// over the incident face {p_i + R_i (sf h_f e_f + s h_u e_u + t h_v e_v)}
// with |s|, |t| <= 1 + slack_st and |x[a]| <= h[a] + slack on the reference
// face's two in-plane axes: a linear program in (s, t), solved by visiting
// every vertex of its 8 half-planes. -inf (as -1e300) when empty.
// eq 104's clip margin (m): side planes moved out by 2^-10 m, kept points clamped onto the face.
const O kClipMargin = O(1.0 / 1024.0);

O max_depth(const Box& ref, int k, const O& sigma, const Box& inc, int f, const O& sf, const O& slack) {
  const int u = f == 0 ? 1 : 0, v = f == 2 ? 1 : 2;
  const int a1 = k == 0 ? 1 : 0, a2 = k == 2 ? 1 : 2;
  const M3 RrT = ref.R.transpose();
  const V3 x0 = RrT * (inc.p + inc.axis(f) * (sf * inc.h[f]) - ref.p);
  const V3 gu = RrT * inc.axis(u) * inc.h[u], gv = RrT * inc.axis(v) * inc.h[v];
  const O slack_st = slack / std::min(inc.h[u], inc.h[v]);
  // Half-planes g . (s, t) <= c.
  struct HalfPlane { O gs, gt, c; };
  std::vector<HalfPlane> hp = {{O(1), O(0), 1 + slack_st}, {O(-1), O(0), 1 + slack_st},
                               {O(0), O(1), 1 + slack_st}, {O(0), O(-1), 1 + slack_st}};
  for (int a : {a1, a2}) {
    hp.push_back({gu[a], gv[a], ref.h[a] + slack - x0[a]});
    hp.push_back({-gu[a], -gv[a], ref.h[a] + slack + x0[a]});
  }
  O best(-1e300);
  for (std::size_t i = 0; i < hp.size(); ++i)
    for (std::size_t j = i + 1; j < hp.size(); ++j) {
      const O det = hp[i].gs * hp[j].gt - hp[i].gt * hp[j].gs;
      if (abs(det) < O(1e-40)) continue;
      const O s = (hp[i].c * hp[j].gt - hp[i].gt * hp[j].c) / det;
      const O t = (hp[i].gs * hp[j].c - hp[i].c * hp[j].gs) / det;
      bool inside = true;
      for (const HalfPlane& q : hp) inside = inside && q.gs * s + q.gt * t <= q.c + O(1e-40);
      if (!inside) continue;
      const O depth = ref.h[k] - sigma * (x0[k] + gu[k] * s + gv[k] * t);
      if (depth > best) best = depth;
    }
  return best;
}

struct Counts { int none = 0, face = 0, face_b = 0, edge = 0; };

// The quantitative checks: |err| <= bound, failing the case with both
// numbers in ulps; the worst ratio of each is printed after the run.
struct Checks {
  std::map<std::string, double> worst;
  double eps = 0;
  void operator()(const char* what, const O& err, const O& bound) {
    const double e = std::fabs(dbl(err)), b = dbl(bound);
    if (!(e <= b)) RC_FAIL(std::string(what) + ": error " + std::to_string(e / eps) + " ulp > bound " + std::to_string(b / eps) + " ulp");
    double& w = worst[what];
    w = std::max(w, e / b);
  }
  // `value >= floor`, as the error floor - value <= 0 within `bound`.
  void at_least(const char* what, const O& value, const O& floor, const O& bound) {
    (*this)(what, value < floor ? O(floor - value) : O(0), bound);
  }
};

template <class T>
class EigenBoxBoxOracle : public ::testing::Test {};
TYPED_TEST_SUITE(EigenBoxBoxOracle, EngineTypes);

TYPED_TEST(EigenBoxBoxOracle, SeparatingAxesAndFaceClipping) {
  using T = TypeParam;
  Counts counts;
  Checks chk;
  chk.eps = Model<T>::eps();
  lockstep_test::check_prop([&] {
    const Pair<T> c = gen_pair<T>();
    const BoxManifold<T> m = box_box_manifold(c.pa, c.Ra, c.ha, c.pb, c.Rb, c.hb, c.tol);
    RC_ASSERT(Num<T>::take_faults() == 0u);
    const Box a{exact(c.pa), exact(c.ha), exact(c.Ra)}, b{exact(c.pb), exact(c.hb), exact(c.Rb)};
    const O tol = exact(c.tol);
    const V3 d = b.p - a.p;
    const double eps = Model<T>::eps();
    const double S = norm1(a.p) + norm1(b.p) + 3 * dbl(a.h.sum() + b.h.sum()) + 1;
    const O e_face(kK * eps * S), e_geo = e_face;
    const O edge_min(1.0 / 64), c_slack(kK * eps);

    // eq 100 on the 15 axes.
    O sA[3], sB[3], sE[9], cn[9];
    V3 LE[9];
    for (int i = 0; i < 3; ++i) {
      sA[i] = separation(a, b, a.axis(i));
      sB[i] = separation(a, b, b.axis(i));
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const V3 cr = a.axis(i).cross(b.axis(j));
        cn[3 * i + j] = cr.norm();
        LE[3 * i + j] = cr / cn[3 * i + j];
        sE[3 * i + j] = separation(a, b, LE[3 * i + j]);
      }
    auto e_edge = [&](int e) { return e_face / cn[e]; };
    auto edge_counts = [&](int e) { return cn[e] > edge_min + c_slack; };    // surely tested by lockstep
    auto edge_maybe = [&](int e) { return cn[e] > edge_min - c_slack; };     // possibly tested
    const O best_a = std::max({sA[0], sA[1], sA[2]}), best_b = std::max({sB[0], sB[1], sB[2]});

    bool separates = false;  // some axis surely beyond tol
    bool may_separate = false;
    for (int i = 0; i < 3; ++i) {
      separates = separates || sA[i] - e_face > tol || sB[i] - e_face > tol;
      may_separate = may_separate || sA[i] + e_face > tol || sB[i] + e_face > tol;
    }
    for (int e = 0; e < 9; ++e) {
      separates = separates || (edge_counts(e) && sE[e] - e_edge(e) > tol);
      may_separate = may_separate || (edge_maybe(e) && sE[e] + e_edge(e) > tol);
    }
    if (separates) RC_ASSERT(m.count == 0);
    if (m.count == 0) {
      ++counts.none;
      if (may_separate) return;
      // No axis separates: only a face contact whose clipped polygon is empty
      // or lies more than tol above its reference face gives no points.
      bool explained = false;
      for (int ref = 0; ref < 2; ++ref)
        for (int k = 0; k < 3; ++k) {
          const Box& r = ref ? b : a;
          const Box& in = ref ? a : b;
          const O sigma = (ref ? -d : d).dot(r.axis(k)) < O(0) ? O(-1) : O(1);
          const V3 nr = r.axis(k) * sigma;
          for (int f = 0; f < 3; ++f)
            for (const O& sf : {O(-1), O(1)}) {
              if (in.axis(f).dot(nr) * sf > e_geo) continue;
              explained = explained || max_depth(r, k, sigma, in, f, sf, e_geo) <= -tol + e_geo;
            }
        }
      RC_ASSERT(explained);
      return;
    }
    RC_ASSERT(!separates);
    RC_ASSERT(m.count <= kBoxManifoldPoints);
    const V3 n = exact(m.n);

    if (m.feature[0] >= kEdgeFeatureBase) {
      // eq 106: one point between two edges.
      ++counts.edge;
      RC_ASSERT(m.count == 1);
      const int ie = (m.feature[0] - kEdgeFeatureBase) / 16, bits = (m.feature[0] - kEdgeFeatureBase) % 16;
      RC_ASSERT(ie >= 0 && ie < 9);
      const int i = ie / 3, j = ie % 3;
      RC_ASSERT(edge_maybe(ie));
      const O ee = e_edge(ie);
      // eq 102: the normal is +-L, from b towards a; the depth is -s(L).
      const O dl = d.dot(LE[ie]);
      const V3 want_n = dl > O(0) ? V3(-LE[ie]) : LE[ie];
      if (abs(dl) > ee) chk("edge normal", (n - want_n).cwiseAbs().maxCoeff(), ee);
      else chk("edge normal", std::min((n - LE[ie]).cwiseAbs().maxCoeff(), (n + LE[ie]).cwiseAbs().maxCoeff()), ee);
      chk("edge depth = -s(L)", exact(m.penetration[0]) + sE[ie], ee);
      // eqs 101-102: the best edge, beating a's face (and so the winning face) by the margin.
      for (int e = 0; e < 9; ++e)
        if (edge_counts(e)) chk.at_least("the best edge", sE[ie], sE[e], ee + e_edge(e));
      chk.at_least("the edge beats a's face by the margin", sE[ie], margin(best_a), ee + O(1.05) * e_face);
      // The two edges the sign bits name lie on the sides the normal faces.
      V3 ea = a.p, eb = b.p;
      int bit = 3;
      for (int k = 0; k < 3; ++k) {
        if (k != i) {
          const bool pos = (bits >> bit--) & 1;
          ea += a.axis(k) * (pos ? a.h[k] : O(-a.h[k]));
          if (abs(a.axis(k).dot(n)) > ee) RC_ASSERT(pos == (a.axis(k).dot(n) < O(0)));
        }
        if (k != j) {
          const bool pos = (bits >> bit--) & 1;
          eb += b.axis(k) * (pos ? b.h[k] : O(-b.h[k]));
          if (abs(b.axis(k).dot(n)) > ee) RC_ASSERT(pos == (b.axis(k).dot(n) > O(0)));
        }
      }
      // The midpoint of the closest points of the two edge lines, each
      // parameter clamped to its edge.
      const V3 Ai = a.axis(i), Bj = b.axis(j), p = eb - ea;
      const O u = Ai.dot(Bj), q1 = Ai.dot(p), q2 = -Bj.dot(p), den = cn[ie] * cn[ie];
      const O ta = std::clamp(O((q1 + u * q2) / den), O(-a.h[i]), a.h[i]);
      const O tb = std::clamp(O((u * q1 + q2) / den), O(-b.h[j]), b.h[j]);
      const V3 want_p = ((ea + Ai * ta) + (eb + Bj * tb)) / 2;
      chk("edge point", (exact(m.point[0]) - want_p).cwiseAbs().maxCoeff(), e_face / den);
      return;
    }

    // eqs 103-105: a face contact. Decode the feature key.
    ++counts.face;
    const int key = m.feature[0] / 64;
    for (int q = 0; q < m.count; ++q) RC_ASSERT(m.feature[q] / 64 == key);
    const int ref_is_b = key / 36, ref_face = key % 36 / 6, inc_face = key % 6;
    const int k = ref_face / 2, f = inc_face / 2;
    const O sigma = ref_face % 2 ? O(1) : O(-1), sf = inc_face % 2 ? O(1) : O(-1);
    counts.face_b += ref_is_b;
    const Box& r = ref_is_b ? b : a;
    const Box& in = ref_is_b ? a : b;
    const V3 nr = r.axis(k) * sigma;  // the reference face's outward normal
    // eq 103: n is -nr for a's face (b -> a), +nr for b's; the face faces the other box.
    const V3 want_n = ref_is_b ? nr : V3(-nr);
    chk("face normal", (n - want_n).cwiseAbs().maxCoeff(), O(eps));
    chk.at_least("the reference face faces the other box", (ref_is_b ? -d : d).dot(nr), O(0), e_geo);
    // eqs 100-102: the best face of its box, a's unless b's beats it by the
    // margin, and no edge beating it by the margin.
    const O s_f = ref_is_b ? sB[k] : sA[k];
    chk.at_least("the best face of its box", s_f, ref_is_b ? best_b : best_a, 2 * e_face);
    if (ref_is_b) chk.at_least("b's face beats a's by the margin", s_f, margin(best_a), O(2.1) * e_face);
    else chk.at_least("a's face is not beaten by b's", margin(s_f), best_b, O(2.1) * e_face);
    for (int e = 0; e < 9; ++e)
      if (edge_counts(e)) chk.at_least("no edge beats the face", margin(s_f), sE[e], e_edge(e) + O(1.05) * e_face);
    // eq 103: the incident face is the one most anti-parallel to nr.
    O best_dot(0);
    for (int j = 0; j < 3; ++j) best_dot = std::max(best_dot, abs(in.axis(j).dot(nr)));
    chk.at_least("the incident face is the most anti-parallel", abs(in.axis(f).dot(nr)), best_dot, e_geo);
    chk.at_least("the incident face opposes the reference face", O(0), in.axis(f).dot(nr) * sf, e_geo);
    // eqs 104-105: each point d/2 below the reference face, inside its side
    // planes, its incident point on the incident face.
    const int a1 = k == 0 ? 1 : 0, a2 = k == 2 ? 1 : 2, u = f == 0 ? 1 : 0, v = f == 2 ? 1 : 2;
    O deepest(-1e300);
    for (int q = 0; q < m.count; ++q) {
      const V3 p = exact(m.point[q]);
      const O depth = exact(m.penetration[q]);
      deepest = std::max(deepest, depth);
      const V3 x = r.R.transpose() * (p - r.p);
      const O dist = sigma * x[k] - r.h[k];  // signed distance to the reference face plane, outward
      chk("point depth/2 below the reference face", dist + depth / 2, e_geo);
      chk.at_least("point inside the side planes", r.h[a1], abs(x[a1]), e_geo);
      chk.at_least("point inside the side planes", r.h[a2], abs(x[a2]), e_geo);
      chk.at_least("point depth > -tol", depth, -tol, e_geo);
      // eq 104 clips against the side planes moved out by the clip margin and
      // clamps onto the face: a point is off the incident face by at most the
      // margin per clamped axis (the clamp moves it along each of the two side
      // planes' normals by up to that much): 2 margins.
      const V3 y = in.R.transpose() * (p - nr * (depth / 2) - in.p);
      chk("incident point on the incident face", sf * y[f] - in.h[f], e_geo + 2 * kClipMargin);
      chk.at_least("incident point within the incident face", in.h[u], abs(y[u]), e_geo + 2 * kClipMargin);
      chk.at_least("incident point within the incident face", in.h[v], abs(y[v]), e_geo + 2 * kClipMargin);
    }
    // The deepest point is the deepest of (incident face) ∩ (side planes
    // moved out by the margin) ...
    chk.at_least("the deepest point is the deepest of the clipped face",
                 max_depth(r, k, sigma, in, f, sf, e_geo + kClipMargin), deepest, e_geo);
    chk.at_least("the deepest point is the deepest of the clipped face", deepest, max_depth(r, k, sigma, in, f, sf, -e_geo),
                 e_geo);
  }, kBoxCases);
  std::printf("[ oracle ] %s: %d face contacts (%d on a face of b), %d edge contacts, %d without contact\n",
              Num<T>::kName, counts.face, counts.face_b, counts.edge, counts.none);
  for (const auto& [what, ratio] : chk.worst) std::printf("[ oracle ]   %-55s worst %.3g of its bound\n", what.c_str(), ratio);
  // Each kind of result is common enough that these floors (a fifth of the
  // usual counts or less) are never missed by chance.
  EXPECT_GT(counts.face, kBoxCases / 10);
  EXPECT_GT(counts.edge, kBoxCases / 20);
  EXPECT_GT(counts.none, kBoxCases / 100);
}

}  // namespace
}  // namespace lockstep::test
