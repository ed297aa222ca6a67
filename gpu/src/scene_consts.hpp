// The scene-wide values the GPU engine's kernels need (SceneConsts).
#pragma once
#include "fault_notes.hpp"
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "lockstep/physics/box_box.hpp"

namespace lockstep::gpu {

// Scene-wide values the kernels need.
template <class T>
struct SceneConsts {
  using F4 = T4<T>;
  Params<T> P{};
  T half_tol{};  // contact_tolerance / 2 (eq 97)
  bool gravity = false, damping = false, friction = false, restitution = false, sleep = false;
  bool ground_on = false;
  T ground_y{}, ground_e{}, ground_mu{};
  int n_sdf = 0;
  const SdfGrid<T>* sdf = nullptr;
  const F4* sdf_material = nullptr;  // x: e, y: mu
  const int* large = nullptr;        // large static bodies, ascending
  int n_large = 0;
  T relaxation = Num<T>::from_int(1);
  bool oriented = false;  // the oriented-box pair model (docs/SPEC.md 2.4, eqs 100-110); false: the source's AABB model
  FaultSink faults;  // Q16 faults (fault_notes.hpp); unused for float
  const T* grow = nullptr;  // oriented-box model: per body, its growth this frame (eqs 97, 107); null: AABB model
  // eqs 97, 107: body i's tolerance for ground corners.
  LS_HD T immovable_tol(int i) const {
    return grow != nullptr ? immovable_tolerance(ro(grow + i), half_tol, P.contact_tolerance) : P.contact_tolerance;
  }
  // Contacts with immovable things per active body: 8 ground corners (when
  // ground_on), then 9 samples per SDF volume.
  LS_HD int ground_slots() const { return ground_on ? 8 : 0; }
  LS_HD int imm_stride() const { return ground_slots() + 9 * n_sdf; }
};

}  // namespace lockstep::gpu
