// Stage 1 of docs/SPEC.md 7.2 on the GPU: velocity integration (eqs 1, 3-6).
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "grid.hpp"
#include "scene_consts.hpp"
#include "contact_records.hpp"

namespace lockstep::gpu {

// Stage 1: velocity integration of the awake bodies; also gathers what the
// awake grid needs of each (Bounds).
template <class T>
struct IntegrateVelocityK {
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  Bounds<T>* bounds;  // per slot, or null
  T* grow = nullptr;  // oriented-box model: per body, its AABB growth this frame (eqs 97, 107); null: AABB model
  int integrate_end = 0x7fffffff;  // slots from here on (woken by eq 108 after stage 1) are not integrated
  LS_HD void operator()(int k) const {
    const int i = list[k];
    clear_faults<T>();
    if ((sc.gravity || sc.damping) && k < integrate_end) {
      Vec3<T> v = xyz(b.vel[i]), w = xyz(b.ang[i]);
      integrate_velocity(v, w, sc.gravity, sc.damping, sc.P);
      b.vel[i] = f4(v, T{});
      b.ang[i] = f4(w, T{});
      note_faults<T>(sc.faults, i, kFqVelocity);
    }
    if (grow != nullptr) {
      const T g = body_growth(sc, xyz(b.vel[i]), xyz(b.ang[i]), xyz(b.half[i]));
      grow[i] = g;
      note_faults<T>(sc.faults, i, kFqPairContact);  // eq 107's reach: World's broadphase, checked with the pairs
      if (bounds != nullptr) {  // the grid's reach covers the grown boxes
        Bounds<T> bd = bounds_of(b.pos[i], b.aabb[i]);
        bd.gmax = g;
        bounds[k] = bd;
      }
      return;
    }
    if (bounds != nullptr) bounds[k] = bounds_of(b.pos[i], b.aabb[i]);
  }
};

}  // namespace lockstep::gpu
