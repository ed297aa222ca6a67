// Stages 3 and 5 (preparation) of docs/SPEC.md 7.2 on the GPU: each active
// body's contacts, its support and its contacts' solver state (ContactsK).
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "colouring.hpp"
#include "contact_records.hpp"
#include "scene_consts.hpp"
#include "solver_data.hpp"

namespace lockstep::gpu {

// What ContactsK works on for one active body (slot k, body i): its pose and
// velocities, what it has found so far (counts, directions) and its support.
template <class T>
struct BodyContacts {
  int k = 0, i = 0;
  Vec3<T> p, a, h;
  Mat3<T> R;
  Vec3<T> v0, w0;
  BodyView<T> self0;  // before the warm start
  BodyView<T> self;   // warm-started velocity
  T e_self = T{}, mu_self = T{};
  bool had = false;  // active last frame
  int prev_slot = 0;
  int q = 0, q_end = 0;  // walks the previous list
  SolveCounts counts;
  unsigned ground_contacts = 0, sdf_contacts = 0, immovable_bodies = 0, pair_points = 0;
  Counter directions = 0;  // contacts with other active bodies per normal direction (jacobi_split)
  // Its support (add_support_contact, eqs 75, 98, 112): the first support
  // contact names the support.
  int support = kNoSupport;
  Vec3<T> support_sum{};
  T support_gap_min{};
  Vec3<T> arms[kMaxSupportPoints];  // eq 112: the lever arms of its support contacts
  int n_arms = 0;                       // kMaxSupportPoints + 1: too many to look at
  Vec3<T> hold_arms[kMaxHolds], hold_n[kMaxHolds];  // eqs 112, 117: what holds it (holds_body): lever arms, normals towards it
  int n_holds = 0;                      // kMaxHolds + 1: too many to look at
  T support_mu = T{};              // eq 116: the first support contact's friction (eq 58)
  int parent = kLoadNone;               // eq 117: fold_load_parent over the support contacts

