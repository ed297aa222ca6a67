// RapidCheck generator of run-time inputs (lockstep/input.hpp) for the input
// properties (tests/reference/inputs_test.cpp, tests/gpu/gpu_inputs_test.cpp):
// creations (boxes of random sizes, masses, tilts; now and then static),
// removals, impulses at off-centre points, forces and torques, poses,
// velocities and wakes at random frames. Values are multiples of powers of
// two (exact in Q16.16).
#pragma once
#include <rapidcheck.h>

#include <algorithm>
#include <vector>

#include "lockstep/input.hpp"
#include "lockstep/world.hpp"
#include "random_scene_gen.hpp"

namespace lockstep::test {

// An input drawn before the run; which body it names is decided when it is
// applied (pick modulo the bodies then), so that it always names a live one.
struct Drawn {
  int frame = 1;
  InputKind kind = InputKind::wake;
  int pick = 0;
  BodyDesc body;   // create
  Vec3d a, b;      // impulse: J and the point's offset from the centre; force: F, torque; velocity: v, omega
  Quatd q;         // set_pose
};

inline rc::Gen<std::vector<Drawn>> drawn_inputs(int frames) {
  return rc::gen::exec([frames] {
    std::vector<Drawn> out(static_cast<std::size_t>(*rc::gen::inRange(0, 13)));
    for (Drawn& x : out) {
      x.frame = *rc::gen::inRange(1, frames + 1);
      x.kind = static_cast<InputKind>(*rc::gen::inRange(0, 7));
      x.pick = *rc::gen::inRange(0, 64);
      BodyDesc& b = x.body;
      b.half_extents = {grid(8, 48, 1.0 / 64), grid(8, 48, 1.0 / 64), grid(8, 48, 1.0 / 64)};  // mass/size ratios 1:6 in size
      b.mass = grid(1, 32, 0.25);                                                            // 0.25-8 kg
      b.material = {grid(0, 8, 1.0 / 16), grid(2, 16, 1.0 / 16)};
      b.position = {grid(-32, 32, 1.0 / 8), grid(8, 48, 1.0 / 8), grid(-32, 32, 1.0 / 8)};
      b.orientation = {1.0, grid(-8, 8, 1.0 / 32), grid(-16, 16, 1.0 / 16), grid(-8, 8, 1.0 / 32)};
      b.velocity = {grid(-8, 8, 1.0 / 4), grid(-8, 8, 1.0 / 4), grid(-8, 8, 1.0 / 4)};
      b.is_static = *rc::gen::inRange(0, 8) == 0;
      x.a = {grid(-64, 64, 1.0 / 8), grid(-64, 64, 1.0 / 8), grid(-64, 64, 1.0 / 8)};
      x.b = {grid(-8, 8, 1.0 / 16), grid(-8, 8, 1.0 / 16), grid(-8, 8, 1.0 / 16)};
      x.q = {1.0, grid(-8, 8, 1.0 / 16), grid(-16, 16, 1.0 / 16), grid(-8, 8, 1.0 / 16)};
      if (x.kind == InputKind::force) x.a = {x.a.x * 8, x.a.y * 8, x.a.z * 8};  // up to 512 N
      if (x.kind == InputKind::set_pose) x.a = b.position;
    }
    std::stable_sort(out.begin(), out.end(), [](const Drawn& l, const Drawn& r) { return l.frame < r.frame; });
    return out;
  });
}

// The concrete input a drawn one becomes in world w (names a live body).
template <class T>
Input concrete(const Drawn& x, const World<T>& w) {
  Input in;
  in.frame = x.frame;
  in.kind = x.kind;
  in.body = x.body;
  in.a = x.a;
  in.b = x.b;
  in.q = x.q;
  if (x.kind == InputKind::create) return in;
  const int n = static_cast<int>(w.bodies().size());
  in.id = w.id_of(x.pick % n);
  if (x.kind == InputKind::impulse) {
    const Body<T>& b = w.body(x.pick % n);
    in.b = {Num<T>::to_double(b.p.x) + x.b.x, Num<T>::to_double(b.p.y) + x.b.y, Num<T>::to_double(b.p.z) + x.b.z};
  }
  return in;
}

}  // namespace lockstep::test
