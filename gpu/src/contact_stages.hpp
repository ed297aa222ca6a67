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

// Stages 3 and 5 (preparation): each active body
// - finds its contacts in World<T>'s order (ground corners, SDF samples,
//   bodies by index) and its support: the touching contacts whose normal
//   towards it is within acos(support_normal_min) of up; the first is the
//   support, the smallest of their gaps the support gap (75); the normalised
//   sum of the up-facing normals of its contacts within support_fade,
//   weighted by support_weight, the support normal (98);
// - counts its contacts with other active bodies per normal direction (the
//   Jacobi mass splitting);
// - prepares each contact for the solver (eqs 48-50, 58, 76, 86) with the
//   velocities before the warm start, then warm-starts (eq 96) its own
//   velocity, in that order. Reads b.vel/b.ang, writes vout/wout;
// - for the coloured solver, sets up each entry's edge (init_edge).
//
// Warm start of a body-body contact: World<T> keeps one cached impulse per
// pair; here each active body kept its own copy last frame, and the two
// copies of a pair whose bodies were both active are equal (both bodies
// prepare, warm-start and solve the contact with the same arguments, body 1
// the lower index). So the body's own copy is used when it was active last
// frame (found by walking its previous list, ascending like the current
// one, alongside), else the other body's copy. A ground corner that was no
// contact last frame has no cached impulse (its slot is not written).
struct ContactsK {
  SolverData d;
  PreviousContacts prev;
  EdgeArrays edges;  // the coloured solver's per-entry state (edges.mate null: Jacobi)
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
  const float* grow = nullptr;  // oriented-box model: per body, its AABB growth (eqs 97, 107)
  int* over_support = nullptr;  // per body: 1 when its centre of mass is over its support contacts (eq 112)
  int* leaning = nullptr;       // per body: 1 when it leans on what holds it beyond its support (eq 115)
  float* settle_limit = nullptr;  // per body: eq 77 damps a relative speed up to this (eq 116)
  int* can_rest = nullptr;      // per body: statics lets it rest (eq 116 here; eq 117 in LoadOverK)
  // The oriented-box model, eq 117's inputs: per body its load parent; per
  // slot its support points' lever arms (kMaxSupportPoints each), how many
  // (kMaxSupportPoints + 1: too many) and whether something holds it (eq 112).
  int* load_parent = nullptr;
  F4* arms_out = nullptr;
  int* n_arms_out = nullptr;
  int* held_out = nullptr;
  LS_HD void operator()(int k) const {
    const BodyArrays& b = d.b;
    const SceneConsts& sc = d.sc;
    const int i = ro(d.list + k);
    const int* nbr = d.lists.nbr;
    const int beg = d.lists.begin(k), m = d.lists.count[k];
    const F4 pi4 = ro(b.pos + i), h4 = ro(b.half + i), in4 = ro(b.inert + i);
    const Vec3<float> p = xyz(pi4), a = xyz(ro(b.aabb + i)), h = xyz(h4);
    const Mat3<float> R = rotation_matrix(quat(ro(b.rot + i)));
    const Vec3<float> v0 = xyz(ro(b.vel + i)), w0 = xyz(ro(b.ang + i));
    const BodyView<float> self0 = dynamic_view(v0, w0, pi4.w, R, xyz(in4));
    BodyView<float> self = self0;  // warm-started velocity
    const float e_self = h4.w, mu_self = in4.w;
    const float itol = sc.immovable_tol(i);  // eqs 97, 107
    const bool had = prev.had(i);
    const int prev_slot = had ? ro(prev.slot_of + i) : 0;
    const int stride = sc.imm_stride();
    SolveCounts counts;
    unsigned ground_contacts = 0, sdf_contacts = 0;
    const Vec3<float> zero{};
    const Vec3<float> up{0.0f, Num<float>::from_int(1), 0.0f};
    int support = kNoSupport;
    Vec3<float> support_sum{};
    float support_gap_min{};
    // Its support (add_support_contact, eqs 75, 98, 112): the first support
    // contact names the support.
    Vec3<float> arms[kMaxSupportPoints];   // eq 112: the lever arms of its support contacts
    int n_arms = 0;                        // kMaxSupportPoints + 1: too many to look at
    bool loaded = false;                   // eq 112: it touches (within slop) something not a support
    float support_mu = 0.0f;               // eq 116: the first support contact's friction (eq 58)
    int parent = kLoadNone;                // eq 117: fold_load_parent over the support contacts
    // v_n: the contact's closing speed (contact_closing_speed, the lower body first).
    // mu2: the other side's friction; movable: the other side is a dynamic body, awake or asleep (eqs 117, 124).
    auto add_support = [&](int who, const Vec3<float>& n, float penetration, const Vec3<float>& point, auto&& v_n,
                           float mu2, bool movable) {  // eqs 75, 98, 112
      if (!add_support_contact(support_sum, arms, n_arms, support_gap_min, support != kNoSupport, n, penetration,
                               point - p, v_n, sc.P))
        return;
      parent = fold_load_parent(parent, movable ? who : kLoadMany);  // eq 117
      if (support == kNoSupport) {
        support = who;
        support_mu = sc.friction ? combined_friction(mu_self, mu2) : 0.0f;  // eq 58, as prepare_contact
      }
    };
    // A contact with an immovable thing: its preparation and warm start.
    auto immovable = [&](int e, const Vec3<float>& r1, const Vec3<float>& n, float e2, float mu2, bool cached_ok) {
      BodyView<float> B = immovable_view<float>();
      ContactState<float> c = prepare_contact(self0, r1, B, zero, n, e_self, mu_self, e2, mu2, sc.restitution,
                                              sc.friction, sc.P, counts);
      const F4 cached = cached_ok ? ro(&prev.imm[prev_slot * stride + e].a) : F4{};
      if (cached.x > 0.0f) warm_start_contact(self, r1, B, zero, n, c, cached.x, sc.P);
      store_state(c, d.imm[k * stride + e].a, d.imm[k * stride + e].b);
    };
    if (sc.ground_on) {
      const int prev_mask = had ? ro(prev.ground_mask + prev_slot) : 0;
      int mask = 0;
      for (int c = 0; c < 8; ++c) {
        Vec3<float> corner;
        const float depth = ground_corner_depth(p, R, h, c, sc.ground_y, corner);
        if (!(depth > -itol)) continue;
        ++ground_contacts;
        if (holds_body(up, depth, true, sc.P)) loaded = true;  // eq 112
        add_support(kStaticSupport, up, depth, corner, [&] { return contact_closing_speed(v0, w0, p, corner, up); },
                    sc.ground_mu, false);
        mask |= 1 << c;
        immovable(c, corner - p, up, sc.ground_e, sc.ground_mu, ((prev_mask >> c) & 1) != 0);
      }
      ground_mask[k] = mask;
    }
    for (int v = 0; v < sc.n_sdf; ++v) {
      const F4 mat = sc.sdf_material[v];
      for (int s = 0; s < 9; ++s) {
        const SdfContact<float> c = sdf_sample_contact(p, R, h, sc.sdf[v], s, sc.P.contact_tolerance);  // eq 97 (no reach)
        const int g = (k * sc.n_sdf + v) * 9 + s;
        const F4 c0 = f4(c.n, c.penetration), c1 = f4(c.point, c.hit ? 1.0f : 0.0f);
        sdf_c0[g] = c0;
        sdf_c1[g] = c1;
        const int e = sc.ground_slots() + 9 * v + s;
        if (!c.hit) {
          d.imm[k * stride + e] = ContactRecord{};
          continue;
        }
        ++sdf_contacts;
        if (holds_body(c.n, c.penetration, true, sc.P)) loaded = true;  // eq 112
        add_support(kStaticSupport, c.n, c.penetration, c.point,
                    [&] { return contact_closing_speed(v0, w0, p, c.point, c.n); }, mat.y, false);
        immovable(e, xyz(c1) - p, xyz(c0), mat.x, mat.y, had);
      }
    }
    Counter directions = 0;
    unsigned immovable_bodies = 0, pair_points = 0;
    int q = had ? prev.lists.begin(prev_slot) : 0;  // walks the previous list
    const int q_end = had ? q + ro(prev.lists.count + prev_slot) : 0;
    const float gi = sc.oriented ? ro(grow + i) : 0.0f;
    for (int t = beg; t < beg + m; ++t) {
      const int j = nbr[t];
      const F4 pj4 = ro(b.pos + j);
      const Vec3<float> pj = xyz(pj4);
      const bool lower = i < j;
      if (sc.oriented) {
        // eqs 100-107: the pair's manifold, as World<T>'s narrowphase (body a
        // the lower index); every point is a contact (support, preparation,
        // warm start by feature, in point order).
        const Mat3<float> Rj = rotation_matrix(quat(ro(b.rot + j)));
        const Vec3<float> hj = xyz(ro(b.half + j));
        const float gj = ro(grow + j);
        const BoxManifold<float> mf = lower ? pair_manifold(sc, p, R, h, gi, pj, Rj, hj, gj)
                                            : pair_manifold(sc, pj, Rj, hj, gj, p, R, h, gi);
        const bool j_awake = is_awake(ro(b.flags + j));
        const Vec3<float> n_i = lower ? mf.n : -mf.n;  // towards body i
        PairManifold& rec = d.man[t];
        rec.count = mf.count;
        rec.n = f4(mf.n, 0.0f);
        for (int c = 0; c < kBoxManifoldPoints; ++c) {
          rec.pt[c] = c < mf.count ? f4(mf.point[c], mf.penetration[c]) : F4{};
          rec.feature[c] = c < mf.count ? mf.feature[c] : 0;
        }
        rec.deepest = deepest_point(mf.penetration, mf.count);
        rec.depth = mean_depth(mf.penetration, mf.count);  // eq 110
        if (edges.mate != nullptr) init_edge(edges, d.lists, i, t, j, j_awake && mf.count > 0, p.y, pj.y);
        if (mf.count == 0) continue;
        if (!j_awake) ++immovable_bodies;
        if (lower || !j_awake) pair_points += static_cast<unsigned>(mf.count);
        const int shift = 8 * direction_of(n_i);
        if (j_awake && ((directions >> shift) & 255u) < 255u) directions += Counter{1} << shift;
        const BodyView<float> other0 = view_of(b, j, b.vel, b.ang);
        const float e_o = ro(b.half + j).w, mu_o = ro(b.inert + j).w;
        // Last frame's copy of the pair: the body's own (walking its previous
        // list alongside) when it was active, else the other body's.
        int prev_t = -1;
        if (had) {
          int mq = q < q_end ? ro(prev.lists.nbr + q) : 0;
          while (q < q_end && mq < j) { ++q; mq = q < q_end ? ro(prev.lists.nbr + q) : 0; }
          if (q < q_end && mq == j) prev_t = q;
        } else {
          prev_t = prev.entry_of(j, i);
        }
        const int prev_count = prev_t >= 0 ? ro(&prev.man[prev_t].count) : 0;
        SolveCounts here;
        for (int c = 0; c < mf.count; ++c) {
          if (holds_body(n_i, mf.penetration[c], !j_awake, sc.P)) loaded = true;  // eq 112
          add_support(j, n_i, mf.penetration[c], mf.point[c],
                      [&] {
                        return lower ? contact_closing_speed(v0, w0, p, other0.v, other0.w, pj, mf.point[c], mf.n)
                                     : contact_closing_speed(other0.v, other0.w, pj, v0, w0, p, mf.point[c], mf.n);
                      },
                      mu_o, ro(b.pos + j).w != 0.0f);
          const Vec3<float> r1 = mf.point[c] - (lower ? p : pj), r2 = mf.point[c] - (lower ? pj : p);
          ContactState<float> cs =
              prepare_contact(pick(lower, self0, other0), r1, pick(lower, other0, self0), r2, mf.n,
                              lower ? e_self : e_o, lower ? mu_self : mu_o, lower ? e_o : e_self,
                              lower ? mu_o : mu_self, sc.restitution, sc.friction, sc.P, here);
          float cached = 0.0f;  // eq 96: the same feature's impulse last frame
          for (int u = 0; u < prev_count; ++u)
            if (ro(&prev.man[prev_t].feature[u]) == mf.feature[c]) { cached = ro(&prev.man[prev_t].st[u].a).x; break; }
          if (cached > 0.0f) {
            BodyView<float> A = pick(lower, self, other0), B = pick(lower, other0, self);
            warm_start_contact(A, r1, B, r2, mf.n, cs, cached, sc.P);
            self.v = pick(lower, A.v, B.v);
            self.w = pick(lower, A.w, B.w);
          }
          store_state(cs, rec.st[c].a, rec.st[c].b);
        }
        if (lower || other0.inv_mass == 0.0f) counts.restitution_bounces += here.restitution_bounces;
        continue;
      }
      const PairContact<float> pc = canonical_pair(sc, i, p, a, j, pj, xyz(ro(b.aabb + j)));
      const Vec3<float> n_i = lower ? pc.n : -pc.n;  // towards body i
      const int shift = 8 * direction_of(n_i);
      const bool j_awake = is_awake(ro(b.flags + j));
      if (!j_awake) ++immovable_bodies;
      if (edges.mate != nullptr) init_edge(edges, d.lists, i, t, j, j_awake, p.y, pj.y);
      if (j_awake && ((directions >> shift) & 255u) < 255u) directions += Counter{1} << shift;
      if (holds_body(n_i, pc.penetration, !j_awake, sc.P)) loaded = true;  // eq 112
      const BodyView<float> other0 = view_of(b, j, b.vel, b.ang);
      add_support(j, n_i, pc.penetration, pc.point,
                  [&] {
                    return lower ? contact_closing_speed(v0, w0, p, other0.v, other0.w, pj, pc.point, pc.n)
                                 : contact_closing_speed(other0.v, other0.w, pj, v0, w0, p, pc.point, pc.n);
                  },
                  ro(b.inert + j).w, ro(b.pos + j).w != 0.0f);
      const Vec3<float> r1 = pc.point - (lower ? p : pj), r2 = pc.point - (lower ? pj : p);
      const float e_o = ro(b.half + j).w, mu_o = ro(b.inert + j).w;
      // Body 1 is the lower index (one call for either order: the threads of a
      // warp stay together).
      SolveCounts here;
      ContactState<float> c = prepare_contact(pick(lower, self0, other0), r1, pick(lower, other0, self0), r2, pc.n,
                                              lower ? e_self : e_o, lower ? mu_self : mu_o, lower ? e_o : e_self,
                                              lower ? mu_o : mu_self, sc.restitution, sc.friction, sc.P, here);
      if (lower || other0.inv_mass == 0.0f) counts.restitution_bounces += here.restitution_bounces;
      F4 cached{};
      if (had) {
        int mq = q < q_end ? ro(prev.lists.nbr + q) : 0;
        while (q < q_end && mq < j) { ++q; mq = q < q_end ? ro(prev.lists.nbr + q) : 0; }
        if (q < q_end && mq == j) cached = ro(&prev.pair[q].a);
      } else {
        cached = prev.from(j, i);
      }
      if (cached.x > 0.0f) {
        BodyView<float> A = pick(lower, self, other0), B = pick(lower, other0, self);
        warm_start_contact(A, r1, B, r2, pc.n, c, cached.x, sc.P);
        self.v = pick(lower, A.v, B.v);
        self.w = pick(lower, A.w, B.w);
      }
      store_state(c, d.pair[t].a, d.pair[t].b);
    }
    dir_count[i] = directions;
    has_immovable[k] = ground_contacts + sdf_contacts + immovable_bodies > 0 ? 1 : 0;
    if (pair_points > 0) add_counter(&ctr[kCBodyContacts], pair_points);
    support_idx[i] = support;
    const Vec3<float> n_s = support != kNoSupport ? normalize(support_sum) : Vec3<float>{};
    support_n[i] = f4(n_s, support_gap_min);  // w: the support gap
    if (over_support != nullptr) {
      const Stance st = stance_of(arms, n_arms, support != kNoSupport, loaded, w0, sc.P);
      over_support[i] = st.over ? 1 : 0;  // eq 112
      leaning[i] = st.leans ? 1 : 0;      // eq 115
    }
    if (settle_limit != nullptr) {  // eq 116
      const Vec3<float> g = sc.gravity ? sc.P.gravity : Vec3<float>{};
      Footing<float> f;
      if (support != kNoSupport) f = footing_of(loaded, sc.oriented, g, n_s, support_mu, sc.P);
      settle_limit[i] = f.limit;
      can_rest[i] = f.can_rest ? 1 : 0;
    }
    if (load_parent != nullptr) {  // eq 117's inputs
      load_parent[i] = parent >= 0 && settles_before(ro(b.pos + parent).y, parent, p.y, i) ? parent : kLoadNone;
      for (int u = 0; u < n_arms && u < kMaxSupportPoints; ++u) arms_out[k * kMaxSupportPoints + u] = f4(arms[u], 0.0f);
      n_arms_out[k] = n_arms;
      held_out[k] = loaded ? 1 : 0;
    }
    vout[i] = f4(self.v, 0.0f);
    wout[i] = f4(self.w, 0.0f);
    add_counter(&ctr[kCGroundContacts], ground_contacts);
    add_counter(&ctr[kCSdfContacts], sdf_contacts);
    add_counter(&ctr[kCRestitutionBounces], counts.restitution_bounces);
  }
};

}  // namespace lockstep::gpu
