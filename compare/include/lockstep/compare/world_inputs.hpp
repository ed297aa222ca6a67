// A run-time input (lockstep/input.hpp) applied to a World<T>: what
// `lockstep run --inputs`, `lockstep replay` and the cross-build replay tool
// (tests/compare/cross) do before the step that computes the input's frame.
#pragma once
#include <stdexcept>
#include <string>

#include "lockstep/input.hpp"
#include "lockstep/world.hpp"

namespace lockstep::compare {

// Throws std::invalid_argument for an input this build's World<T> cannot take.
template <class T>
void apply_to_world(World<T>& w, const Input& in) {
  const auto i = static_cast<int>(in.id.slot);
  if (in.id.generation != 0 || i < 0 || i >= static_cast<int>(w.bodies().size()))
    throw std::invalid_argument("input of frame " + std::to_string(in.frame) + ": body " + std::to_string(in.id.slot) +
                                " does not exist");
  auto v = [](const Vec3d& x) { return Vec3<T>{Num<T>::from_double(x.x), Num<T>::from_double(x.y), Num<T>::from_double(x.z)}; };
  switch (in.kind) {
    case InputKind::set_velocity: w.set_velocity(i, v(in.a), v(in.b)); return;
    case InputKind::wake: w.wake(i); return;
    default:
      throw std::invalid_argument(std::string("input kind ") + input_kind_name(in.kind) +
                                  ": this build's engines take set_velocity and wake (the other inputs come with "
                                  "World<T>::apply, issue 32)");
  }
}

}  // namespace lockstep::compare
