// Formula cases: the per-equation functions that the GPU engine's kernels
// call, evaluated on packed float inputs, so that a test can run the very
// same code on the device and on the host and compare the results in ulps
// (tests/gpu/formula_cases_test.cpp; docs/GPU.md "Kernel verification").
#pragma once
#include <vector>

#include "lockstep/gpu/elements.hpp"

namespace lockstep::gpu {

inline constexpr int kFormulaInputs = 32;   // floats per case
inline constexpr int kFormulaOutputs = 16;  // floats per result

enum FormulaKind : int {
  kFormulaIntegrate = 0,  // eqs 1, 5, 6, 13, 2, 7-10
  kFormulaRotation,       // rotation matrix, eq 31
  kFormulaPair,           // eqs 38-43, 85
  kFormulaSolve,          // eqs 48-62, 76, 86-88 (two unit-mass cubes)
  kFormulaGround,         // eq 84 corner depths
  kFormulaSettle,         // eqs 64-75, 77
  kFormulaSleep,          // eqs 78-80
  kFormulaSdf,            // eqs 32-34
  kFormulaKinds
};

inline const char* formula_kind_name(int kind) {
  static const char* const kNames[kFormulaKinds] = {"integrate", "rotation", "pair", "solve",
                                                    "ground", "settle", "sleep", "sdf"};
  return kind >= 0 && kind < kFormulaKinds ? kNames[kind] : "?";
}

// Evaluates one case: in[kFormulaInputs] -> out[kFormulaOutputs] (unused outputs 0).
LS_HD inline void evaluate_formula_case(int kind, const Params<float>& P, const float* in, float* out) {
  for (int k = 0; k < kFormulaOutputs; ++k) out[k] = 0.0f;
  auto v3 = [in](int o) { return Vec3<float>{in[o], in[o + 1], in[o + 2]}; };
  auto q4 = [in](int o) { return normalize(Quat<float>{in[o], in[o + 1], in[o + 2], in[o + 3]}); };
  auto put3 = [out](int o, const Vec3<float>& v) { out[o] = v.x; out[o + 1] = v.y; out[o + 2] = v.z; };
  switch (kind) {
    case kFormulaIntegrate: {
      Vec3<float> v = v3(0), w = v3(3), p = v3(6);
      Quat<float> q = q4(9);
      integrate_velocity(v, w, true, true, P);
      integrate_pose(p, q, v, w, P);
      put3(0, v); put3(3, w); put3(6, p);
      out[9] = q.w; out[10] = q.x; out[11] = q.y; out[12] = q.z;
      break;
    }
    case kFormulaRotation: {
      const Mat3<float> R = rotation_matrix(q4(0));
      for (int r = 0; r < 3; ++r) put3(3 * r, R.row[r]);
      put3(9, rotated_half_extents(R, v3(4)));
      break;
    }
    case kFormulaPair: {
      const float tol = P.contact_tolerance;
      const PairContact<float> c = pair_contact(v3(0), v3(3), v3(6), v3(9), tol * 0.5f, tol);
      out[0] = c.hit ? 1.0f : 0.0f;
      out[1] = c.penetration;
      put3(2, c.n);
      put3(5, c.point);
      break;
    }
    case kFormulaSolve: {
      const Vec3<float> h{0.5f, 0.5f, 0.5f};
      const Vec3<float> I = box_inverse_inertia(h, 1.0f, 3.0f);
      BodyView<float> A = dynamic_view(v3(0), v3(3), 1.0f, rotation_matrix(q4(6)), I);
      BodyView<float> B = dynamic_view(v3(10), v3(13), 1.0f, rotation_matrix(q4(16)), I);
      const Vec3<float> n = normalize(v3(26));
      const Vec3<float> r1 = v3(20), r2 = v3(23);
      SolveCounts counts;
      ContactState<float> c = prepare_contact(A, r1, B, r2, n, in[29], in[30], 0.3f, 0.6f, true, true, P, counts);
      warm_start_contact(A, r1, B, r2, n, c, 0.01f, P);
      for (int it = 0; it < 2; ++it) solve_contact(A, r1, B, r2, n, in[31], c, true, true, 1.0f, P, counts);
      put3(0, A.v); put3(3, A.w); put3(6, B.v); put3(9, B.w);
      out[12] = c.j_n;
      out[13] = c.j_t.x + c.j_t.y + c.j_t.z;
      out[14] = static_cast<float>(counts.normal_impulses + 4 * counts.friction_steps + 16 * counts.restitution_bounces);
      break;
    }
    case kFormulaGround: {
      const Mat3<float> R = rotation_matrix(q4(3));
      for (int c = 0; c < 8; ++c) {
        Vec3<float> corner;
        out[c] = ground_corner_depth(v3(0), R, v3(7), c, in[10], corner);
        if (c < 2) put3(8 + 3 * c, corner);
      }
      break;
    }
    case kFormulaSettle: {
      Vec3<float> v = v3(0);
      const float speed = settle_linear_velocity(v, v3(3), normalize(v3(6)), Num<float>::abs(in[19]) * 0.01f, P, false,
                                                 P.settle_speed);
      put3(0, v);
      out[3] = speed;
      put3(4, settle_angular_velocity(v3(9), rotation_matrix(q4(12)), normalize(v3(16)), speed, true, in[20] > 0.5f,
                                      P));  // in[20] > 0.5: leaning (eq 115), not righted
      break;
    }
    case kFormulaSleep: {
      Vec3<float> v = v3(0), w = v3(3);
      int counter = static_cast<int>(in[10]);
      // radius in [0, 2] m: both branches of eq 78; in[16] > 0.5: leaning (eq 115)
      const bool asleep = update_sleep(v, w, counter, in[11] > 0.0f, true, in[16] > 0.5f, true, true, rotation_matrix(q4(6)),
                                       normalize(v3(12)), Num<float>::abs(in[15]), P);
      put3(0, v); put3(3, w);
      out[6] = static_cast<float>(counter);
      out[7] = asleep ? 1.0f : 0.0f;
      break;
    }
    case kFormulaSdf: {
      SdfGrid<float> g;
      g.min = {0.0f, 0.0f, 0.0f};
      g.max = {1.0f, 2.0f, 1.0f};
      g.n[0] = 2; g.n[1] = 3; g.n[2] = 2;
      g.inv_spacing = {1.0f, 1.0f, 1.0f};
      g.spacing = {1.0f, 1.0f, 1.0f};
      g.values = in + 3;  // 12 samples
      out[0] = sdf_distance(g, v3(0));
      put3(1, sdf_gradient(g, v3(0)));
      break;
    }
    default: break;
  }
}

// Evaluates n = inputs.size() / kFormulaInputs cases of one kind with the
// default constants (Params<float>::from(Constants{})).
std::vector<float> evaluate_formula_cases_on_host(int kind, const std::vector<float>& inputs);
// The same on the CUDA device; throws std::runtime_error without one.
std::vector<float> evaluate_formula_cases_on_device(int kind, const std::vector<float>& inputs);

}  // namespace lockstep::gpu
