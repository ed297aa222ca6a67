// The GPU engine's per-element functions. The physics of one body, contact or
// manifold lives once, in reference/include/lockstep/physics/ (solver.hpp,
// narrow.hpp, body_step.hpp): World<T>'s loops (reference/src/) and the GPU
// engine's kernels and host build (gpu/src/) call the same host/device
// functions, so the engines differ in number type and scheduling, not in
// formulas. This header adds what only the GPU's scheduling needs.
#pragma once
#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/body_step.hpp"
#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/physics/narrow.hpp"
#include "lockstep/physics/params.hpp"
#include "lockstep/physics/sdf.hpp"
#include "lockstep/physics/settle.hpp"
#include "lockstep/physics/sleep.hpp"
#include "lockstep/physics/solver.hpp"

namespace lockstep::gpu {

// The shared per-element functions under their gpu:: names.
using lockstep::ContactState;
using lockstep::dynamic_view;
using lockstep::gravity_pressing;
using lockstep::ground_corner_depth;
using lockstep::identity3;
using lockstep::immovable_view;
using lockstep::integrate_pose;
using lockstep::integrate_velocity;
using lockstep::pair_contact;
using lockstep::PairContact;
using lockstep::prepare_contact;
using lockstep::sdf_sample_contact;
using lockstep::SdfContact;
using lockstep::settle_angular_velocity;
using lockstep::settle_linear_velocity;
using lockstep::solve_contact;
using lockstep::solve_manifold;
using lockstep::SolveCounts;
using lockstep::support_gap;
using lockstep::support_weight;
using lockstep::update_sleep;
using lockstep::wake_test;
using lockstep::warm_start_contact;

// Grid cells of the GPU broadphase: a 32-bit spatial hash of the integer cell
// coordinates (wrapping unsigned arithmetic), masked to the table size by the
// caller.
LS_HD inline unsigned cell_hash(int x, int y, int z) {
  return (static_cast<unsigned>(x) * 73856093u) ^ (static_cast<unsigned>(y) * 19349663u) ^
         (static_cast<unsigned>(z) * 83492791u);
}

}  // namespace lockstep::gpu