  // A contact (normal n towards the body) joins its support (eqs 75, 98,
  // 112, 117). v_n(): its closing speed (contact_closing_speed, the lower body
  // first); mu2: the other side's friction; movable: the other side is a
  // dynamic body, awake or asleep (eqs 117, 124).
  template <class ClosingSpeed>
  LS_HD_INLINE void add_support(const SceneConsts<T>& sc, int who, const Vec3<T>& n, T penetration,
                                const Vec3<T>& point, ClosingSpeed&& v_n, T mu2, bool movable) {
    if (!add_support_contact(support_sum, arms, n_arms, support_gap_min, support != kNoSupport, n, penetration,
                             point - p, v_n, sc.P))
      return;
    parent = fold_load_parent(parent, movable ? who : kLoadMany);  // eq 117
    if (support == kNoSupport) {
      support = who;
      support_mu = sc.friction ? combined_friction(mu_self, mu2) : T{};  // eq 58, as prepare_contact
    }
  }
  // eqs 112, 117: a contact (normal n towards the body, point) that holds it, in contact order.
  LS_HD_INLINE void hold(const Vec3<T>& n, T penetration, bool immovable, const Vec3<T>& point, const Params<T>& P) {
    if (holds_body(n, penetration, immovable, P)) add_hold(hold_arms, hold_n, n_holds, point - p, n);
  }
  // A contact with another active body, normal n_i towards this one: counted in its direction.
  LS_HD_INLINE void count_direction(const Vec3<T>& n_i) {
    const int shift = 8 * direction_of(n_i);
    if (((directions >> shift) & 255u) < 255u) directions += Counter{1} << shift;
  }
};

// Stages 3 and 5 (preparation): each active body
// - finds its contacts in World<T>'s order (ground corners, SDF samples,
//   bodies by index: ground, volumes, oriented_pair (the manifolds that
//   PairManifoldK formed) / aabb_pair) and its
//   support (BodyContacts::add_support);
// - counts its contacts with other active bodies per normal direction (the
//   Jacobi mass splitting);
// - prepares each contact for the solver (eqs 48-50, 58, 76, 86) with the
//   velocities before the warm start, then warm-starts (eq 96) its own
//   velocity, in that order. Reads b.vel/b.ang, writes vout/wout;
// - for the coloured solver, sets up each entry's edge (init_edge);
// - writes its support and what statics decides from it (write_support:
//   eqs 112, 115-117).
//
// Warm start of a body-body contact: World<T> keeps one cached impulse per
// pair; here each active body kept its own copy last frame, and the two
// copies of a pair whose bodies were both active are equal (both bodies
// prepare, warm-start and solve the contact with the same arguments, body 1
// the lower index). So the body's own copy is used when it was active last
// frame (found by walking its previous list, ascending like the current
// one, alongside), else the other body's copy. A ground corner that was no
// contact last frame has no cached impulse (its slot is not written).
template <class T>
struct ContactsK {
  using F4 = T4<T>;
  SolverData<T> d;
  PreviousContacts<T> prev;
  EdgeArrays<T> edges;  // the coloured solver's per-entry state (edges.mate null: Jacobi)
  F4* sdf_c0;  // per slot, volume and sample: n, penetration
  F4* sdf_c1;  // contact point, hit (1/0)
  int* support_idx;
  F4* support_n;
  Counter* dir_count;
  int* ground_mask;  // this frame's, per slot
  int* has_immovable;  // per slot: 1 when the body has a contact with an immovable thing (SolveK's work)
  F4* vout;
  F4* wout;
  Counter* ctr;
  int* over_support = nullptr;  // per body: 1 when its centre of mass is over its support contacts (eq 112)
  int* leaning = nullptr;       // per body: 1 when it leans on what holds it beyond its support (eq 115)
  T* settle_limit = nullptr;  // per body: eq 77 damps a relative speed up to this (eq 116)
  int* can_rest = nullptr;      // per body: statics lets it rest (eq 116 here; eq 117 in LoadOverK)
  // The oriented-box model, eq 117's inputs: per body its load parent; per
  // slot its support points' lever arms (kMaxSupportPoints each), how many
  // (kMaxSupportPoints + 1: too many) and what holds it (eq 112: lever arms
  // and normals, kMaxHolds each; how many, kMaxHolds + 1: too many).
  int* load_parent = nullptr;
  F4* arms_out = nullptr;
  int* n_arms_out = nullptr;
  F4* hold_arms_out = nullptr;
  F4* hold_n_out = nullptr;
  int* n_holds_out = nullptr;
  // thread -> slot (WorkOrder: the bodies near the ground together, then by
  // the length of their lists, so that a warp's threads do the same work),
  // or null: thread k is slot k. Each slot's results are its own: any order
  // gives the same values.
  const int* order = nullptr;

  // A contact with an immovable thing (slot e of the body's): its preparation and warm start.
  LS_HD_INLINE void immovable(BodyContacts<T>& c, int e, const Vec3<T>& r1, const Vec3<T>& n, T e2, T mu2,
                              bool cached_ok) const {
    const SceneConsts<T>& sc = d.sc;
    const int stride = sc.imm_stride();
    const Vec3<T> zero{};
    BodyView<T> B = immovable_view<T>();
    note_faults<T>(sc.faults, c.i, e < sc.ground_slots() ? kFqGround : kFqSdf);
    ContactState<T> cs = prepare_contact(c.self0, r1, B, zero, n, c.e_self, c.mu_self, e2, mu2, sc.restitution,
                                             sc.friction, sc.P, c.counts);
    note_faults<T>(sc.faults, c.i, kFqPreparation);
    const F4 cached = cached_ok ? ro(&prev.imm[c.prev_slot * stride + e].a) : F4{};
    if (cached.x > T{}) warm_start_contact(c.self, r1, B, zero, n, cs, cached.x, sc.P);
    note_faults<T>(sc.faults, c.i, kFqWarmStart);
    store_state(cs, d.imm[c.k * stride + e].a, d.imm[c.k * stride + e].b);
  }

