// lockstep's math layer (lockstep/math/vec.hpp, and for Q16 the exact-
// accumulator overloads of lockstep/fixed/q16_vec.hpp) against the Eigen
// oracle of eigen_oracle.hpp, on Q16, float, double and mp (issue 16).
//
// Every check is `|lockstep - oracle| <= bound`, the bound stated in ulps of
// the type (eps: 2^-16 Q16, 2^-23 float, 2^-52 double, 2^-112 mp):
//
//  * Q16: the bounds of fixed/README.md ("Error bounds"): 1/2 ulp for every
//    one-rounding operation (dot, cross, quaternion product, the entries of
//    rotation_matrix against the polynomial P(q)); rotate against P(q) v:
//    1/2 + norm1(v)/2; against the rotation of q/|q|: plus (N - 1)(R - I),
//    at most 2|N - 1| per diagonal entry, |N - 1| off the diagonal and
//    2|N - 1| len(v) for rotate (N = |q|^2, exact); normalize: 1/2 + 2^15/L.
//  * float, double, mp: the standard rounding model (u = eps/2, gamma_n =
//    n u / (1 - n u)), derived beside each check from the order lockstep
//    evaluates its formulas in (left to right, -ffp-contract=off).
//
// The inputs are rapidcheck-generated unit quaternions with 180-degree
// turns, 45-degree ties and tiny angles, vectors, and boxes from flat plates
// to cubes (eigen_oracle.hpp). A sign convention changed anywhere in the
// math layer (the order of the quaternion product, the direction of the
// rotation, a transposed matrix, the sign of a cross product) is an error of
// order 1, a million ulps and more for every type but Q16 (65,536 ulps
// there): each check below fails on the first random case.
//
// Each test prints the worst error it saw, in ulps, and its ratio to the
// bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "eigen_oracle.hpp"
#include "fixed/prop.hpp"
#include "lockstep/physics/integrate.hpp"

