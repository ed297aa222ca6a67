// Stage 3 of docs/SPEC.md 7.2 on the GPU, the oriented-box model: each body
// pair's contact manifold (eqs 100-107), formed once a frame for both of its
// list entries (PairManifoldK), before ContactsK reads it.
#pragma once
#include "contact_records.hpp"
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "scene_consts.hpp"
#include "solver_data.hpp"

namespace lockstep::gpu {

// The geometry of a pair's record (eqs 100-107, 110): the normal, the points
// with their penetrations and features, the deepest point, the mean depth.
// The solver states are ContactsK's.
template <class T>
LS_HD_INLINE void write_manifold(PairManifold<T>& rec, const BoxManifold<T>& mf) {
  rec.count = mf.count;
  rec.n = f4(mf.n, T{});
  for (int u = 0; u < kBoxManifoldPoints; ++u) {
    rec.pt[u] = u < mf.count ? f4(mf.point[u], mf.penetration[u]) : T4<T>{};
    rec.feature[u] = u < mf.count ? mf.feature[u] : 0;
  }
  rec.deepest = deepest_point(mf.penetration, mf.count);
  rec.depth = mean_depth(mf.penetration, mf.count);  // eq 110
}

// Each active body (thread -> slot through `order`, as ContactsK) forms the
// manifolds of its list's pairs (World<T>'s narrowphase, body a the lower
// index) that it owns: a pair with an awake body j is the lower index's, who
// writes both entries (its own and j's, found in j's list: the same values
// each side formed before, once); a pair with a sleeping or static j is i's
// alone. A Q16 fault is noted on the lower index, as World<T> notes it.
template <class T>
struct PairManifoldK {
  SolverData<T> d;
  const int* slot_of;  // per body: its slot this frame (awake bodies; ContactIndex)
  const T* grow;       // per body: its AABB growth (eqs 97, 107)
  const int* order = nullptr;  // thread -> slot (WorkOrder), or null: thread k is slot k
  LS_HD void operator()(int thread) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    const int k = order != nullptr ? ro(order + thread) : thread;
    const int i = ro(d.list + k);
    clear_faults<T>();
    const Vec3<T> p = xyz(ro(b.pos + i)), h = xyz(ro(b.half + i));
    const Mat3<T> R = rotation_matrix(quat(ro(b.rot + i)));
    const T gi = ro(grow + i);
    const int beg = d.lists.begin(k), end = d.lists.end(k);
    for (int t = beg; t < end; ++t) {
      const int j = ro(d.lists.nbr + t);
      const int m = is_awake(ro(b.flags + j)) ? d.lists.find(ro(slot_of + j), i) : -1;  // j's entry of the pair
      if (m >= 0 && j < i) continue;  // j's thread writes both
      const BoxManifold<T> mf = pair_manifold(sc, i < j, p, R, h, gi, xyz(ro(b.pos + j)),
                                              rotation_matrix(quat(ro(b.rot + j))), xyz(ro(b.half + j)), ro(grow + j));
      note_faults<T>(sc.faults, i < j ? i : j, kFqPairContact);
      write_manifold(d.man[t], mf);
      if (m >= 0) write_manifold(d.man[m], mf);
    }
  }
};

}  // namespace lockstep::gpu