  // The ground corners (eqs 84, 97, 107), in corner order.
  LS_HD_INLINE void ground(BodyContacts<T>& c) const {
    const SceneConsts<T>& sc = d.sc;
    const Vec3<T> up{T{}, Num<T>::from_int(1), T{}};
    const T itol = sc.immovable_tol(c.i);  // eqs 97, 107
    const int prev_mask = c.had ? ro(prev.ground_mask + c.prev_slot) : 0;
    int mask = 0;
    for (int q = 0; q < 8; ++q) {
      Vec3<T> corner;
      const T depth = ground_corner_depth(c.p, c.R, c.h, q, sc.ground_y, corner);
      if (!(depth > -itol)) continue;
      ++c.ground_contacts;
      c.hold(up, depth, true, corner, sc.P);  // eq 112
      c.add_support(sc, kStaticSupport, up, depth, corner,
                    [&] { return contact_closing_speed(c.v0, c.w0, c.p, corner, up); }, sc.ground_mu, false);
      mask |= 1 << q;
      immovable(c, q, corner - c.p, up, sc.ground_e, sc.ground_mu, ((prev_mask >> q) & 1) != 0);
    }
    ground_mask[c.k] = mask;
    note_faults<T>(sc.faults, c.i, kFqGround);
  }

  // Each SDF volume's 9 samples (eqs 33-37, 93, 97).
  LS_HD_INLINE void volumes(BodyContacts<T>& c) const {
    const SceneConsts<T>& sc = d.sc;
    const int stride = sc.imm_stride();
    for (int v = 0; v < sc.n_sdf; ++v) {
      const F4 mat = sc.sdf_material[v];
      for (int s = 0; s < 9; ++s) {
        const SdfContact<T> sd = sdf_sample_contact(c.p, c.R, c.h, sc.sdf[v], s, sc.P.contact_tolerance);  // eq 97 (no reach)
        const int g = (c.k * sc.n_sdf + v) * 9 + s;
        const F4 c0 = f4(sd.n, sd.penetration), c1 = f4(sd.point, sd.hit ? Num<T>::from_int(1) : T{});
        sdf_c0[g] = c0;
        sdf_c1[g] = c1;
        const int e = sc.ground_slots() + 9 * v + s;
        if (!sd.hit) {
          d.imm[c.k * stride + e] = ContactRecord<T>{};
          continue;
        }
        ++c.sdf_contacts;
        c.hold(sd.n, sd.penetration, true, sd.point, sc.P);  // eq 112
        c.add_support(sc, kStaticSupport, sd.n, sd.penetration, sd.point,
                      [&] { return contact_closing_speed(c.v0, c.w0, c.p, sd.point, sd.n); }, mat.y, false);
        immovable(c, e, xyz(c1) - c.p, xyz(c0), mat.x, mat.y, c.had);
      }
    }
    note_faults<T>(sc.faults, c.i, kFqSdf);
  }

  // Last frame's entry of the pair with j: the body's own (walking its
  // previous list alongside) when it was active, else the other body's; -1: none.
  LS_HD_INLINE int previous_entry(BodyContacts<T>& c, int j) const {
    if (!c.had) return prev.entry_of(j, c.i);
    int mq = c.q < c.q_end ? ro(prev.lists.nbr + c.q) : 0;
    while (c.q < c.q_end && mq < j) {
      ++c.q;
      mq = c.q < c.q_end ? ro(prev.lists.nbr + c.q) : 0;
    }
    return c.q < c.q_end && mq == j ? c.q : -1;
  }

