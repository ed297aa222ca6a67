// A run-time input (lockstep/input.hpp) applied to a World<T>: what
// `lockstep run --inputs`, `lockstep replay` and the cross-build replay tool
// (tests/compare/cross) do before the step that computes the input's frame.
#pragma once
#include "lockstep/input.hpp"
#include "lockstep/world.hpp"

namespace lockstep::compare {

// World<T>::apply (docs/SPEC.md "Run-time inputs"); throws
// std::invalid_argument for an input the world refuses (a stale id, ...).
template <class T>
void apply_to_world(World<T>& w, const Input& in) {
  (void)w.apply(in);
}

}  // namespace lockstep::compare
