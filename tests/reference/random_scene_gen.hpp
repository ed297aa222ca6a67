// RapidCheck generator of perturbed scenes for the snapshot and input
// properties (snapshot_test.cpp, inputs_test.cpp): 1-6 boxes of random sizes
// (0.25-0.75 m half extents), masses (0.5-4 kg), materials, tilts, offsets
// and velocities stacked loosely on the ground, a tilted static slab or the
// SDF bowl; either pair model; now and then random effects off. Values are
// multiples of powers of two (exact in Q16.16).
#pragma once
#include <rapidcheck.h>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::test {

inline double grid(int lo, int hi, double step) { return *rc::gen::inRange(lo, hi + 1) * step; }

inline rc::Gen<Scene> random_scene() {
  return rc::gen::exec([] {
    Scene s;
    s.name = "snapshot_case";
    s.pair_contacts = *rc::gen::inRange(0, 4) == 0 ? PairModel::kAabb : PairModel::kOrientedBox;
    const bool bowl = *rc::gen::inRange(0, 5) == 0;
    if (bowl) s.sdfs = builtin_scene("bowl")->sdfs;  // sphere of radius 6 about (0, 7, 0), floor at y = 1
    s.effects.sdf = bowl;
    if (*rc::gen::inRange(0, 5) == 0) {
      s.effects.settling = *rc::gen::arbitrary<bool>();
      s.effects.friction = *rc::gen::arbitrary<bool>();
      s.effects.restitution = *rc::gen::arbitrary<bool>();
      s.effects.sleep = *rc::gen::arbitrary<bool>();
    }
    s.ground.material = {grid(0, 8, 1.0 / 16), grid(2, 16, 1.0 / 16)};
    const int n = *rc::gen::inRange(1, 7);
    double y = bowl ? 1.0 : 0.0;
    if (!bowl && *rc::gen::inRange(0, 4) == 0) {  // a static slab under the pile
      BodyDesc slab;
      slab.is_static = true;
      slab.half_extents = {2.0, 0.25, 2.0};
      slab.position = {grid(-4, 4, 1.0 / 8), 0.25, grid(-4, 4, 1.0 / 8)};
      slab.orientation = {1.0, grid(-2, 2, 1.0 / 64), 0.0, 0.0};
      s.bodies.push_back(slab);
      y = 0.5;
    }
    for (int i = 0; i < n; ++i) {
      BodyDesc b;
      b.half_extents = {grid(16, 48, 1.0 / 64), grid(16, 48, 1.0 / 64), grid(16, 48, 1.0 / 64)};
      b.mass = grid(2, 16, 0.25);
      b.material = {grid(0, 8, 1.0 / 16), grid(2, 16, 1.0 / 16)};
      b.position = {grid(-4, 4, 1.0 / 8), y + b.half_extents.y + grid(0, 8, 1.0 / 16), grid(-4, 4, 1.0 / 8)};
      y = b.position.y + b.half_extents.y;
      b.orientation = {1.0, grid(-4, 4, 1.0 / 64), grid(-8, 8, 1.0 / 16), grid(-4, 4, 1.0 / 64)};
      b.velocity = {grid(-8, 8, 1.0 / 8), grid(-8, 4, 1.0 / 8), grid(-8, 8, 1.0 / 8)};
      b.angular_velocity = {grid(-4, 4, 1.0 / 8), grid(-4, 4, 1.0 / 8), grid(-4, 4, 1.0 / 8)};
      s.bodies.push_back(b);
    }
    return s;
  });
}

}  // namespace lockstep::test