namespace lockstep::test {
namespace {

using namespace oracle;

// Cases per property and number type: 400 (a few hundred ms per test).
constexpr int kOracleCases = 400;

// The worst error seen in one test, in ulps and as a fraction of its bound.
struct Worst {
  double ulps = 0, ratio = 0;
  std::string what;
  void print(const char* type) const {
    std::printf("[ oracle ] %s: worst error %.3g ulp (%.3g of its bound) in %s\n", type, ulps, ratio, what.c_str());
  }
};

// Fails the rapidcheck case (with every number needed to judge it) unless
// |err| <= bound (both absolute, in units); records the worst.
template <class T>
void within(Worst& w, const std::string& what, const O& err, double bound) {
  const double e = std::fabs(dbl(err)), eps = Model<T>::eps(), b = bound + Model<T>::oracle();
  if (!(e <= b))
    RC_FAIL(std::string(Num<T>::kName) + " " + what + ": error " + std::to_string(e / eps) + " ulp > bound " +
            std::to_string(b / eps) + " ulp");
  if (e / b > w.ratio) {
    w.ratio = e / b;
    w.ulps = e / eps;
    w.what = what;
  }
}

template <class T>
class EigenOracle : public ::testing::Test {};
TYPED_TEST_SUITE(EigenOracle, EngineTypes);

// Hamilton product a * b against Eigen's Quaternion product. Q16: one
// rounding per component (1/2 ulp). Floating: four products summed left to
// right, gamma_4 times the sum of |terms| <= |a| |b| (Cauchy-Schwarz).
TYPED_TEST(EigenOracle, QuaternionProduct) {
  using T = TypeParam;
  Worst worst;
  lockstep_test::check_prop([&] {
    const Quat<T> a = round_to<T>(gen_unit_quaternion(gen_rotation()));
    const Quat<T> b = round_to<T>(gen_unit_quaternion(gen_rotation()));
    const Quat<T> got = a * b;
    const Q want = exact(a) * exact(b);
    const double eps = Model<T>::eps();
    const double bound = Model<T>::kFixed ? 0.5 * eps : Model<T>::gamma(4) * eps * dbl(exact(a).norm() * exact(b).norm());
    within<T>(worst, "w", exact(got.w) - want.w(), bound);
    within<T>(worst, "x", exact(got.x) - want.x(), bound);
    within<T>(worst, "y", exact(got.y) - want.y(), bound);
    within<T>(worst, "z", exact(got.z) - want.z(), bound);
  }, kOracleCases);
  worst.print(Num<T>::kName);
}

// The rotation matrix of a quaternion (eq 31's R, eq 90's R) against
//  (a) Eigen's toRotationMatrix of the same, unnormalised q: the polynomial
//      P(q). Q16: 1/2 ulp. Floating: 1 - 2(yy + zz) is two squares, a sum, a
//      product by 2 (exact) and a difference: 2(2u + u^2) S + u|1 - 2S|
//      (S = yy + zz); 2(xy - wz): 4u (|xy| + |wz|)(1 + u) <= 2u N (1 + u).
//  (b) the rotation of q/|q|: P(q) - R = (N - 1)(R - I), plus 2|N - 1| on
//      the diagonal, |N - 1| off it.
//  (c) Rodrigues' formula (Eigen's AngleAxis::toRotationMatrix) of the exact
//      angle and axis q was rounded from: independent of every quaternion
//      formula, so a transposed R or a rotation the wrong way round fails
//      here even if lockstep and Eigen shared a convention. q's rounding
//      (<= 0.51 eps per component, double rounding included) moves q/|q| by
//      at most 2.04 eps, and each entry of R(q) is a quadratic form of norm
//      1 on unit q: plus 4.1 eps per entry.
TYPED_TEST(EigenOracle, RotationMatrix) {
  using T = TypeParam;
  Worst worst;
  lockstep_test::check_prop([&] {
    const AA r = gen_rotation();
    const Quat<T> q = round_to<T>(gen_unit_quaternion(r));
    const Mat3<T> got = rotation_matrix(q);
    const Q qe = exact(q);
    const M3 P = qe.toRotationMatrix(), R = qe.normalized().toRotationMatrix(), RR = r.toRotationMatrix();
    const double eps = Model<T>::eps(), N = dbl(qe.squaredNorm()), dN = dbl(abs(qe.squaredNorm() - 1));
    const O S[3] = {qe.y() * qe.y() + qe.z() * qe.z(), qe.x() * qe.x() + qe.z() * qe.z(),
                    qe.x() * qe.x() + qe.y() * qe.y()};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const bool diag = i == j;
        double b;
        if (Model<T>::kFixed) b = 0.5 * eps;
        else if (diag) b = (2 * (1 + eps) * dbl(S[i]) * 1.0001 + 0.5 * std::fabs(1 - 2 * dbl(S[i])) * 1.0001) * eps;
        else b = 1.0001 * N * eps;
        const std::string at = "R[" + std::to_string(i) + "][" + std::to_string(j) + "]";
        const O e = exact(got.row[i][j]);
        within<T>(worst, at + " vs P(q)", e - P(i, j), b);
        const double bn = b + (diag ? 2 : 1) * dN;
        within<T>(worst, at + " vs R(q/|q|)", e - R(i, j), bn);
        within<T>(worst, at + " vs AngleAxis", e - RR(i, j), bn + 4.1 * eps);
      }
  }, kOracleCases);
  worst.print(Num<T>::kName);
}

// rotate(q, v) = P(q) v, against (a) the exact P(q) v, (b) Eigen's q/|q| * v
// and (c) AngleAxis * v (as RotationMatrix). Q16 (fixed/README.md): (a)
// 1/2 + norm1(v)/2 ulp, (b) plus 2|N - 1| len(v). Floating: the entry bound
// b_P of RotationMatrix times norm1(v), and a 3-term dot, gamma_3 times
// sum |P_ij v_j| <= (N + |1 - N| + b_P) norm1(v).
TYPED_TEST(EigenOracle, RotateVector) {
  using T = TypeParam;
  Worst worst;
  lockstep_test::check_prop([&] {
    const AA r = gen_rotation();
    const Quat<T> q = round_to<T>(gen_unit_quaternion(r));
    const Vec3<T> v = round_to<T>(gen_vector(8));
    const Vec3<T> got = rotate(q, v);
    const Q qe = exact(q);
    const V3 ve = exact(v);
    const V3 a = qe.toRotationMatrix() * ve, b = qe.normalized() * ve, c = r * ve;
    const double eps = Model<T>::eps(), N = dbl(qe.squaredNorm()), dN = dbl(abs(qe.squaredNorm() - 1));
    const double n1 = norm1(ve), len = dbl(ve.norm());
    double bound;
    if (Model<T>::kFixed) {
      bound = 0.5 * eps + 0.5 * eps * n1;
    } else {
      const double bP = std::max(2 * (1 + eps) * N * 1.0001 + 0.5 * (1 + 2 * N) * 1.0001, 1.0001 * N) * eps;
      bound = bP * n1 + Model<T>::gamma(3) * eps * (N + dN + bP) * n1;
    }
    const V3 e = exact(got);
    for (int i = 0; i < 3; ++i) {
      const std::string at = "component " + std::to_string(i);
      within<T>(worst, at + " vs P(q) v", e[i] - a[i], bound);
      within<T>(worst, at + " vs q/|q| * v", e[i] - b[i], bound + 2 * dN * len);
      within<T>(worst, at + " vs AngleAxis * v", e[i] - c[i], bound + 2 * dN * len + 4.1 * eps * n1);
    }
  }, kOracleCases);
  worst.print(Num<T>::kName);
}

// normalize(q) and normalize(v) against Eigen's normalized(), for lengths in
// [1/16, 16]. Q16 (fixed/README.md): 1/2 + 2^15/L ulp, L = round(len 2^16).
// Floating: the sum of n squares (gamma_n), a square root (halves it, adds
// u) and a division (u): (gamma_n / 2 + 2u)|n_i|.
TYPED_TEST(EigenOracle, Normalize) {
  using T = TypeParam;
  Worst worst;
  lockstep_test::check_prop([&] {
    const O scale(log_uniform(1.0 / 16, 16));
    const Quat<T> q = round_to<T>(Q(gen_unit_quaternion(gen_rotation()).coeffs() * scale));
    const Vec3<T> v = round_to<T>(gen_axis() * scale);
    const Quat<T> nq = normalize(q);
    const Vec3<T> nv = normalize(v);
    const Q want_q = exact(q).normalized();
    const V3 want_v = exact(v).normalized();
    const double eps = Model<T>::eps();
    auto bound = [&](const O& len, const O& component, int n) {
      if (Model<T>::kFixed) return 0.5 * eps + std::ldexp(1.0, 15) / std::nearbyint(dbl(len) * 65536) * eps;
      return (Model<T>::gamma(n) / 2 + 1) * 1.0001 * eps * std::fabs(dbl(component));
    };
    const O lq = exact(q).norm(), lv = exact(v).norm();
    within<T>(worst, "quaternion w", exact(nq.w) - want_q.w(), bound(lq, want_q.w(), 4));
    within<T>(worst, "quaternion x", exact(nq.x) - want_q.x(), bound(lq, want_q.x(), 4));
    within<T>(worst, "quaternion y", exact(nq.y) - want_q.y(), bound(lq, want_q.y(), 4));
    within<T>(worst, "quaternion z", exact(nq.z) - want_q.z(), bound(lq, want_q.z(), 4));
    for (int i = 0; i < 3; ++i)
      within<T>(worst, "vector " + std::to_string(i), exact(nv[i]) - want_v[i], bound(lv, want_v[i], 3));
  }, kOracleCases);
  worst.print(Num<T>::kName);
}

// dot and cross (eq 51) against Eigen's dot() and cross(). Q16: 1/2 ulp.
// Floating: dot gamma_3 sum |a_i b_i|; each cross component p1 - p2 of two
// products 2u (|p1| + |p2|)(1 + u).
TYPED_TEST(EigenOracle, DotAndCross) {
  using T = TypeParam;
  Worst worst;
  lockstep_test::check_prop([&] {
    const Vec3<T> a = round_to<T>(gen_vector(8)), b = round_to<T>(gen_vector(8));
    const V3 ae = exact(a), be = exact(b);
    const double eps = Model<T>::eps();
    const double bd = Model<T>::kFixed ? 0.5 * eps : Model<T>::gamma(3) * eps * dbl(ae.cwiseAbs().dot(be.cwiseAbs()));
    within<T>(worst, "dot", exact(dot(a, b)) - ae.dot(be), bd);
    const V3 c = ae.cross(be), got = exact(cross(a, b));
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const double bc = Model<T>::kFixed ? 0.5 * eps : (1 + eps) * eps * dbl(abs(ae[j] * be[k]) + abs(ae[k] * be[j]));
      within<T>(worst, "cross " + std::to_string(i), got[i] - c[i], bc);
    }
  }, kOracleCases);
  worst.print(Num<T>::kName);
}

