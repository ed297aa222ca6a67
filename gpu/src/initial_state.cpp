#include "initial_state.hpp"

#include "lockstep/fixed/q16_num.hpp"
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/world.hpp"

namespace lockstep::gpu {
namespace {
template <class T>
Vec3<T> to_vec(const Vec3d& v) {
  return {Num<T>::from_double(v.x), Num<T>::from_double(v.y), Num<T>::from_double(v.z)};
}
// World<T>::check_faults at construction (frame 0): Q16's faults by body and quantity.
template <class T>
void check_faults(int body, const char* quantity) {
  if (const std::uint32_t f = Num<T>::take_faults()) throw RunError(0, body, quantity, q16_flag_name(f));
}
}  // namespace

template <class T>
InitialState<T> make_initial_state(const Scene& scene) {
  InitialState<T> s;
  auto n = [](double x) { return Num<T>::from_double(x); };
  s.n = static_cast<int>(scene.bodies.size());
  s.P = Params<T>::from(scene.constants);
  Num<T>::take_faults();  // World<T>: the constants' faults are not checked (its initialiser list)
  s.fx = scene.effects;
  s.oriented = scene.pair_contacts == PairModel::kOrientedBox;
  s.ground_on = scene.effects.ground && scene.ground.present;
  s.ground_y = n(scene.ground.height);
  s.ground_e = n(scene.ground.material.restitution);
  s.ground_mu = n(scene.ground.material.friction);
  check_faults<T>(-1, "constants and ground");
  const T three = Num<T>::from_int(3);
  const auto count = static_cast<std::size_t>(s.n);
  for (auto* v : {&s.pos, &s.rot, &s.aabb, &s.half, &s.inert, &s.vel, &s.ang}) v->resize(count);
  s.flags.assign(count, 0);
  s.sleep_counter.assign(count, 0);
  s.sleep_frame.assign(count, -1);
  T max_dynamic_radius{};
  for (std::size_t i = 0; i < count; ++i) {
    const BodyDesc& d = scene.bodies[i];
    // World<T>::World, term by term.
    const Vec3<T> p = to_vec<T>(d.position);
    const Vec3<T> v = d.is_static ? Vec3<T>{} : to_vec<T>(d.velocity);
    const Vec3<T> w = d.is_static ? Vec3<T>{} : to_vec<T>(d.angular_velocity);
    const Quat<T> q = normalize(Quat<T>{n(d.orientation.w), n(d.orientation.x), n(d.orientation.y), n(d.orientation.z)});  // eq 10
    const Vec3<T> h = to_vec<T>(d.half_extents);
    const T inv_mass = d.is_static ? T{} : Num<T>::from_int(1) / n(d.mass);
    const Vec3<T> inv_inertia = d.is_static ? Vec3<T>{} : box_inverse_inertia(h, inv_mass, three);  // eqs 14-18
    const T e = n(d.material.restitution), mu = n(d.material.friction);
    const Mat3<T> R = rotation_matrix(q);
    const Vec3<T> a = rotated_half_extents(R, h);  // eq 31
    check_faults<T>(static_cast<int>(i), "initial state (inverse mass, inertia, orientation, AABB)");
    s.pos[i] = f4(p, inv_mass);
    s.rot[i] = f4(q);
    s.aabb[i] = f4(a, Num<T>::max(a.x, Num<T>::max(a.y, a.z)));
    s.half[i] = f4(h, e);
    s.inert[i] = f4(inv_inertia, mu);
    s.vel[i] = f4(v, T{});
    s.ang[i] = f4(w, T{});
    s.flags[i] = static_cast<std::uint8_t>((d.is_static ? kFlagStatic : 0) | (d.asleep && !d.is_static ? kFlagAsleep : 0));
    if (d.is_static) ++s.n_static;
    else max_dynamic_radius = Num<T>::max(max_dynamic_radius, length(h));
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!(s.flags[i] & kFlagStatic)) {
      if (!(s.flags[i] & kFlagAsleep)) s.awake.push_back(static_cast<int>(i));
      continue;
    }
    if (length(xyz(s.half[i])) > Num<T>::from_int(2) * max_dynamic_radius) s.large.push_back(static_cast<int>(i));
    else ++s.n_static_small;
  }
  Num<T>::take_faults();  // the grids' choice of large statics only (no state)
  if (scene.effects.sdf) {
    for (const SdfDesc& d : scene.sdfs) {
      SdfGrid<T> g;
      g.min = to_vec<T>(d.min);
      g.max = to_vec<T>(d.max);
      g.n[0] = d.nx; g.n[1] = d.ny; g.n[2] = d.nz;
      set_grid_spacing(g);  // eq 32
      s.sdf_offsets.push_back(s.sdf_values.size());
      for (double v : d.values) s.sdf_values.push_back(n(v));
      s.sdf_grids.push_back(g);
      s.sdf_material.push_back(T4<T>{n(d.material.restitution), n(d.material.friction), T{}, T{}});
      check_faults<T>(-1, "SDF volume");
    }
  }
  return s;
}

template InitialState<float> make_initial_state<float>(const Scene&);
template InitialState<Q16> make_initial_state<Q16>(const Scene&);

}  // namespace lockstep::gpu
