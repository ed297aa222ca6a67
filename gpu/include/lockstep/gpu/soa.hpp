// Structure-of-arrays state of the GPU engine: one array per quantity, each
// element a 16-byte group of the number type (T4<T>: F4 for float, Q4 for
// Q16.16, both four 4-byte values) so that a thread reads a neighbour's
// position, orientation or velocity with one aligned 128-bit load. The same
// layout is used on the device and by the host build (then the pointers are
// host memory), for both number types.
#pragma once
#include <cstdint>
#include <type_traits>

#include "lockstep/hd.hpp"
#include "lockstep/math/vec.hpp"

namespace lockstep::gpu {

template <class T>
struct alignas(16) T4 {
  T x{}, y{}, z{}, w{};
};
using F4 = T4<float>;
static_assert(sizeof(F4) == 16 && alignof(F4) == 16, "one 128-bit load per group");

template <class T>
LS_HD inline Vec3<T> xyz(const T4<T>& a) { return {a.x, a.y, a.z}; }
template <class T>
LS_HD inline T4<T> f4(const Vec3<T>& v, const std::type_identity_t<T>& w) { return {v.x, v.y, v.z, w}; }
// A quaternion (w, x, y, z) is stored as T4{w, x, y, z}.
template <class T>
LS_HD inline Quat<T> quat(const T4<T>& a) { return {a.x, a.y, a.z, a.w}; }
template <class T>
LS_HD inline T4<T> f4(const Quat<T>& q) { return {q.w, q.x, q.y, q.z}; }

// Body flags (one byte per body).
inline constexpr std::uint8_t kFlagStatic = 1;  // never moves, m^-1 = 0
inline constexpr std::uint8_t kFlagAsleep = 2;  // 4.7; cleared by a wake (81)

// Per-body state, indexed by body (scene order). Units as in lockstep::Body.
template <class T>
struct BodyArrays {
  using F4 = T4<T>;
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

// The fourth value of the packed per-body groups, by name: pos's inverse
// mass, half's restitution, inert's friction, aabb's largest half extent.
template <class T> LS_HD inline T inv_mass_of(const T4<T>& pos) { return pos.w; }
template <class T> LS_HD inline T restitution_of(const T4<T>& half) { return half.w; }
template <class T> LS_HD inline T friction_of(const T4<T>& inert) { return inert.w; }
template <class T> LS_HD inline T max_half_of(const T4<T>& aabb) { return aabb.w; }

// A body is awake when it is neither static nor asleep (woken bodies included).
LS_HD inline bool is_awake(std::uint8_t f) { return (f & (kFlagStatic | kFlagAsleep)) == 0; }

}  // namespace lockstep::gpu
