// Stage 5 of docs/SPEC.md 7.2 on the GPU: the solver's iterations, per body
// (SolveK, Jacobi or the coloured solver's immovable contacts) and per
// edge of a colour (SolveEdgeK).
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "colouring.hpp"
#include "contact_records.hpp"
#include "scene_consts.hpp"
#include "solver_data.hpp"

namespace lockstep::gpu {

// A ground corner of body (p, R, h) as a manifold point (eq 99) of SolveK's
// ground visit, and an SDF volume's sample, as the visits and ImmRowsK read them.
template <class T>
LS_HD_INLINE bool ground_point(const Vec3<T>& p, const Mat3<T>& R, const Vec3<T>& h, int c, const SceneConsts<T>& sc,
                               const T& tol, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
  r2 = Vec3<T>{};
  Vec3<T> corner;
  penetration = ground_corner_depth(p, R, h, c, sc.ground_y, corner);
  r1 = corner - p;
  n = Vec3<T>{T{}, Num<T>::from_int(1), T{}};
  return penetration > -tol;
}
template <class T>
LS_HD_INLINE bool sdf_point(const SolverData<T>& d, int k, int v, int s, const Vec3<T>& p, Vec3<T>& r1, Vec3<T>& r2,
                            Vec3<T>& n, T& penetration) {
  r2 = Vec3<T>{};
  const int g = (k * d.sc.n_sdf + v) * 9 + s;
  const T4<T> c1 = ro(d.sdf_c1 + g), c0 = ro(d.sdf_c0 + g);
  r1 = xyz(c1) - p;
  n = xyz(c0);
  penetration = c0.w;
  return c1.w != T{};
}

// gpu-fixed's rows formed once per frame (docs/GPU.md "gpu-fixed"): a Q16
// visit reads each point's rows (eqs 114, 128-129) from these arrays instead
// of forming them in every pass; float visits form the half they read
// (solver.hpp, solve_manifold_rows), as before. kRowsOnce<T>: whether T's
// visits read them.
template <class T>
inline constexpr bool kRowsOnce = Num<T>::kExact;

// The rows a manifold visit (solve_manifold_rows) forms, into rows[0..N-1]:
// contact_rows of each point that is a contact, in point order, stopping
// after the first if its k_n is 0 (the visit returns there, both sides
// immovable); the same values, and the same Q16 status flags, as the visit's
// own forming of them.
template <int N, class T, class Point, class Load>
LS_HD_INLINE void form_manifold_rows(const BodyView<T>& A, const BodyView<T>& B, const Point& point_at,
                                     const Load& load_at, ContactRows<T>* rows) {
  bool first = true;
#if defined(__CUDA_ARCH__)
#pragma unroll 1
#endif
  for (int k = 0; k < N; ++k) {
    Vec3<T> r1, r2, n;
    T penetration;
    if (!point_at(k, r1, r2, n, penetration)) continue;
    const T k_n = load_at(k).k_n;
    rows[k] = contact_rows(A, r1, B, r2, n, k_n);
    if (first && !(k_n > T{})) return;  // the first contact's k_n is 0: the visit returns
    first = false;
  }
}

// A manifold visit of solve_manifold (k_scale as its), through rows formed
// once (kRowsOnce<T>: `rows`, the visit's N points') or forming them.
// kKeep: the visit keeps its points and states (solve_manifold_rows'
// kKeepOnDevice), for points formed by `point` rather than read; kImmovableB:
// B is immovable_view() (solve_manifold_rows' flag: its exact zeros left out).
template <int N, bool kKeep = false, bool kImmovableB = false, class T, class Point, class Load, class Store>
LS_HD_INLINE void visit_manifold(BodyView<T>& A, BodyView<T>& B, const Point& point, const ContactRows<T>* rows,
                                 const Load& load, const Store& store, bool friction, bool gravity, const T& k_scale,
                                 const Params<T>& P, SolveCounts& counts) {
  if constexpr (kRowsOnce<T>) {
    auto row = [rows](int k) -> const ContactRows<T>& { return rows[k]; };
    solve_manifold_rows<N, kKeep, kImmovableB>(A, B, point, row, load, store, friction, gravity, k_scale, P, counts);
  } else {
    (void)rows;
    solve_manifold<N>(A, B, point, load, store, friction, gravity, k_scale, P, counts);
  }
}

// Stage 5, one iteration for every active body (docs/GPU.md "Contact
// resolution"). Contacts with immovable things (the ground and SDF manifolds
// of eq 99, sleeping and static bodies) are visited one after the other on
// the body's own velocity, as World<T> visits them. Contacts with other
// active bodies are Jacobi: both bodies visit the contact, each against the
// velocities at the start of the iteration (vin/win), so both compute the
// same impulse and keep equal copies of its accumulated state; each adds its
// own velocity change, and the effective masses are scaled by the larger
// of the two bodies' contact counts in the contact's direction (mass
// splitting) over the relaxation. With `edge_colour` (the coloured solver,
// colouring.hpp) the body visits only its immovable contacts, in place (vin
// = vout): the contacts with active bodies are SolveEdgeK's.
template <class T>
struct SolveK {
  using F4 = T4<T>;
  SolverData<T> d;
  const int* order;  // thread -> slot (WorkOrder), or null: thread k is slot k
  const int* edge_colour;  // the coloured solver's colours per entry, or null: Jacobi
  const int* has_immovable;  // per slot (ContactsK): the coloured solver skips bodies without immovable contacts
  const F4* vin;
  const F4* win;
  F4* vout;
  F4* wout;
  Counter* ctr;
  bool reverse = false;  // oriented-box model, odd passes: the body's visits in reverse (7.2 step 5)
  int pass = 0;          // the solver pass (eq 113)
  const ContactRows<T>* imm_rows = nullptr;  // kRowsOnce<T>: ImmRowsK's, imm_stride() per slot
  LS_HD void operator()(int thread) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    const int k = order != nullptr ? ro(order + thread) : thread;
    const bool coloured = edge_colour != nullptr;
    if (coloured && ro(has_immovable + k) == 0) return;  // nothing to visit; the velocity stays in place
    const int i = ro(d.list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i), h4 = ro(b.half + i);
    const Vec3<T> p = xyz(pi4), a = xyz(ro(b.aabb + i)), h = xyz(h4);
    const Mat3<T> R = rotation_matrix(quat(ro(b.rot + i)));
    const Vec3<T> I = xyz(ro(b.inert + i));
    const Vec3<T> v0 = xyz(coloured ? vin[i] : ro(vin + i)), w0 = xyz(coloured ? win[i] : ro(win + i));
    BodyView<T> self = dynamic_view(v0, w0, inv_mass_of(pi4), R, I);
    const T tol = sc.immovable_tol(i);  // eqs 97, 107
    const int stride = sc.imm_stride();
    SolveCounts counts;
    // Ground corners and each SDF volume's samples: manifolds (eq 99); the
    // points' state is read and written where it lives.
    BodyView<T> env = immovable_view<T>();
    auto loader = [&](int base) {
      return [&, base](int e) {
        const ContactRecord<T>& r = d.imm[k * stride + base + e];
        return load_state(r.a, r.b);
      };
    };
    auto storer = [&](int base) {
      return [&, base](int e, const ContactState<T>& c) {
        d.imm[k * stride + base + e].a = F4{c.j_n, c.j_t.x, c.j_t.y, c.j_t.z};
      };
    };
    // The ground manifold and SDF volume v's (eq 99), on the body's own velocity.
    const T one = Num<T>::from_int(1);
    auto rows_at = [&](int base) { return imm_rows != nullptr ? imm_rows + (static_cast<long>(k) * stride + base) : nullptr; };
    auto solve_ground = [&] {
      auto corner_point = [&](int c, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
        return ground_point(p, R, h, c, sc, tol, r1, r2, n, penetration);
      };
      visit_manifold<8, true, true>(self, env, corner_point, rows_at(0), loader(0), storer(0), sc.friction, sc.gravity, one, sc.P,
                        counts);
    };
    auto solve_volume = [&](int v) {
      const int base = sc.ground_slots() + 9 * v;
      auto sample = [&](int s, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
        return sdf_point(d, k, v, s, p, r1, r2, n, penetration);
      };
      visit_manifold<9, true, true>(self, env, sample, rows_at(base), loader(base), storer(base), sc.friction, sc.gravity, one,
                        sc.P, counts);
    };
    // A pair visit's result for the body (mv, mw: its velocity after it):
    // Jacobi adds the change to dv, dw, else it is the body's velocity; the
    // pair's counts go to the lower index (or to the only active side).
    Vec3<T> dv{}, dw{};
    auto take = [&](const Vec3<T>& mv, const Vec3<T>& mw, bool jacobi, bool lower, const SolveCounts& here) {
      if (jacobi) {
        dv += mv - v0;
        dw += mw - w0;
      } else {
        self.v = mv;
        self.w = mw;
      }
      if (lower || !jacobi) {
        counts.solver_contacts += here.solver_contacts;
        counts.normal_impulses += here.normal_impulses;
        counts.friction_steps += here.friction_steps;
      }
    };
    if (sc.oriented) {
      // The oriented-box model: the ground manifold, each SDF volume's, then
      // the pairs with immovable bodies (and, Jacobi, with active ones) as
      // manifolds (eq 99), in World<T>'s order; odd passes in reverse.
      // eq 113: each immovable manifold's record, 4 F4 (the environment side zero).
      auto imm_visit = [&](int m, auto&& solve) {
        F4* st = d.conv_imm != nullptr ? d.conv_imm + (static_cast<long>(k) * (sc.ground_slots() / 8 + sc.n_sdf) + m) * 4
                                       : nullptr;
        if (visit_is_converged(st, self, env, sc.P, pass)) return;
        const Vec3<T> v0s = self.v, w0s = self.w;
        const unsigned shortened0 = counts.shortened_steps;
        solve();
        note_faults<T>(sc.faults, i, kFqImpulse);
        record_visit(st, v0s, w0s, env.v, env.w, self, env, sc.P, counts.shortened_steps - shortened0);
      };
      auto ground = [&] { imm_visit(0, solve_ground); };
      auto volume = [&](int v) { imm_visit(sc.ground_slots() / 8 + v, [&] { solve_volume(v); }); };
      auto pair = [&](int t) {
        const int j = ro(d.lists.nbr + t);
        if (coloured && ro(edge_colour + t) != kNoEdge) return;  // SolveEdgeK's
        PairManifold<T>& rec = d.man[t];
        const int count = rec.count;
        if (count == 0) return;
        const Vec3<T> pj = xyz(ro(b.pos + j));
        const bool lower = i < j;
        const bool jacobi = !coloured && is_awake(ro(b.flags + j));
        BodyView<T> me = self;
        if (jacobi) { me.v = v0; me.w = w0; }
        const BodyView<T> other = coloured ? immovable_view<T>() : view_of(b, j, vin, win);
        const Vec3<T> n = xyz(rec.n);
        const T split =
            jacobi ? jacobi_split(ro(d.dir_count + i), ro(d.dir_count + j), lower ? n : -n, sc.relaxation) : Num<T>::from_int(1);
        BodyView<T> A = pick(lower, me, other), B = pick(lower, other, me);
        F4* conv = d.conv_of_pair(t);
        if (visit_is_converged(conv, A, B, sc.P, pass)) return;  // eq 113
        const Vec3<T> va0 = A.v, wa0 = A.w, vb0 = B.v, wb0 = B.w;
        const Vec3<T> pa = lower ? p : pj, pb = lower ? pj : p;
        auto point = [&](int c, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& nc, T& penetration) {
          if (c >= count) return false;
          const F4 pt = rec.pt[c];
          r1 = xyz(pt) - pa;
          r2 = xyz(pt) - pb;
          nc = n;
          penetration = pt.w;
          return true;
        };
        auto load = [&](int c) { return load_state(rec.st[c].a, rec.st[c].b); };
        auto store = [&](int c, const ContactState<T>& cs) { rec.st[c].a = F4{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z}; };
        SolveCounts here;
        solve_manifold<kBoxManifoldPoints>(A, B, point, load, store, sc.friction, sc.gravity, split, sc.P, here);
        note_faults<T>(sc.faults, lower ? i : j, kFqImpulseBody);  // World's body a: the lower index
        record_visit(conv, va0, wa0, vb0, wb0, A, B, sc.P, here.shortened_steps);
        take(pick(lower, A.v, B.v), pick(lower, A.w, B.w), jacobi, lower, here);
      };
      const int beg = d.lists.begin(k), end = d.lists.end(k);
      if (!reverse) {
        if (sc.ground_on) ground();
        for (int v = 0; v < sc.n_sdf; ++v) volume(v);
        for (int t = beg; t < end; ++t) pair(t);
      } else {
        for (int t = end - 1; t >= beg; --t) pair(t);
        for (int v = sc.n_sdf - 1; v >= 0; --v) volume(v);
        if (sc.ground_on) ground();
      }
      note_faults<T>(sc.faults, i, kFqImpulse);
      vout[i] = f4(coloured ? self.v : self.v + dv, T{});  // (no + 0: keeps a -0 component)
      wout[i] = f4(coloured ? self.w : self.w + dw, T{});
      add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
      add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
      add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
      return;
    }
    if (sc.ground_on) solve_ground();
    for (int v = 0; v < sc.n_sdf; ++v) solve_volume(v);
    note_faults<T>(sc.faults, i, kFqImpulse);
    const int beg = d.lists.begin(k), end = d.lists.end(k);
    for (int t = beg; t < end; ++t) {
      const int j = ro(d.lists.nbr + t);
      // The coloured solver's edges are SolveEdgeK's; an awake j that is no
      // edge (its list lacks i: cannot happen, the pair test is symmetric) is
      // met as immovable, so that no velocity is read that another thread writes.
      if (coloured && ro(edge_colour + t) != kNoEdge) continue;
      const F4 pj4 = ro(b.pos + j);
      const Vec3<T> pj = xyz(pj4);
      const bool lower = i < j;
      const PairContact<T> pc = canonical_pair(sc, i, p, a, j, pj, xyz(ro(b.aabb + j)));
      const Vec3<T> r1 = pc.point - (lower ? p : pj), r2 = pc.point - (lower ? pj : p);
      ContactState<T> c = load_state(d.pair[t].a, d.pair[t].b);
      // One call of solve_contact for every kind of pair (the threads of a
      // warp stay together): body 1 is the lower index; an immovable j is
      // solved on the body's own current velocity (self), an active j
      // (Jacobi) on both bodies' velocities at the start of the iteration.
      const bool jacobi = !coloured && is_awake(ro(b.flags + j));
      BodyView<T> me = self;
      if (jacobi) { me.v = v0; me.w = w0; }
      const BodyView<T> other = coloured ? immovable_view<T>() : view_of(b, j, vin, win);
      const T split =
          jacobi ? jacobi_split(ro(d.dir_count + i), ro(d.dir_count + j), lower ? pc.n : -pc.n, sc.relaxation) : Num<T>::from_int(1);
      BodyView<T> A = pick(lower, me, other), B = pick(lower, other, me);
      SolveCounts here;
      solve_contact(A, r1, B, r2, pc.n, pc.penetration, c, sc.friction, sc.gravity, split, sc.P, here);
      note_faults<T>(sc.faults, lower ? i : j, kFqImpulseBody);  // World's body a: the lower index
      take(pick(lower, A.v, B.v), pick(lower, A.w, B.w), jacobi, lower, here);
      d.pair[t].a = F4{c.j_n, c.j_t.x, c.j_t.y, c.j_t.z};
    }
    note_faults<T>(sc.faults, i, kFqImpulse);
    vout[i] = f4(self.v + dv, T{});
    wout[i] = f4(self.w + dw, T{});
    add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
    add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
    add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
  }
};