  // One point of a body pair (body 1 the lower index: one call for either
  // order, the threads of a warp stay together): its preparation and, with a
  // cached impulse, its warm start of the body's own velocity.
  LS_HD_INLINE ContactState<T> pair_point(BodyContacts<T>& c, bool lower, const BodyView<T>& other0, T e_o,
                                              T mu_o, const Vec3<T>& r1, const Vec3<T>& r2,
                                              const Vec3<T>& n, T cached, SolveCounts& here, int lo) const {
    const SceneConsts<T>& sc = d.sc;
    note_faults<T>(sc.faults, lo, kFqPairContact);
    ContactState<T> cs = prepare_contact(pick(lower, c.self0, other0), r1, pick(lower, other0, c.self0), r2, n,
                                             lower ? c.e_self : e_o, lower ? c.mu_self : mu_o, lower ? e_o : c.e_self,
                                             lower ? mu_o : c.mu_self, sc.restitution, sc.friction, sc.P, here);
    note_faults<T>(sc.faults, lo, kFqPreparation);
    if (cached > T{}) {
      BodyView<T> A = pick(lower, c.self, other0), B = pick(lower, other0, c.self);
      warm_start_contact(A, r1, B, r2, n, cs, cached, sc.P);
      c.self.v = pick(lower, A.v, B.v);
      c.self.w = pick(lower, A.w, B.w);
    }
    note_faults<T>(sc.faults, lo, kFqWarmStart);
    return cs;
  }

  // The oriented-box model: entry t's pair manifold (eqs 100-107, formed by
  // PairManifoldK, body a the lower index); every point is a contact
  // (support, preparation, warm start by feature, in point order).
  LS_HD_INLINE void oriented_pair(BodyContacts<T>& c, int t) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    const int i = c.i, j = d.lists.nbr[t];
    const Vec3<T> pj = xyz(ro(b.pos + j));
    const bool lower = i < j;
    PairManifold<T>& rec = d.man[t];
    const int count = rec.count;
    const Vec3<T> n = xyz(rec.n);
    const bool j_awake = is_awake(ro(b.flags + j));
    const Vec3<T> n_i = lower ? n : -n;  // towards body i
    if (edges.mate != nullptr) init_edge(edges, d.lists, i, t, j, j_awake && count > 0, c.p.y, pj.y);
    if (count == 0) return;
    if (!j_awake) ++c.immovable_bodies;
    if (lower || !j_awake) c.pair_points += static_cast<unsigned>(count);
    if (j_awake) c.count_direction(n_i);
    const BodyView<T> other0 = view_of(b, j, b.vel, b.ang);
    const T e_o = restitution_of(ro(b.half + j)), mu_o = friction_of(ro(b.inert + j));
    const int prev_t = previous_entry(c, j);
    const int prev_count = prev_t >= 0 ? ro(&prev.man[prev_t].count) : 0;
    SolveCounts here;
    for (int u = 0; u < count; ++u) {
      const F4 pt = rec.pt[u];
      const Vec3<T> point = xyz(pt);
      const T penetration = pt.w;
      c.hold(n_i, penetration, !j_awake, point, sc.P);  // eq 112
      c.add_support(sc, j, n_i, penetration, point,
                    [&] {
                      return contact_closing_speed(pick(lower, c.v0, other0.v), pick(lower, c.w0, other0.w), pick(lower, c.p, pj),
                                                 pick(lower, other0.v, c.v0), pick(lower, other0.w, c.w0), pick(lower, pj, c.p),
                                                 point, n);
                    },
                    mu_o, inv_mass_of(ro(b.pos + j)) != T{});
      const Vec3<T> r1 = point - (lower ? c.p : pj), r2 = point - (lower ? pj : c.p);
      const int feature = rec.feature[u];
      T cached = T{};  // eq 96: the same feature's impulse last frame
      for (int w = 0; w < prev_count; ++w)
        if (ro(&prev.man[prev_t].feature[w]) == feature) { cached = ro(&prev.man[prev_t].st[w].a).x; break; }
      const ContactState<T> cs = pair_point(c, lower, other0, e_o, mu_o, r1, r2, n, cached, here, lower ? i : j);
      store_state(cs, rec.st[u].a, rec.st[u].b);
    }
    if (lower || other0.inv_mass == T{}) c.counts.restitution_bounces += here.restitution_bounces;
  }