// A box's inverse inertia in the world frame (eqs 14-18, 90), against the
// inverse of the world inertia tensor R I R^T (Eigen's Matrix3 inverse),
// R the rotation of q/|q|: a transposed R (R^T I^-1 R) or a wrong moment
// fails. Boxes from flat plates and rods to cubes (the cube short cut of
// eq 90), masses 0.5-50 kg.
//  (a) box_inverse_inertia against 3 m^-1 / (h_j^2 + h_k^2). Q16: the sum
//      of two rounded squares is within 1 ulp of s, then two roundings of
//      1/2: m^-1 (3 / (s (s - 1 ulp)) + 1/2) + 1/2 ulp. Floating: 2u for s,
//      u for the division and u for the product: 4u (1.0001) relative.
//  (b) apply_inverse_inertia(R_T, D, x) against (R I R^T)^-1 x, with D the
//      lockstep diagonal from (a) taken as exact and R_T lockstep's rotation
//      matrix, each entry within e_R of R (RotationMatrix (b)). Through
//      z = R_T^T x, w = D z and y = R_T w, with n1 = norm1(x), dmax = max D:
//      Q16 |dz| <= e_R n1 + 1/2, |dw| <= dmax |dz| + 1/2,
//          |dy| <= 3 (1 + e_R)|dw| + 3 e_R (dmax (1 + e_R) n1 + |dw|) + 1/2;
//      floating |dz| <= (e_R + gamma_3 (1 + e_R)) n1,
//          |dw| <= dmax (|dz| + u (1 + e_R) n1),
//          |dy| <= 3 (1 + e_R)|dw| + 3 dmax (1 + e_R) n1 (e_R + gamma_3 (1 + e_R)),
//      all times 1.001 for the second-order terms.
TYPED_TEST(EigenOracle, BoxInertiaInWorldFrame) {
  using T = TypeParam;
  Worst worst;
  lockstep_test::check_prop([&] {
    const int shape = *rc::gen::inRange(0, 3);  // 0 any box, 1 cube, 2 plate or rod
    V3 h(O(real(0.1, 2)), O(real(0.1, 2)), O(real(0.1, 2)));
    if (shape == 1) h = V3::Constant(h.x());
    if (shape == 2) h[*rc::gen::inRange(0, 3)] = O(real(0.05, 0.1));
    const Vec3<T> hT = round_to<T>(h);
    const T inv_mass = round_to<T>(O(1) / O(log_uniform(0.5, 50)));
    const Vec3<T> D = box_inverse_inertia(hT, inv_mass, Num<T>::from_int(3));
    const double eps = Model<T>::eps();
    const V3 he = exact(hT);
    const O im = exact(inv_mass);
    V3 De;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      const O s = he[j] * he[j] + he[k] * he[k];
      De[i] = O(3) * im / s;
      double b;
      if (Model<T>::kFixed) b = (dbl(im) * (3 / (dbl(s) * (dbl(s) - eps)) + 0.5) + 0.5) * eps;
      else b = 2 * 1.0001 * eps * dbl(De[i]);
      within<T>(worst, "I^-1 body " + std::to_string(i), exact(D[i]) - De[i], b);
    }
    // (b): the world frame.
    const Quat<T> q = round_to<T>(gen_unit_quaternion(gen_rotation()));
    const Vec3<T> x = round_to<T>(gen_vector(4));
    const Mat3<T> RT = rotation_matrix(q);
    const Vec3<T> got = apply_inverse_inertia(RT, D, x);
    const Q qe = exact(q);
    const M3 R = qe.normalized().toRotationMatrix();
    M3 I_body = M3::Zero();
    for (int i = 0; i < 3; ++i) I_body(i, i) = O(1) / exact(D[i]);
    const M3 I_world = R * I_body * R.transpose();
    const V3 xe = exact(x), want = I_world.inverse() * xe;
    const double N = dbl(qe.squaredNorm()), dN = dbl(abs(qe.squaredNorm() - 1)), n1 = norm1(xe);
    const double dmax = dbl(exact(D).maxCoeff());
    double eR, b;
    if (Model<T>::kFixed) {
      eR = 0.5 * eps + 2 * dN;
      const double dz = eR * n1 + 0.5 * eps, dw = dmax * dz + 0.5 * eps;
      b = 3 * (1 + eR) * dw + 3 * eR * (dmax * (1 + eR) * n1 + dw) + 0.5 * eps;
    } else {
      eR = (2 * (1 + eps) * N * 1.0001 + 0.5 * (1 + 2 * N) * 1.0001) * eps + 2 * dN;
      const double g3 = Model<T>::gamma(3) * eps;
      const double dz = (eR + g3 * (1 + eR)) * n1, dw = dmax * (dz + 0.5 * eps * (1 + eR) * n1);
      b = 3 * (1 + eR) * dw + 3 * dmax * (1 + eR) * n1 * (eR + g3 * (1 + eR));
    }
    const V3 e = exact(got);
    for (int i = 0; i < 3; ++i)
      within<T>(worst, "I^-1 world x, component " + std::to_string(i), e[i] - want[i], 1.001 * b);
    RC_ASSERT(Num<T>::take_faults() == 0u);
  }, kOracleCases);
  worst.print(Num<T>::kName);
}

}  // namespace
}  // namespace lockstep::test
