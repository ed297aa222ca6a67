// The GPU engine's state built from a scene on the host, in the number type T
// (float or Q16), with the same formulas as World<T>'s constructor (eqs 10, 14-18, 31); both
// backends start from it (the device backend uploads it).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lockstep/gpu/soa.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/physics/sdf.hpp"
#include "lockstep/scene.hpp"

namespace lockstep::gpu {

template <class T>
struct InitialState {
  using F4 = T4<T>;
  int n = 0;
  Params<T> P{};
  Effects fx;
  bool oriented = true;              // the oriented-box pair model (docs/SPEC.md 2.4); false: the source's AABB model
  bool ground_on = false;            // effect ground and a ground plane present
  T ground_y{}, ground_e{}, ground_mu{};
  std::vector<F4> pos, rot, aabb, half, inert, vel, ang;
  std::vector<std::uint8_t> flags;
  std::vector<int> sleep_counter, sleep_frame;
  // SDF volumes (only when effect sdf is on): grids whose `values` are offsets
  // into sdf_values until the backend re-points them at its own copy.
  std::vector<SdfGrid<T>> sdf_grids;
  std::vector<std::size_t> sdf_offsets;
  std::vector<T> sdf_values;
  std::vector<F4> sdf_material;      // x: restitution, y: friction
  // Static bodies too large for the frozen grid (bounding radius above twice
  // the largest dynamic body's): every awake body tests them directly.
  std::vector<int> large;
  int n_static = 0;        // static bodies
  int n_static_small = 0;  // static bodies in the frozen grid
  std::vector<int> awake;  // awake bodies at frame 0, ascending
};

// Instantiated for float and Q16 (initial_state.cpp). Throws RunError
// (frame 0) for a Q16 fault in a body's initial state, as World<Q16> does.
template <class T>
InitialState<T> make_initial_state(const Scene& scene);

}  // namespace lockstep::gpu