// One colour of one iteration, a thread per edge: the contact (body 1 = the
// lower index, its owner, as World<T>) solved on both bodies' current
// velocities, which it updates in place (no other edge of the colour touches
// either body); both copies of the contact state are rewritten.
template <class T>
struct SolveEdgeK {
  using F4 = T4<T>;
  SolverData<T> d;
  const int* edges;  // this colour's
  const int* mate;
  F4* vel;
  F4* ang;
  Counter* ctr;
  int pass = 0;  // the solver pass (eq 113)
  const ContactRows<T>* rows = nullptr;  // kRowsOnce<T>, oriented-box model: EdgeRowsK's, kBoxManifoldPoints per edge of this colour
  LS_HD void operator()(int e) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    const int t = ro(edges + e);
    const int i = ro(d.list + t / d.lists.stride), j = ro(d.lists.nbr + t);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i), pj4 = ro(b.pos + j);
    const Vec3<T> p = xyz(pi4), pj = xyz(pj4);
    if (sc.oriented) {  // the pair's manifold (eq 99), i < j
      PairManifold<T>& rec = d.man[t];
      PairManifold<T>& twin = d.man[ro(mate + t)];
      BodyView<T> A = dynamic_view(xyz(vel[i]), xyz(ang[i]), inv_mass_of(pi4), rotation_matrix(quat(ro(b.rot + i))),
                                       xyz(ro(b.inert + i)));
      BodyView<T> B = dynamic_view(xyz(vel[j]), xyz(ang[j]), inv_mass_of(pj4), rotation_matrix(quat(ro(b.rot + j))),
                                       xyz(ro(b.inert + j)));
      const int count = rec.count;
      const Vec3<T> n = xyz(rec.n);
      auto point = [&](int c, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& nc, T& penetration) {
        if (c >= count) return false;
        const F4 pt = rec.pt[c];
        r1 = xyz(pt) - p;
        r2 = xyz(pt) - pj;
        nc = n;
        penetration = pt.w;
        return true;
      };
      auto load = [&](int c) { return load_state(rec.st[c].a, rec.st[c].b); };
      auto store = [&](int c, const ContactState<T>& cs) {
        const F4 state{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z};
        rec.st[c].a = state;
        twin.st[c].a = state;
      };
      F4* conv = d.conv_of_pair(t);
      if (visit_is_converged(conv, A, B, sc.P, pass)) return;  // eq 113
      const ContactRows<T>* edge_rows = rows != nullptr ? rows + static_cast<long>(e) * kBoxManifoldPoints : nullptr;
      const Vec3<T> va0 = A.v, wa0 = A.w, vb0 = B.v, wb0 = B.w;
      SolveCounts counts;
      visit_manifold<kBoxManifoldPoints>(A, B, point, edge_rows, load, store, sc.friction, sc.gravity, Num<T>::from_int(1), sc.P, counts);
      record_visit(conv, va0, wa0, vb0, wb0, A, B, sc.P, counts.shortened_steps);
      if (F4* twin_conv = d.conv_of_pair(ro(mate + t)); conv != nullptr && twin_conv != nullptr)
        for (int q = 0; q < 4; ++q) twin_conv[q] = conv[q];
      note_faults<T>(sc.faults, i, kFqImpulseBody);  // i < j: World's body a
      vel[i] = f4(A.v, T{});
      ang[i] = f4(A.w, T{});
      vel[j] = f4(B.v, T{});
      ang[j] = f4(B.w, T{});
      add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
      add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
      add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
      return;
    }
    const PairContact<T> pc = canonical_pair(sc, i, p, xyz(ro(b.aabb + i)), j, pj, xyz(ro(b.aabb + j)));  // i < j
    BodyView<T> A = dynamic_view(xyz(vel[i]), xyz(ang[i]), inv_mass_of(pi4), rotation_matrix(quat(ro(b.rot + i))),
                                     xyz(ro(b.inert + i)));
    BodyView<T> B = dynamic_view(xyz(vel[j]), xyz(ang[j]), inv_mass_of(pj4), rotation_matrix(quat(ro(b.rot + j))),
                                     xyz(ro(b.inert + j)));
    ContactState<T> cs = load_state(d.pair[t].a, d.pair[t].b);
    SolveCounts counts;
    solve_contact(A, pc.point - p, B, pc.point - pj, pc.n, pc.penetration, cs, sc.friction, sc.gravity, Num<T>::from_int(1), sc.P,
                  counts);
    note_faults<T>(sc.faults, i, kFqImpulseBody);
    vel[i] = f4(A.v, T{});
    ang[i] = f4(A.w, T{});
    vel[j] = f4(B.v, T{});
    ang[j] = f4(B.w, T{});
    const F4 state{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z};
    d.pair[t].a = state;
    d.pair[ro(mate + t)].a = state;
    add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
    add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
    add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
  }
};

