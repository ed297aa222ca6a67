// Appendix A constants converted once into the engine's number type T.
// Derived factors (such as 1 - lambda*dt) are computed in T, so the fixed
// engine's values are the Q16.16 results of the stated formulas.
#pragma once
#include "lockstep/math/vec.hpp"
#include "lockstep/scene.hpp"

namespace lockstep {

template <class T>
struct Params {
  T dt, half_dt, inv_dt;
  Vec3<T> gravity;                  // g (m/s^2), eq 5
  Vec3<T> gravity_dt;               // g*dt, the per-frame velocity change of eq 1/5
  T linear_damping_factor;          // 1 - lambda_v*dt (eq 6)
  T angular_damping_factor;         // 1 - lambda_w*dt (eq 13)
  T inv_cell_size;                  // 1 / cell_size (eq 26)
  T slop, baumgarte;                // eq 63
  int solver_iterations;
  int converged_pass;               // eq 113: from this pass (0-based: solver_iterations / 4) on, converged visits are skipped
  T converged_speed;                // eq 113 (m/s, rad/s; default 0: never): a visit whose sides changed less is converged
  T contact_tolerance;              // eqs 84, 97: speculative contact distance
  T support_fade;                   // eq 98: max(slop, |g dt| dt) (m); |g dt| dt: how far a body falls from rest in one frame
  T kp, kd_dt, speed_factor_min, speed_factor_max;  // eqs 69-71
  T support_normal_min;
  T align_fine, align_good, align_fair, damp_fine, damp_good, damp_fair;  // eqs 72-74
  T rest_speed;                     // eq 75
  T restitution_min_speed;          // eq 76
  T settle_speed, settle_factor;    // eq 77: factor = 1 - settle_damping
  T sleep_linear, sleep_angular, sleep_alignment, drowsy_damping;  // eqs 78-79
  // eq 78 for small bodies: below this half-diagonal (m), 0.5 m, the spin
  // test is on the corner speed |w| r < sleep_angular * 0.5 m.
  T sleep_small_radius, sleep_corner_speed;
  int drowsy_frames, sleep_frames;  // eqs 79-80
  T wake_speed, wake_penetration;   // eq 81
  T wake_support_distance;          // eq 108
  T righting_min_axis;              // 2^-12: below it the righting axis (68) is undefined

  static Params from(const Constants& c) {
    auto n = [](double x) { return Num<T>::from_double(x); };
    Params p;
    p.dt = n(c.dt);
    p.half_dt = p.dt * n(0.5);
    p.inv_dt = n(1.0) / p.dt;
    p.gravity = Vec3<T>{n(c.gravity.x), n(c.gravity.y), n(c.gravity.z)};
    p.gravity_dt = p.gravity * p.dt;
    p.linear_damping_factor = n(1.0) - n(c.linear_damping) * p.dt;
    p.angular_damping_factor = n(1.0) - n(c.angular_damping) * p.dt;
    p.inv_cell_size = n(1.0) / n(c.cell_size);
    p.slop = n(c.slop);
    p.baumgarte = n(c.baumgarte);
    p.solver_iterations = c.solver_iterations;
    p.converged_pass = c.solver_iterations / 4;
    p.converged_speed = n(c.converged_speed);
    p.contact_tolerance = n(c.contact_tolerance);
    p.support_fade = Num<T>::max(p.slop, length(p.gravity_dt) * p.dt);
    p.kp = n(c.kp);
    p.kd_dt = n(c.kd) * p.dt;
    p.speed_factor_min = n(c.speed_factor_min);
    p.speed_factor_max = n(c.speed_factor_max);
    p.support_normal_min = n(c.support_normal_min);
    p.align_fine = n(c.align_fine);
    p.align_good = n(c.align_good);
    p.align_fair = n(c.align_fair);
    p.damp_fine = n(c.damp_fine);
    p.damp_good = n(c.damp_good);
    p.damp_fair = n(c.damp_fair);
    p.rest_speed = n(c.rest_speed);
    p.restitution_min_speed = n(c.restitution_min_speed);
    p.settle_speed = n(c.settle_speed);
    p.settle_factor = n(1.0) - n(c.settle_damping);
    p.sleep_linear = n(c.sleep_linear);
    p.sleep_angular = n(c.sleep_angular);
    p.sleep_small_radius = n(0.5);
    p.sleep_corner_speed = n(c.sleep_angular * 0.5);
    p.sleep_alignment = n(c.sleep_alignment);
    p.drowsy_damping = n(c.drowsy_damping);
    p.drowsy_frames = c.drowsy_frames;
    p.sleep_frames = c.sleep_frames;
    p.wake_speed = n(c.wake_speed);
    p.wake_penetration = n(c.wake_penetration);
    p.wake_support_distance = n(c.wake_support_distance);
    p.righting_min_axis = n(1.0 / 4096.0);
    return p;
  }
};

}  // namespace lockstep
