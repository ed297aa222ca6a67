// Structure-of-arrays state of the GPU engine: one array per quantity, each
// element a 16-byte group (F4) so that a thread reads a neighbour's position,
// orientation or velocity with one aligned 128-bit load. The same layout is
// used on the device and by the host build (then the pointers are host memory).
#pragma once
#include <cstdint>

#include "lockstep/hd.hpp"
#include "lockstep/math/vec.hpp"

namespace lockstep::gpu {

struct alignas(16) F4 {
  float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

LS_HD inline Vec3<float> xyz(const F4& a) { return {a.x, a.y, a.z}; }
LS_HD inline F4 f4(const Vec3<float>& v, float w) { return {v.x, v.y, v.z, w}; }
// A quaternion (w, x, y, z) is stored as F4{w, x, y, z}.
LS_HD inline Quat<float> quat(const F4& a) { return {a.x, a.y, a.z, a.w}; }
LS_HD inline F4 f4(const Quat<float>& q) { return {q.w, q.x, q.y, q.z}; }

// Body flags (one byte per body).
inline constexpr std::uint8_t kFlagStatic = 1;  // never moves, m^-1 = 0
inline constexpr std::uint8_t kFlagAsleep = 2;  // 4.7; cleared by a wake (81)

// Per-body state, indexed by body (scene order). Units as in lockstep::Body.
struct BodyArrays {
  F4* pos = nullptr;      // p (m); w: inverse mass m^-1 (1/kg), 0 when static
  F4* rot = nullptr;      // unit quaternion q as {w, x, y, z}
  F4* aabb = nullptr;     // AABB half extents of eq 31 (m); w: their largest component
  F4* half = nullptr;     // box half extents h (m); w: restitution e (1)
  F4* inert = nullptr;    // body-frame diagonal of I^-1 (1/(kg m^2)), eqs 14-18; w: friction mu (1)
  F4* vel = nullptr;      // v (m/s), the state (w unused)
  F4* ang = nullptr;      // omega (rad/s, world), the state (w unused)
  std::uint8_t* flags = nullptr;
  int* sleep_counter = nullptr;  // eq 78
  int* sleep_frame = nullptr;    // frame at which it last fell asleep, -1 never
};

// The fourth float of the packed per-body groups, by name: pos's inverse
// mass, half's restitution, inert's friction, aabb's largest half extent.
LS_HD inline float inv_mass_of(const F4& pos) { return pos.w; }
LS_HD inline float restitution_of(const F4& half) { return half.w; }
LS_HD inline float friction_of(const F4& inert) { return inert.w; }
LS_HD inline float max_half_of(const F4& aabb) { return aabb.w; }

// A body is awake when it is neither static nor asleep (woken bodies included).
LS_HD inline bool is_awake(std::uint8_t f) { return (f & (kFlagStatic | kFlagAsleep)) == 0; }

}  // namespace lockstep::gpu
