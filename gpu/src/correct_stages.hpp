// Stages 6 (the last settling sweep), 7 and 8 of docs/SPEC.md 7.2 on the GPU:
// the final velocity, the world's position corrections (eqs 63, 89) and the
// integration (CorrectIntegrateK).
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "contact_records.hpp"
#include "scene_consts.hpp"
#include "settle_stages.hpp"

namespace lockstep::gpu {

// Stages 6 (the last settling sweep), 7-8: the final velocity (the
// solver's, settled when settling is on: eqs 75, 77, 64-74), position
// correction (eqs 63, 89) from the contacts of the frame (measured at the
// start-of-frame positions), then integration (eqs 2, 7-10). Poses go to
// per-slot buffers, committed by the next kernel, since other threads read
// the start-of-frame positions.
template <class T>
struct CorrectIntegrateK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  NeighbourLists lists;
  const F4* sdf_c0;
  const F4* sdf_c1;
  const ContactRecord<T>* imm;   // the contacts' solver state: b.y is e_eff (eq 76); a bouncing contact is not corrected
  const ContactRecord<T>* pair;
  const F4* vpost;  // the solver's velocities
  const F4* wpost;
  bool settle;       // settling on: the last sweep
  SettleSweep<T> sweep;
  F4* p_out;
  F4* q_out;
  Counter* ctr;
  F4* p_world = nullptr;  // oriented-box model: the position after the world's corrections, per slot (eq 110 goes on)
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i);
    const Vec3<T> p0 = xyz(pi4), a = xyz(ro(b.aabb + i));
    const T inv_self = inv_mass_of(pi4);
    Vec3<T> p = p0, dummy{};
    const Quat<T> q0 = quat(ro(b.rot + i));
    Vec3<T> vf = xyz(ro(vpost + i)), wf = xyz(ro(wpost + i));
    if (settle) {
      bool final = true;
      const T speed = sweep.linear(b, i, sc.P, vf, final);  // eqs 75, 77
      if (speed >= T{}) {
        // eqs 64-74: the AABB model damps by the regimes on every support; the
        // oriented-box model on an immovable one only (a support body that is
        // not awake, the ground, an SDF volume).
        const int s = ro(sweep.support_idx + i);
        const bool movable = sc.oriented && s >= 0 && is_awake(ro(b.flags + s));
        wf = settle_spin(wf, movable, [&] { return xyz(ro(wpost + s)); }, rotation_matrix(q0),
                         xyz(ro(sweep.support_n + i)), speed, sweep.leans(i), sc.P);  // eqs 64-74, 115
        add_counter(&ctr[kCSettlingBodies], 1u);
      }
    }
    note_faults<T>(sc.faults, i, kFqSettling);
    b.vel[i] = f4(vf, T{});
    b.ang[i] = f4(wf, T{});
    unsigned corrections = 0;
    const T slop = sc.P.slop, percent = sc.P.baumgarte, tol = sc.immovable_tol(i);  // eqs 97, 107
    // eq 89's order: the body pairs first, then the ground and SDF contacts
    // with their penetration less what the pairs moved this body along n.
    const int beg = lists.begin(k), end = sc.oriented ? beg : lists.end(k);  // oriented: eq 110 (PairCorrectK)
    for (int t = beg; t < end; ++t) {
      const int j = ro(lists.nbr + t);
      const F4 pj4 = ro(b.pos + j);
      const bool j_awake = is_awake(ro(b.flags + j));
      const T inv_j = j_awake ? inv_mass_of(pj4) : T{};
      const bool lower = i < j;
      const PairContact<T> c = canonical_pair(sc, i, p0, a, j, xyz(pj4), xyz(ro(b.aabb + j)));
      const T inv_a = lower ? inv_self : inv_j, inv_b = lower ? inv_j : inv_self;
      if (bounces(ro(&pair[t].b)) || (inv_a == T{} && inv_b == T{})) continue;
      if (lower) baumgarte_correction(p, dummy, c.n, c.penetration, inv_a, inv_b, slop, percent);
      else baumgarte_correction(dummy, p, c.n, c.penetration, inv_a, inv_b, slop, percent);
      if (lower || !j_awake) ++corrections;
    }
    if (sc.ground_on) {  // the deepest corner (first on ties, a resting one before a bouncing one) carries the correction
      const Mat3<T> R = rotation_matrix(q0);
      const Vec3<T> h = xyz(ro(b.half + i));
      auto corner_depth = [&](int c, T& depth) {
        Vec3<T> corner;
        depth = ground_corner_depth(p0, R, h, c, sc.ground_y, corner);
        return depth > -tol;
      };
      auto corner_bounces = [&](int c) { return bounces(ro(&imm[k * sc.imm_stride() + c].b)); };
      T deepest_depth = T{};
      const int deepest = ground_correction_point(8, corner_depth, corner_bounces, deepest_depth);  // eq 89's tie rule
      if (deepest >= 0 && !corner_bounces(deepest) && inv_self != T{}) {
        const Vec3<T> up{T{}, Num<T>::from_int(1), T{}};
        baumgarte_correction(p, dummy, up, deepest_depth - dot(p - p0, up), inv_self, T{}, slop, percent);
        ++corrections;
      }
    }
    for (int v = 0; v < sc.n_sdf; ++v) {  // per volume, the deepest sample
      int deepest = -1, deepest_s = 0;
      for (int s = 0; s < 9; ++s) {
        const int g = (k * sc.n_sdf + v) * 9 + s;
        if (sdf_c1[g].w == T{}) continue;
        if (deepest < 0 || sdf_c0[g].w > sdf_c0[deepest].w) { deepest = g; deepest_s = s; }
      }
      if (deepest < 0 || bounces(imm[k * sc.imm_stride() + sc.ground_slots() + 9 * v + deepest_s].b) ||
          inv_self == T{})
        continue;
      const F4 c0 = sdf_c0[deepest];
      baumgarte_correction(p, dummy, xyz(c0), c0.w - dot(p - p0, xyz(c0)), inv_self, T{}, slop, percent);
      ++corrections;
    }
    note_faults<T>(sc.faults, i, kFqCorrection);
    if (p_world != nullptr) {  // the pairs' corrections (eq 110) and the integration follow
      p_world[k] = f4(p, inv_self);
      add_counter(&ctr[kCCorrections], corrections);
      return;
    }
    Quat<T> q = q0;
    integrate_pose(p, q, vf, wf, sc.P);  // eqs 2, 7-10
    note_faults<T>(sc.faults, i, kFqPosition);
    p_out[k] = f4(p, inv_self);
    q_out[k] = f4(q);
    add_counter(&ctr[kCCorrections], corrections);
  }
};

}  // namespace lockstep::gpu