// gpu-fixed's rows of every slot's ground and SDF manifold points
// (kRowsOnce<T>), once per frame before the solver's iterations: what
// SolveK's visits of them form (form_manifold_rows, the same sides and
// points), at the index of their state in SolverData::imm; the Q16 flags
// noted where the visits note them (the body, "contact impulse").
template <class T>
struct ImmRowsK {
  using F4 = T4<T>;
  SolverData<T> d;
  const int* has_immovable;  // the coloured solver's (SolveK skips the slots without); null: Jacobi
  ContactRows<T>* rows;
  LS_HD void operator()(int k) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    if (has_immovable != nullptr && ro(has_immovable + k) == 0) return;
    const int i = ro(d.list + k);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i);
    const Vec3<T> p = xyz(pi4), h = xyz(ro(b.half + i));
    const Mat3<T> R = rotation_matrix(quat(ro(b.rot + i)));
    const BodyView<T> self = dynamic_view(Vec3<T>{}, Vec3<T>{}, inv_mass_of(pi4), R, xyz(ro(b.inert + i)));
    const BodyView<T> env = immovable_view<T>();
    const T tol = sc.immovable_tol(i);
    const int stride = sc.imm_stride();
    const long at = static_cast<long>(k) * stride;
    auto loader = [&](int base) {
      return [&, base](int e) {
        const ContactRecord<T>& r = d.imm[at + base + e];
        return load_state(r.a, r.b);
      };
    };
    if (sc.ground_on) {
      auto corner_point = [&](int c, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
        return ground_point(p, R, h, c, sc, tol, r1, r2, n, penetration);
      };
      form_manifold_rows<8>(self, env, corner_point, loader(0), rows + at);
    }
    for (int v = 0; v < sc.n_sdf; ++v) {
      const int base = sc.ground_slots() + 9 * v;
      auto sample = [&](int s, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
        return sdf_point(d, k, v, s, p, r1, r2, n, penetration);
      };
      form_manifold_rows<9>(self, env, sample, loader(base), rows + at + base);
    }
    note_faults<T>(sc.faults, i, kFqImpulse);
  }
};

