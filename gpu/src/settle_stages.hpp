// Stage 6 of docs/SPEC.md 7.2 on the GPU: the settling sweeps (eqs 75, 77).
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "scene_consts.hpp"
#include "solver_data.hpp"

namespace lockstep::gpu {

// Stage 6: settling sweeps. World<T> settles supported bodies lowest first
// (height, then index), so eq 75 sees a lower support's settled velocity and
// a higher one's unsettled velocity. Sweep k reads the supports' values of
// sweep k-1 (sin; sweep 0 reads the solver's result) and writes its own;
// after as many sweeps as the longest chain of supports, the result is
// World<T>'s. The last sweep, which also settles the angular velocity (eqs
// 64-74), runs in CorrectIntegrateK.
template <class T>
struct SettleSweep {
  using F4 = T4<T>;
  const int* support_idx;
  const F4* support_n;
  const F4* vpost;  // solver result
  const F4* sin;    // the previous sweep's (sweep 0: vpost)
  bool relative = false;  // the oriented-box model: eq 77 relative to the support's velocity
  const int* over = nullptr;  // the oriented-box model: per body, over its support (eq 112); one that is not does not settle
  const int* leaning = nullptr;  // the oriented-box model: per body, it leans (eq 115): not righted
  const T* limit = nullptr;  // per body: eq 77 damps a relative speed up to this (eq 116)
  LS_HD bool settles(int i) const { return over == nullptr || ro(over + i) != 0; }
  LS_HD bool leans(int i) const { return leaning != nullptr && ro(leaning + i) != 0; }
  // Eqs 75, 77 on v (the solver's velocity of body i); returns |v| after eq 75
  // (what righting uses), or a negative value for a body with no support
  // (v unchanged). `final`: the result is World<T>'s (it read no support's
  // settled velocity, or a final one: a sweep's output carries w = 1 when
  // final, and the solver's velocities w = 0).
  LS_HD T linear(const BodyArrays<T>& b, int i, const Params<T>& P, Vec3<T>& v, bool& final) const {
    final = true;
    const int s = ro(support_idx + i);
    if (s == kNoSupport || !settles(i)) return -Num<T>::from_int(1);
    Vec3<T> v_s{};
    if (s >= 0 && is_awake(ro(b.flags + s))) {
      if (settles_before(ro(b.pos + s).y, s, ro(b.pos + i).y, i) && ro(support_idx + s) != kNoSupport && settles(s)) {
        const F4 settled = ro(sin + s);
        v_s = xyz(settled);
        final = settled.w != T{};
      } else {
        v_s = xyz(ro(vpost + s));
      }
    }
    const F4 sn = ro(support_n + i);  // the support normal, w: the support gap
    return settle_linear_velocity(v, v_s, xyz(sn), sn.w, P, relative,
                                  limit == nullptr ? P.settle_speed : ro(limit + i));  // eqs 75, 77, 116
  }
};

// One settling sweep but the last: the linear velocity of every supported
// body, w = 1 where final. With `unsettled`, counts the bodies whose result
// is not final yet (an integer atomic, order-free).
template <class T>
struct SettleK {
  using F4 = T4<T>;
  const int* list;
  BodyArrays<T> b;
  SceneConsts<T> sc;
  SettleSweep<T> sweep;
  F4* sout;
  int* unsettled;
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    clear_faults<T>();
    Vec3<T> v = xyz(ro(sweep.vpost + i));
    bool final = true;
    if (sweep.linear(b, i, sc.P, v, final) >= T{}) sout[i] = f4(v, final ? Num<T>::from_int(1) : T{});
    note_faults<T>(sc.faults, i, kFqSettling);
    if (unsettled != nullptr) add_to(unsettled, final ? 0 : 1);
  }
};

}  // namespace lockstep::gpu
