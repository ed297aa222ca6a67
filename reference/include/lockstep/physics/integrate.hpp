// Part 1 of docs/SPEC.md: integration and inertia, per body, host and device.
#pragma once
#include "lockstep/math/vec.hpp"

namespace lockstep {

// eq 1, 5: v(n+1) = v(n) + g*dt (gravity is the only applied force; g*dt precomputed).
template <class T>
LS_HD Vec3<T> apply_gravity(const Vec3<T>& v, const Vec3<T>& gravity_dt) { return v + gravity_dt; }

// eq 6 (linear) and eq 13 (angular): x * (1 - lambda*dt), factor precomputed.
template <class T>
LS_HD Vec3<T> apply_damping(const Vec3<T>& x, const T& factor) { return x * factor; }

// eq 2: p(n+1) = p(n) + v(n+1)*dt.
template <class T>
LS_HD Vec3<T> integrate_position(const Vec3<T>& p, const Vec3<T>& v, const T& dt) { return p + v * dt; }

// eqs 7-10: q(n+1) = normalize(q + (1/2)(0, w) q dt), w in the world frame.
template <class T>
LS_HD Quat<T> integrate_orientation(const Quat<T>& q, const Vec3<T>& w, const T& half_dt) {
  const Quat<T> wq{T{}, w.x, w.y, w.z};  // eq 7
  const Quat<T> d = wq * q;              // eq 8 without the 1/2, folded into half_dt
  return normalize(Quat<T>{q.w + d.w * half_dt, q.x + d.x * half_dt, q.y + d.y * half_dt,
                           q.z + d.z * half_dt});  // eqs 9, 10
}

// eqs 14-18 (with (19) corrected to I = m/6 for the unit cube): the body-frame
// inverse inertia of a box, I^-1_xx = 3 m^-1 / (hy^2 + hz^2), etc. Computed
// from m^-1 so a static body (m^-1 = 0) gets 0 without dividing by infinity.
template <class T>
LS_HD Vec3<T> box_inverse_inertia(const Vec3<T>& h, const T& inv_mass, const T& three) {
  const T xx = h.x * h.x, yy = h.y * h.y, zz = h.z * h.z;
  return {three / (yy + zz) * inv_mass, three / (xx + zz) * inv_mass, three / (xx + yy) * inv_mass};
}

// eq 90: I^-1_world x = R diag(I^-1_body) R^T x; for a cube (all three
// entries equal) this is exactly I^-1 x, and the rotation is skipped.
template <class T>
LS_HD_INLINE Vec3<T> apply_inverse_inertia(const Mat3<T>& R, const Vec3<T>& inv_inertia, const Vec3<T>& x) {
  if (inv_inertia.x == inv_inertia.y && inv_inertia.y == inv_inertia.z) return x * inv_inertia.x;
  return R * hadamard(inv_inertia, mat_transpose_mul(R, x));
}

}  // namespace lockstep