// gpu-fixed's rows of every coloured edge's manifold points (oriented-box
// model, kRowsOnce<T>), once per frame: what SolveEdgeK's visit of edge e
// forms, at rows[e * kBoxManifoldPoints]; the flags noted where it notes them.
template <class T>
struct EdgeRowsK {
  using F4 = T4<T>;
  SolverData<T> d;
  const int* edges;  // all colours'
  ContactRows<T>* rows;
  LS_HD void operator()(int e) const {
    const BodyArrays<T>& b = d.b;
    const int t = ro(edges + e);
    const int i = ro(d.list + t / d.lists.stride), j = ro(d.lists.nbr + t);
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i), pj4 = ro(b.pos + j);
    const Vec3<T> p = xyz(pi4), pj = xyz(pj4);
    const PairManifold<T>& rec = d.man[t];
    const BodyView<T> A = dynamic_view(Vec3<T>{}, Vec3<T>{}, inv_mass_of(pi4), rotation_matrix(quat(ro(b.rot + i))),
                                       xyz(ro(b.inert + i)));
    const BodyView<T> B = dynamic_view(Vec3<T>{}, Vec3<T>{}, inv_mass_of(pj4), rotation_matrix(quat(ro(b.rot + j))),
                                       xyz(ro(b.inert + j)));
    const int count = rec.count;
    const Vec3<T> n = xyz(rec.n);
    auto point = [&](int c, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& nc, T& penetration) {
      if (c >= count) return false;
      const F4 pt = rec.pt[c];
      r1 = xyz(pt) - p;
      r2 = xyz(pt) - pj;
      nc = n;
      penetration = pt.w;
      return true;
    };
    auto load = [&](int c) { return load_state(rec.st[c].a, rec.st[c].b); };
    form_manifold_rows<kBoxManifoldPoints>(A, B, point, load, rows + static_cast<long>(e) * kBoxManifoldPoints);
    note_faults<T>(d.sc.faults, i, kFqImpulseBody);
  }
};

}  // namespace lockstep::gpu