  // The source's AABB model: entry t's one contact (eqs 38-43, 85).
  LS_HD_INLINE void aabb_pair(BodyContacts<T>& c, int t) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    const int i = c.i, j = d.lists.nbr[t];
    const Vec3<T> pj = xyz(ro(b.pos + j));
    const bool lower = i < j;
    const PairContact<T> pc = canonical_pair(sc, i, c.p, c.a, j, pj, xyz(ro(b.aabb + j)));
    note_faults<T>(sc.faults, lower ? i : j, kFqPairContact);
    const Vec3<T> n_i = lower ? pc.n : -pc.n;  // towards body i
    const bool j_awake = is_awake(ro(b.flags + j));
    if (!j_awake) ++c.immovable_bodies;
    if (edges.mate != nullptr) init_edge(edges, d.lists, i, t, j, j_awake, c.p.y, pj.y);
    if (j_awake) c.count_direction(n_i);
    c.hold(n_i, pc.penetration, !j_awake, pc.point, sc.P);  // eq 112
    const BodyView<T> other0 = view_of(b, j, b.vel, b.ang);
    c.add_support(sc, j, n_i, pc.penetration, pc.point,
                  [&] {
                    return contact_closing_speed(pick(lower, c.v0, other0.v), pick(lower, c.w0, other0.w), pick(lower, c.p, pj),
                                                 pick(lower, other0.v, c.v0), pick(lower, other0.w, c.w0), pick(lower, pj, c.p),
                                                 pc.point, pc.n);
                  },
                  friction_of(ro(b.inert + j)), inv_mass_of(ro(b.pos + j)) != T{});
    const Vec3<T> r1 = pc.point - (lower ? c.p : pj), r2 = pc.point - (lower ? pj : c.p);
    const T e_o = restitution_of(ro(b.half + j)), mu_o = friction_of(ro(b.inert + j));
    const int prev_t = previous_entry(c, j);
    const F4 cached = prev_t >= 0 ? ro(&prev.pair[prev_t].a) : F4{};
    SolveCounts here;
    const ContactState<T> cs = pair_point(c, lower, other0, e_o, mu_o, r1, r2, pc.n, cached.x, here, lower ? i : j);
    if (lower || other0.inv_mass == T{}) c.counts.restitution_bounces += here.restitution_bounces;
    store_state(cs, d.pair[t].a, d.pair[t].b);
  }

  // The body's support and what statics decides from it (eqs 112, 115-117).
  LS_HD_INLINE void write_support(const BodyContacts<T>& c) const {
    const SceneConsts<T>& sc = d.sc;
    const int i = c.i, k = c.k;
    support_idx[i] = c.support;
    const Vec3<T> n_s = c.support != kNoSupport ? normalize(c.support_sum) : Vec3<T>{};
    support_n[i] = f4(n_s, c.support_gap_min);  // w: the support gap
    if (over_support != nullptr) {
      const Stance st = stance_of(c.arms, c.n_arms, c.support != kNoSupport, c.n_holds > 0, c.w0, sc.P);
      over_support[i] = st.over ? 1 : 0;  // eq 112
      leaning[i] = st.leans ? 1 : 0;      // eq 115
    }
    if (settle_limit != nullptr) {  // eq 116
      const Vec3<T> g = sc.gravity ? sc.P.gravity : Vec3<T>{};
      Footing<T> f;
      if (c.support != kNoSupport) f = footing_of(c.n_holds > 0, sc.oriented, g, n_s, c.support_mu, sc.P);
      settle_limit[i] = f.limit;
      can_rest[i] = f.can_rest ? 1 : 0;
    }
    if (load_parent != nullptr) {  // eq 117's inputs
      const int s = c.parent;
      load_parent[i] = s >= 0 && settles_before(ro(d.b.pos + s).y, s, c.p.y, i) ? s : kLoadNone;
      for (int u = 0; u < c.n_arms && u < kMaxSupportPoints; ++u)
        arms_out[k * kMaxSupportPoints + u] = f4(c.arms[u], T{});
      n_arms_out[k] = c.n_arms;
      n_holds_out[k] = c.n_holds;
      for (int u = 0; u < c.n_holds && u < kMaxHolds; ++u) {
        hold_arms_out[k * kMaxHolds + u] = f4(c.hold_arms[u], T{});
        hold_n_out[k * kMaxHolds + u] = f4(c.hold_n[u], T{});
      }
    }
  }

  LS_HD void operator()(int thread) const {
    const BodyArrays<T>& b = d.b;
    const SceneConsts<T>& sc = d.sc;
    const int k = order != nullptr ? ro(order + thread) : thread;
    BodyContacts<T> c;
    c.k = k;
    c.i = ro(d.list + k);
    const int i = c.i;
    clear_faults<T>();
    const F4 pi4 = ro(b.pos + i), h4 = ro(b.half + i), in4 = ro(b.inert + i);
    c.p = xyz(pi4);
    c.a = xyz(ro(b.aabb + i));
    c.h = xyz(h4);
    c.R = rotation_matrix(quat(ro(b.rot + i)));
    c.v0 = xyz(ro(b.vel + i));
    c.w0 = xyz(ro(b.ang + i));
    c.self0 = dynamic_view(c.v0, c.w0, inv_mass_of(pi4), c.R, xyz(in4));
    c.self = c.self0;
    c.e_self = restitution_of(h4);
    c.mu_self = friction_of(in4);
    c.had = prev.had(i);
    c.prev_slot = c.had ? ro(prev.slot_of + i) : 0;
    if (sc.ground_on) ground(c);
    volumes(c);
    c.q = c.had ? prev.lists.begin(c.prev_slot) : 0;
    c.q_end = c.had ? c.q + ro(prev.lists.count + c.prev_slot) : 0;
    const int beg = d.lists.begin(k), m = d.lists.count[k];
    for (int t = beg; t < beg + m; ++t) {
      if (sc.oriented) oriented_pair(c, t);
      else aabb_pair(c, t);
    }
    dir_count[i] = c.directions;
    has_immovable[k] = c.ground_contacts + c.sdf_contacts + c.immovable_bodies > 0 ? 1 : 0;
    if (c.pair_points > 0) add_counter(&ctr[kCBodyContacts], c.pair_points);
    note_faults<T>(sc.faults, i, kFqLoad);  // eqs 75, 98, 112: the support
    write_support(c);
    note_faults<T>(sc.faults, i, kFqLoad);  // eqs 112, 115-117
    vout[i] = f4(c.self.v, T{});
    wout[i] = f4(c.self.w, T{});
    add_counter(&ctr[kCGroundContacts], c.ground_contacts);
    add_counter(&ctr[kCSdfContacts], c.sdf_contacts);
    add_counter(&ctr[kCRestitutionBounces], c.counts.restitution_bounces);
  }
};

// ---------------------------------------------------------------------------
// Eq 112's chain (stage 3, after ContactsK), one sweep over the active
// bodies: body i is over its support when ContactsK found it so (`over0`)
// and its first support is not an awake body that settles before it
// (settles_before) and tips (the previous sweep's `in`; the first sweep
// reads over0). World<T> decides it in one pass in stage 6's order; each
// body here reads only bodies before it in that order, so the sweeps reach
// World<T>'s result.
template <class T>
struct TipChainK {
  const int* list;
  BodyArrays<T> b;
  const int* support_idx;
  const int* over0;
  const int* in;
  int* out;
  int* changed;  // bodies whose result differs from `in`
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    int over = ro(over0 + i);
    const int s = ro(support_idx + i);
    if (over != 0 && s >= 0 && is_awake(ro(b.flags + s))) {
      const bool before = settles_before(ro(b.pos + s).y, s, ro(b.pos + i).y, i);
      over = over_with_support(true, before, ro(in + s) != 0) ? 1 : 0;
    }
    out[i] = over;
    if (changed != nullptr) add_to(changed, over != ro(in + i) ? 1 : 0);
  }
};

}  // namespace lockstep::gpu
