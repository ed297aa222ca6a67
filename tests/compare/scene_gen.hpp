// RapidCheck generator of simple scenes for the agreement property: one to
// three boxes (random sizes, masses, poses, velocities, materials) dropped
// on the ground or, for a single box, into the SDF bowl of the built-in
// `bowl` scene. Sizes, masses, positions, velocities and materials are
// multiples of powers of two (exact in Q16.16, so every engine starts from the
// same values; orientations are normalised on load by each engine) and shrink
// towards the plain case: a unit cube of 1 kg at rest, upright, dropped from
// just above the ground at height 0.
//
// The scenes stay clear of knife edges, where an engine's rounding may
// rightly decide the outcome (which face a tumbling box lands on, whether a
// tower topples): tilts stay below 0.1 rad, spins below 0.5 rad/s, stacked
// boxes are upright, at rest, narrower than the box below and centred on it
// to within 1/8 m.
#pragma once
#include <rapidcheck.h>

#include <algorithm>
#include <cmath>
#include <ostream>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene.hpp"

namespace lockstep {
// How RapidCheck prints a counterexample: a summary (the full scene is the
// JSON file the property writes). Declared before any generator of Scene is
// instantiated, so that RapidCheck's show trait finds it.
inline void showValue(const Scene& s, std::ostream& os) {
  os << s.bodies.size() << " bodies, " << s.frames << " frames, ground " << (s.ground.present ? "y=" : "absent ")
     << s.ground.height << (s.sdfs.empty() ? "" : ", SDF " + s.sdfs[0].name);
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const BodyDesc& b = s.bodies[i];
    os << "\n  body " << i << ": h (" << b.half_extents.x << ", " << b.half_extents.y << ", " << b.half_extents.z << ") m, "
       << b.mass << " kg, p (" << b.position.x << ", " << b.position.y << ", " << b.position.z << "), q (" << b.orientation.w
       << ", " << b.orientation.x << ", " << b.orientation.y << ", " << b.orientation.z << "), v (" << b.velocity.x << ", "
       << b.velocity.y << ", " << b.velocity.z << "), w (" << b.angular_velocity.x << ", " << b.angular_velocity.y << ", "
       << b.angular_velocity.z << "), e " << b.material.restitution << ", mu " << b.material.friction;
  }
}
}  // namespace lockstep

namespace lockstep_test {

// k * step with k in [-max_steps, max_steps]; shrinks towards 0.
inline double centred(int max_steps, double step) {
  const int k = *rc::gen::inRange(0, max_steps + 1);
  const bool negative = *rc::gen::arbitrary<bool>();
  return (negative ? -k : k) * step;
}
// k * step with k in [0, max_steps]; shrinks towards 0.
inline double upto(int max_steps, double step) { return *rc::gen::inRange(0, max_steps + 1) * step; }

inline lockstep::Material gen_material() {
  lockstep::Material m;
  m.restitution = upto(8, 1.0 / 16);        // [0, 0.5]
  m.friction = 0.5 + centred(8, 1.0 / 32);  // [0.25, 0.75]
  return m;
}

inline rc::Gen<lockstep::Scene> gen_simple_scene() {
  return rc::gen::exec([] {
    using namespace lockstep;
    Scene s;
    s.name = "agreement_case";
    s.frames = 480;
    s.effects.sdf = false;
    const int n = *rc::gen::inRange(1, 4);
    const bool stacked = n > 1 && *rc::gen::arbitrary<bool>();
    const bool bowl = n == 1 && *rc::gen::inRange(0, 4) == 3;
    s.ground.height = bowl ? 0.0 : centred(16, 1.0 / 16);  // [-1, 1] m
    s.ground.material = gen_material();
    if (bowl) {
      s.effects.sdf = true;
      s.sdfs = builtin_scene("bowl")->sdfs;  // sphere of radius 6 about (0, 7, 0), floor at y = 1
      s.sdfs[0].material = gen_material();
    }
    double top = s.ground.height;  // stacked: the top of the box below (m)
    Vec3d below_half{1, 1, 1};
    for (int i = 0; i < n; ++i) {
      BodyDesc b;
      b.half_extents = {0.5 + centred(16, 1.0 / 64), 0.5 + centred(16, 1.0 / 64), 0.5 + centred(16, 1.0 / 64)};
      b.mass = 1.0 + centred(6, 1.0 / 8) + upto(12, 0.25);  // [0.25, 4.75] kg
      b.material = gen_material();
      if (stacked) {
        b.half_extents = {std::min(b.half_extents.x, below_half.x), b.half_extents.y,
                          std::min(b.half_extents.z, below_half.z)};
        below_half = b.half_extents;
        const double gap = upto(16, 1.0 / 64);  // [0, 0.25] m
        b.position = {centred(8, 1.0 / 64), top + gap + b.half_extents.y, centred(8, 1.0 / 64)};
        top = b.position.y + b.half_extents.y;
        s.bodies.push_back(b);
        continue;
      }
      // Free boxes, 4 m apart in x: they never meet.
      // Half the box diagonal, rounded up to 1/64 m: no corner starts below the floor.
      const double reach = std::ceil(64.0 * std::sqrt(b.half_extents.x * b.half_extents.x + b.half_extents.y * b.half_extents.y +
                                                      b.half_extents.z * b.half_extents.z)) / 64.0;
      const double drop = upto(24, 1.0 / 16);  // [0, 1.5] m above the lowest safe height
      const double floor_y = bowl ? 1.0 : s.ground.height;
      const double x = bowl ? centred(16, 1.0 / 16) : 4.0 * i;
      const double z = bowl ? centred(16, 1.0 / 16) : 0.0;
      b.position = {x, floor_y + reach + 0.5 * (bowl ? 1.0 : 0.0) + drop, z};
      // Yaw k * 22.5 deg (any value is fine: exactness is not needed for q,
      // the engines normalise it on load), then a small tilt about x and z.
      const int yaw_k = *rc::gen::inRange(0, 16);
      const double half_yaw = yaw_k * 3.14159265358979323846 / 32.0;
      const double tx = centred(6, 1.0 / 64), tz = centred(6, 1.0 / 64);  // ~ half-angles up to 0.094 rad
      const double cy = std::cos(half_yaw), sy = std::sin(half_yaw);
      // q = yaw (cy, 0, sy, 0) * tilt (1, tx, 0, tz), unnormalised.
      b.orientation = {cy, cy * tx + sy * tz, sy, cy * tz - sy * tx};
      b.velocity = {centred(16, 1.0 / 8), centred(8, 1.0 / 8), centred(16, 1.0 / 8)};  // up to 2, 1, 2 m/s
      b.angular_velocity = {centred(8, 1.0 / 16), centred(8, 1.0 / 16), centred(8, 1.0 / 16)};  // up to 0.5 rad/s
      s.bodies.push_back(b);
    }
    return s;
  });
}

}  // namespace lockstep_test
