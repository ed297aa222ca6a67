#include "initial_state.hpp"

#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/integrate.hpp"

namespace lockstep::gpu {
namespace {
Vec3<float> to_vec(const Vec3d& v) {
  return {Num<float>::from_double(v.x), Num<float>::from_double(v.y), Num<float>::from_double(v.z)};
}
}  // namespace

InitialState make_initial_state(const Scene& scene) {
  InitialState s;
  auto n = [](double x) { return Num<float>::from_double(x); };
  s.n = static_cast<int>(scene.bodies.size());
  s.P = Params<float>::from(scene.constants);
  s.fx = scene.effects;
  s.oriented = scene.pair_contacts == PairModel::kOrientedBox;
  s.ground_on = scene.effects.ground && scene.ground.present;
  s.ground_y = n(scene.ground.height);
  s.ground_e = n(scene.ground.material.restitution);
  s.ground_mu = n(scene.ground.material.friction);
  const float three = Num<float>::from_int(3);
  const auto count = static_cast<std::size_t>(s.n);
  for (auto* v : {&s.pos, &s.rot, &s.aabb, &s.half, &s.inert, &s.vel, &s.ang}) v->resize(count);
  s.flags.assign(count, 0);
  s.sleep_counter.assign(count, 0);
  s.sleep_frame.assign(count, -1);
  float max_dynamic_radius = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    const BodyDesc& d = scene.bodies[i];
    // World<T>::World, term by term.
    const Vec3<float> p = to_vec(d.position);
    const Vec3<float> v = d.is_static ? Vec3<float>{} : to_vec(d.velocity);
    const Vec3<float> w = d.is_static ? Vec3<float>{} : to_vec(d.angular_velocity);
    const Quat<float> q = normalize(Quat<float>{n(d.orientation.w), n(d.orientation.x), n(d.orientation.y), n(d.orientation.z)});  // eq 10
    const Vec3<float> h = to_vec(d.half_extents);
    const float inv_mass = d.is_static ? 0.0f : Num<float>::from_int(1) / n(d.mass);
    const Vec3<float> inv_inertia = d.is_static ? Vec3<float>{} : box_inverse_inertia(h, inv_mass, three);  // eqs 14-18
    const Mat3<float> R = rotation_matrix(q);
    const Vec3<float> a = rotated_half_extents(R, h);  // eq 31
    s.pos[i] = f4(p, inv_mass);
    s.rot[i] = f4(q);
    s.aabb[i] = f4(a, Num<float>::max(a.x, Num<float>::max(a.y, a.z)));
    s.half[i] = f4(h, n(d.material.restitution));
    s.inert[i] = f4(inv_inertia, n(d.material.friction));
    s.vel[i] = f4(v, 0.0f);
    s.ang[i] = f4(w, 0.0f);
    s.flags[i] = static_cast<std::uint8_t>((d.is_static ? kFlagStatic : 0) | (d.asleep && !d.is_static ? kFlagAsleep : 0));
    if (d.is_static) ++s.n_static;
    else max_dynamic_radius = Num<float>::max(max_dynamic_radius, length(h));
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!(s.flags[i] & kFlagStatic)) {
      if (!(s.flags[i] & kFlagAsleep)) s.awake.push_back(static_cast<int>(i));
      continue;
    }
    if (length(xyz(s.half[i])) > 2.0f * max_dynamic_radius) s.large.push_back(static_cast<int>(i));
    else ++s.n_static_small;
  }
  if (scene.effects.sdf) {
    for (const SdfDesc& d : scene.sdfs) {
      SdfGrid<float> g;
      g.min = to_vec(d.min);
      g.max = to_vec(d.max);
      g.n[0] = d.nx; g.n[1] = d.ny; g.n[2] = d.nz;
      set_grid_spacing(g);  // eq 32
      s.sdf_offsets.push_back(s.sdf_values.size());
      for (double v : d.values) s.sdf_values.push_back(n(v));
      s.sdf_grids.push_back(g);
      s.sdf_material.push_back(F4{n(d.material.restitution), n(d.material.friction), 0.0f, 0.0f});
    }
  }
  return s;
}

}  // namespace lockstep::gpu
