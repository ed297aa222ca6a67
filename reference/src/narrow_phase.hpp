// Stages 3-4 of docs/SPEC.md 7.2: contacts against the ground (eq 84), SDF
// volumes (eqs 32-37, 93) and other bodies (eqs 100-106, or the source's
// eqs 38-43, 85), and waking (eq 81).
#pragma once
#include <algorithm>
#include <vector>

#include "lockstep/physics/box_box.hpp"
#include "lockstep/physics/narrow.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

template <class T>
void World<T>::narrow_phase() {
  // contacts_ is not cleared: it is resized to this frame's count, and
  // every element kept is overwritten, so that only a longer list
  // constructs its tail (value-initialising 2,000 contacts of 288 bytes took
  // 0.1 ms of a frame on one thread).
  std::fill(wake_load_.begin(), wake_load_.end(), 0);
  std::vector<ContactPoint<T>>& pair_contacts = scratch_.pair_contacts;
  const T half_tol = P_.contact_tolerance * Num<T>::from_double(0.5);
  const T tol = half_tol + half_tol;  // the two growths together
  // Body against body, pairs in ascending (i, j) order.
  const bool oriented = scene_.pair_contacts == PairModel::kOrientedBox;
  // eqs 100-107 (oriented-box model): each pair's manifold, the pairs in
  // parallel on the world's threads (each a function of its two bodies
  // alone), then their contacts appended in pair order.
  if (oriented) {
    scratch_.pair_manifolds.resize(pairs_.size());
    scratch_.pair_deepest.resize(pairs_.size());
    scratch_.pair_depth.resize(pairs_.size());
    parallel_each(pairs_.size(), 64, [&](std::size_t k, int) {
      const auto [i, j] = pairs_[k];
      const Body<T>& A = bodies_[static_cast<std::size_t>(i)];
      const Body<T>& B = bodies_[static_cast<std::size_t>(j)];
      // the grown AABBs (reach included) as the early-out, then up to 4
      // points with one normal within contact_tolerance plus both reaches
      const T ga = grow_[static_cast<std::size_t>(i)], gb = grow_[static_cast<std::size_t>(j)];
      BoxManifold<T>& m = scratch_.pair_manifolds[k];
      if (!aabb_overlap(A.p, A.aabb_half + Vec3<T>{ga, ga, ga}, B.p, B.aabb_half + Vec3<T>{gb, gb, gb}).hit) {
        m.count = 0;
        return;
      }
      const T pair_tol = (ga - half_tol) + (gb - half_tol) + P_.contact_tolerance;
      m = box_box_manifold(A.p, A.R, A.half, B.p, B.R, B.half, pair_tol);
      if (m.count > 0) {  // eq 110: only the deepest point (first on ties) corrects the pair, by the mean depth of its points
        scratch_.pair_deepest[k] = deepest_point(m.penetration, m.count);
        scratch_.pair_depth[k] = mean_depth(m.penetration, m.count);
      }
      check_faults(i, "box-box contact");
    });
  }
  counters_.pairs_tested += pairs_.size();
  if (oriented) {
    // The pairs' points in pair order: each pair's place by a running sum,
    // then the pairs filled in parallel.
    std::vector<int>& first = scratch_.pair_first;
    first.resize(pairs_.size() + 1);
    first[0] = 0;
    for (std::size_t pk = 0; pk < pairs_.size(); ++pk) first[pk + 1] = first[pk] + scratch_.pair_manifolds[pk].count;
    pair_contacts.resize(static_cast<std::size_t>(first.back()));
    counters_.body_contacts += static_cast<std::uint64_t>(first.back());
    parallel_each(pairs_.size(), 64, [&](std::size_t pk, int) {
      const BoxManifold<T>& m = scratch_.pair_manifolds[pk];
      for (int k = 0; k < m.count; ++k) {
        ContactPoint<T>& c = pair_contacts[static_cast<std::size_t>(first[pk] + k)];
        c = ContactPoint<T>{};  // whole: the element may hold an earlier frame's point
        c.a = pairs_[pk].first;
        c.b = pairs_[pk].second;
        c.n = m.n;
        c.penetration = m.penetration[k];
        c.point = m.point[k];
        c.feature = m.feature[k];
        c.corrects = k == scratch_.pair_deepest[pk];
        if (c.corrects) c.correct_depth = scratch_.pair_depth[pk];
      }
    });
  }
  if (!oriented) pair_contacts.clear();
  for (std::size_t pk = 0; pk < pairs_.size() && !oriented; ++pk) {
    const auto [i, j] = pairs_[pk];
    const Body<T>& A = bodies_[static_cast<std::size_t>(i)];
    const Body<T>& B = bodies_[static_cast<std::size_t>(j)];
    const PairContact<T> pc = pair_contact(A.p, A.aabb_half, B.p, B.aabb_half, half_tol, tol);
    if (!pc.hit) continue;
    {
      ContactPoint<T> c;
      c.a = i;
      c.b = j;
      c.n = pc.n;
      c.penetration = pc.penetration;  // the true overlap (negative: a gap)
      c.point = pc.point;
      pair_contacts.push_back(c);
      ++counters_.body_contacts;
      check_faults(i, "body contact");
    }
  }
  if (scene_.effects.sleep) wake_touched(pair_contacts);

  // The environment's contacts, body by body (each a function of its body
  // alone): the bodies in parallel on the world's threads, in chunks of 64
  // whose contacts are then appended in chunk order, so in body order.
  constexpr std::size_t kEnvChunk = 64;
  std::vector<EnvPart>& env = scratch_.env_parts;
  env.resize((bodies_.size() + kEnvChunk - 1) / kEnvChunk);
  for (EnvPart& e : env) {
    e.contacts.clear();
    e.ground = e.sdf = 0;
  }
  parallel_each(bodies_.size(), kEnvChunk, [&](std::size_t i, int) {
    EnvPart& out = env[i / kEnvChunk];
    std::vector<ContactPoint<T>>& list = out.contacts;
    const Body<T>& b = bodies_[i];
    if (!b.awake()) return;  // 7.3
    // eqs 97, 107: ground corners are speculative contacts within the contact
    // tolerance plus, oriented-box model, the body's reach; SDF samples within
    // the tolerance (with the reach a box came to rest 0.5 mm off the bowl:
    // BowlRest).
    const T reach_tol = oriented ? immovable_tolerance(grow_[i], half_tol, P_.contact_tolerance) : P_.contact_tolerance;
    if (scene_.effects.ground && scene_.ground.present) {
      // eqs 44-46 refined by eq 84: every corner below the plane, or above it by
      // less than contact_tolerance (eq 97), is a contact point (a flat cube gets its 4 bottom corners, an edge 2, a corner 1),
      // in corner order; only the deepest (first on ties) carries the
      // position correction of eq 89, so the body is corrected once.
      int first = static_cast<int>(list.size());
      int deepest = -1;
      for (int k = 0; k < 8; ++k) {
        Vec3<T> corner;
        const T depth = ground_corner_depth(b.p, b.R, b.half, k, ground_y_, corner);  // eq 84
        if (!(depth > -reach_tol)) continue;  // eq 97: speculative within the tolerance (and reach, eq 107)
        ContactPoint<T> c;
        c.a = static_cast<int>(i);
        c.b = -1;
        c.n = Vec3<T>{T{}, Num<T>::from_int(1), T{}};
        c.penetration = depth;
        c.point = corner;
        c.corrects = false;
        c.feature = k;
        if (deepest < 0 || depth > list[static_cast<std::size_t>(deepest)].penetration)
          deepest = static_cast<int>(list.size());
        list.push_back(c);
        ++out.ground;
      }
      if (deepest >= first) list[static_cast<std::size_t>(deepest)].corrects = true;
      check_faults(static_cast<int>(i), "ground contact");
    }
    if (scene_.effects.sdf) {
      for (std::size_t k = 0; k < sdf_.grids.size(); ++k) {
        const SdfGrid<T>& g = sdf_.grids[k];
        // eq 93: sample the 8 corners (radius 0) and the centre (radius min h);
        // as on the ground (eq 84), every penetrating sample is a contact point
        // with its own normal, and only the deepest carries the correction.
        const int first = static_cast<int>(list.size());
        int deepest = -1;
        for (int s = 0; s < 9; ++s) {
          const SdfContact<T> sc = sdf_sample_contact(b.p, b.R, b.half, g, s, P_.contact_tolerance);  // eqs 33-37, 97
          if (!sc.hit) continue;
          ContactPoint<T> c;
          c.a = static_cast<int>(i);
          c.b = -2 - static_cast<int>(k);
          c.n = sc.n;
          c.point = sc.point;
          c.penetration = sc.penetration;
          c.corrects = false;
          c.feature = s;
          if (deepest < 0 || sc.penetration > list[static_cast<std::size_t>(deepest)].penetration)
            deepest = static_cast<int>(list.size());
          list.push_back(c);
          ++out.sdf;
        }
        if (deepest >= first) list[static_cast<std::size_t>(deepest)].corrects = true;
        check_faults(static_cast<int>(i), "SDF contact");
      }
    }
  });
  // The list: the chunks' environment contacts in chunk order, then the
  // pairs' contacts, copied into place on the world's threads.
  std::size_t env_count = 0;
  for (EnvPart& e : env) {
    e.first = env_count;
    env_count += e.contacts.size();
    counters_.ground_contacts += e.ground;
    counters_.sdf_contacts += e.sdf;
  }
  contacts_.resize(env_count + pair_contacts.size());
  parallel_each(env.size(), 1, [&](std::size_t k, int) {
    for (std::size_t m = 0; m < env[k].contacts.size(); ++m) env[k].contacts[m].assign_to(contacts_[env[k].first + m]);
  });
  parallel_each(pair_contacts.size(), 256, [&](std::size_t k, int) { pair_contacts[k].assign_to(contacts_[env_count + k]); });

  // Support contacts (settling, sleep): touching to within slop (penetration
  // > -slop: rounding noise of a resting body is not a gap, a speculative gap
  // is) with a normal within acos(support_normal_min) of up. A body's support
  // normal (98) is the normalised sum of the normals (turned towards it) of
  // its contacts within support_fade (max(slop, |g dt| dt); |g dt| dt: what
  // it falls from rest in a frame) that face up so, each weighted by
  // support_weight (1 touching, fading to 0 at a gap of support_fade; every
  // support contact weighs > 0): (0, 1, 0) on the ground, the mean
  // surface normal under a box resting on a curved SDF, turning smoothly as a
  // corner rocks on and off. Its support gap (75) is the smallest gap of its
  // support contacts.
  std::fill(support_.begin(), support_.end(), -1);
  std::fill(support_n_.begin(), support_n_.end(), Vec3<T>{});
  std::fill(support_gap_.begin(), support_gap_.end(), T{});
  // eq 112's inputs: the lever arms of each body's contacts in its support
  // normal (within support_fade: a corner it would fall onto within a frame
  // holds it as one it touches), how many, and whether it also touches something (within slop)
  // that is not a support: a neighbour beside it, a body above it.
  scratch_.support_arms.resize(bodies_.size());
  scratch_.n_arms.assign(bodies_.size(), 0);
  std::vector<int>& n_arms = scratch_.n_arms;
  scratch_.hold_arms.resize(bodies_.size());
  scratch_.hold_n.resize(bodies_.size());
  scratch_.n_holds.assign(bodies_.size(), 0);
  std::vector<int>& n_holds = scratch_.n_holds;
  auto add_holder = [&](int body, const Contact<T>& cc, const Vec3<T>& n) {  // eqs 112, 117: what holds it, and which way
    const auto i = static_cast<std::size_t>(body);
    add_hold(scratch_.hold_arms[i].data(), scratch_.hold_n[i].data(), n_holds[i], cc.point - bodies_[i].p, n);
  };
  auto add_support = [&](int body, std::size_t ci, const Vec3<T>& n) {  // eqs 75, 98, 112
    const auto i = static_cast<std::size_t>(body);
    const Contact<T>& cc = contacts_[ci];
    auto v_n = [&] {
      const Body<T>& A = bodies_[static_cast<std::size_t>(cc.a)];
      if (cc.b < 0) return contact_closing_speed(A.v, A.w, A.p, cc.point, cc.n);
      const Body<T>& B = bodies_[static_cast<std::size_t>(cc.b)];
      return contact_closing_speed(A.v, A.w, A.p, B.v, B.w, B.p, cc.point, cc.n);
    };
    if (add_support_contact(support_n_[i], scratch_.support_arms[i].data(), n_arms[i], support_gap_[i], support_[i] >= 0, n,
                            cc.penetration, cc.point - bodies_[i].p, v_n, P_) &&
        support_[i] < 0)
      support_[i] = static_cast<int>(ci);
  };
  // Per body its contacts in contact order (body_contacts), then each body
  // alone: its holds and supports, its contacts in contact order, and its stance.
  std::vector<int>& first_contact = scratch_.body_contact_begin;
  std::vector<int>& body_contacts = scratch_.body_contacts;
  first_contact.assign(bodies_.size() + 1, 0);
  for (const Contact<T>& c : contacts_) {
    ++first_contact[static_cast<std::size_t>(c.a) + 1];
    if (c.b >= 0) ++first_contact[static_cast<std::size_t>(c.b) + 1];
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) first_contact[i + 1] += first_contact[i];
  body_contacts.resize(static_cast<std::size_t>(first_contact.back()));
  {
    std::vector<int> at(first_contact.begin(), first_contact.end() - 1);
    for (std::size_t ci = 0; ci < contacts_.size(); ++ci) {
      const Contact<T>& c = contacts_[ci];
      body_contacts[static_cast<std::size_t>(at[static_cast<std::size_t>(c.a)]++)] = static_cast<int>(ci);
      if (c.b >= 0) body_contacts[static_cast<std::size_t>(at[static_cast<std::size_t>(c.b)]++)] = static_cast<int>(ci);
    }
  }
  parallel_each(bodies_.size(), 64, [&](std::size_t i, int) {  // each body alone
    const int body = static_cast<int>(i);
    for (int k = first_contact[i]; k < first_contact[i + 1]; ++k) {
      const auto ci = static_cast<std::size_t>(body_contacts[static_cast<std::size_t>(k)]);
      const Contact<T>& c = contacts_[ci];
      const int other = c.a == body ? c.b : c.a;
      const Vec3<T> n = c.a == body ? c.n : -c.n;  // towards this body
      // eq 112's holds; immovable: ground, SDF, static, asleep
      const bool other_immovable = other < 0 || !bodies_[static_cast<std::size_t>(other)].awake();
      if (holds_body(n, c.penetration, other_immovable, P_)) add_holder(body, c, n);
      add_support(body, ci, n);
    }
    if (support_[i] >= 0) support_n_[i] = normalize(support_n_[i]);
    const Stance st = stance_of(scratch_.support_arms[i].data(), n_arms[i], support_[i] >= 0, n_holds[i] > 0, bodies_[i].w, P_);
    over_support_[i] = st.over;              // eq 112
    leaning_[i] = oriented && st.leans ? 1 : 0;  // eq 115
    check_faults(static_cast<int>(i), "support normal and stance (eqs 98, 112)");
  });
  // Stage 6's order (settle() walks it): the supported awake bodies, lowest
  // first (ties: index). Nothing before stage 6 moves or wakes a body.
  scratch_.settle_order.clear();
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (bodies_[i].awake() && support_[i] >= 0) scratch_.settle_order.push_back(static_cast<int>(i));
  std::sort(scratch_.settle_order.begin(), scratch_.settle_order.end(), [&](int a, int b) {
    return settles_before(bodies_[static_cast<std::size_t>(a)].p.y, a, bodies_[static_cast<std::size_t>(b)].p.y, b);
  });
  // eq 116: friction holds it on its first support contact's friction (eq 58),
  // or something holds it from the side or from above (eq 112's holds).
  const Vec3<T> g = scene_.effects.gravity ? P_.gravity : Vec3<T>{};
  auto material_mu = [&](int idx) {
    return idx >= 0 ? bodies_[static_cast<std::size_t>(idx)].friction
                    : (idx == -1 ? ground_mu_ : sdf_mu_[static_cast<std::size_t>(-2 - idx)]);
  };
  std::fill(can_rest_.begin(), can_rest_.end(), 1);
  for (const int idx : scratch_.settle_order) {
    const auto i = static_cast<std::size_t>(idx);
    const Contact<T>& c = contacts_[static_cast<std::size_t>(support_[i])];
    const T mu = scene_.effects.friction ? combined_friction(material_mu(c.a), material_mu(c.b)) : T{};
    const Footing<T> f = footing_of(n_holds[i] > 0, oriented, g, support_n_[i], mu, P_);
    can_rest_[i] = f.can_rest ? 1 : 0;
    settle_limit_[i] = f.limit;
  }
  if (!oriented) return;
  // eq 117: load parents (the one dynamic body below that every support
  // contact touches; eq 117 reads it when that body is awake, eq 124 when it
  // sleeps), then each load from the top down (stage 6's order reversed:
  // children first), its children in ascending index; a body whose load's
  // centre is not over its support tips with its load: it does not settle
  // and cannot rest, unless something holds it (eq 112).
  scratch_.load_parent.assign(bodies_.size(), kLoadNone);
  for (const Contact<T>& c : contacts_) {
    if (!(c.penetration > -P_.slop)) continue;
    if (c.n.y >= P_.support_normal_min) {
      const bool movable = c.b >= 0 && !bodies_[static_cast<std::size_t>(c.b)].is_static;
      int& s = scratch_.load_parent[static_cast<std::size_t>(c.a)];
      s = fold_load_parent(s, movable ? c.b : kLoadMany);
    }
    if (c.b >= 0 && -c.n.y >= P_.support_normal_min) {
      int& s = scratch_.load_parent[static_cast<std::size_t>(c.b)];
      s = fold_load_parent(s, !bodies_[static_cast<std::size_t>(c.a)].is_static ? c.a : kLoadMany);
    }
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {  // a load parent settles before its child (no cycle)
    int& s = scratch_.load_parent[i];
    if (s >= 0 && !settles_before(bodies_[static_cast<std::size_t>(s)].p.y, s, bodies_[i].p.y, static_cast<int>(i)))
      s = kLoadNone;
  }
  scratch_.load_children.clear();
  scratch_.sleeper_children.clear();
  for (const int idx : scratch_.settle_order) {
    const int s = sleeper_load_parent(true, scratch_.load_parent[static_cast<std::size_t>(idx)], kLoadNone);
    if (s < 0) continue;
    (bodies_[static_cast<std::size_t>(s)].asleep ? scratch_.sleeper_children : scratch_.load_children).emplace_back(s, idx);
  }
  if (!scratch_.load_children.empty() || !scratch_.sleeper_children.empty()) {
    std::sort(scratch_.load_children.begin(), scratch_.load_children.end());
    scratch_.load_mass.resize(bodies_.size());
    scratch_.load_offset.resize(bodies_.size());
    scratch_.load_tips.resize(bodies_.size());
    // Top down (stage 6's order reversed), each load tree on its own (a
    // body reads its load children's loads alone).
    auto awake_load_parent = [&](int idx) {
      const int s = scratch_.load_parent[static_cast<std::size_t>(idx)];
      return s >= 0 && !bodies_[static_cast<std::size_t>(s)].asleep ? s : -1;
    };
    in_order_by_groups(scratch_.settle_order, true, awake_load_parent, [&](int idx) {
      const auto i = static_cast<std::size_t>(idx);
      const auto [first, last] = form_load(idx, scratch_.load_children);
      check_faults(idx, "load (eq 117)");
      const bool carries = first != last;
      bool child_tips = false;
      for (auto c = first; c != last; ++c) child_tips = child_tips || scratch_.load_tips[static_cast<std::size_t>(c->second)] != 0;
      // no load children: eq 112's answer stands; held: only where the holds block its load's every way to tip
      if (carries && !load_stands(scratch_.support_arms[i].data(), n_arms[i], scratch_.load_offset[i],
                                  length(bodies_[i].w) < P_.sleep_angular, scratch_.hold_arms[i].data(),
                                  scratch_.hold_n[i].data(), n_holds[i])) {
        over_support_[i] = 0;
        can_rest_[i] = 0;
      }
      if (!load_rests(child_tips)) can_rest_[i] = 0;
      scratch_.load_tips[i] = load_tips(over_support_[i] != 0, child_tips) ? 1 : 0;
    });
    if (!scratch_.sleeper_children.empty()) sleeper_loads();
  }
  // eq 112's chain, in that order: a body riding on a body that tips tips too.
  for (const int idx : scratch_.settle_order) {
    const auto i = static_cast<std::size_t>(idx);
    const Contact<T>& c = contacts_[static_cast<std::size_t>(support_[i])];  // the first support
    const int s = c.a == idx ? c.b : c.a;
    if (s < 0 || !bodies_[static_cast<std::size_t>(s)].awake()) continue;
    const auto si = static_cast<std::size_t>(s);
    const bool before = settles_before(bodies_[si].p.y, s, bodies_[i].p.y, idx);
    over_support_[i] = over_with_support(over_support_[i] != 0, before, over_support_[si] != 0) ? 1 : 0;
  }
}

// eq 117: body idx's load (scratch_.load_mass, scratch_.load_offset) from its children in
// `children` ((parent, child), sorted), whose loads are formed; returns its
// children's range there.
template <class T>
auto World<T>::form_load(int idx, const LoadChildren& children)
    -> std::pair<LoadChildren::const_iterator, LoadChildren::const_iterator> {
  const auto i = static_cast<std::size_t>(idx);
  const auto first = std::lower_bound(children.begin(), children.end(), std::pair<int, int>{idx, -1});
  auto last = first;
  while (last != children.end() && last->first == idx) ++last;
  auto each_child = [&](auto&& f) {
    for (auto c = first; c != last; ++c) {
      const auto j = static_cast<std::size_t>(c->second);
      f(scratch_.load_mass[j], bodies_[j].p, scratch_.load_offset[j]);
    }
  };
  sum_load(bodies_[i].inv_mass, bodies_[i].p, each_child, scratch_.load_mass[i], scratch_.load_offset[i]);  // eq 117
  return {first, last};
}

// eq 124: with an awake body resting on a sleeper (scratch_.sleeper_children holds
// those), the sleepers' loads: their sleeping children join, each sleeper's
// load is formed from the top down (descending stage 6 order), and a sleeper
// whose load's centre is not over its recorded support points wakes at the
// end of the frame (wake_loaded).
template <class T>
void World<T>::sleeper_loads() {
  auto before = [&](int a, int b) {
    return settles_before(bodies_[static_cast<std::size_t>(a)].p.y, a, bodies_[static_cast<std::size_t>(b)].p.y, b);
  };
  for (std::size_t j = 0; j < bodies_.size(); ++j) {
    if (!bodies_[j].asleep) continue;
    const int s = sleeper_load_parent(false, kLoadNone, sleep_support_[j].parent);
    if (s >= 0 && bodies_[static_cast<std::size_t>(s)].asleep && before(s, static_cast<int>(j)))
      scratch_.sleeper_children.emplace_back(s, static_cast<int>(j));
  }
  std::sort(scratch_.sleeper_children.begin(), scratch_.sleeper_children.end());
  scratch_.sleeper_loads.clear();
  for (const auto& [s, c] : scratch_.sleeper_children) {
    scratch_.sleeper_loads.push_back(s);
    if (bodies_[static_cast<std::size_t>(c)].asleep) scratch_.sleeper_loads.push_back(c);
  }
  std::sort(scratch_.sleeper_loads.begin(), scratch_.sleeper_loads.end(), [&](int a, int b) { return before(b, a); });
  scratch_.sleeper_loads.erase(std::unique(scratch_.sleeper_loads.begin(), scratch_.sleeper_loads.end()), scratch_.sleeper_loads.end());
  for (const int idx : scratch_.sleeper_loads) {
    const auto [first, last] = form_load(idx, scratch_.sleeper_children);
    const bool carries = first != last;
    check_faults(idx, "sleeper load (eq 124)");
    const SleepSupport& rec = sleep_support_[static_cast<std::size_t>(idx)];
    if (carries && !sleeper_load_over_support(rec.arms.data(), rec.count, scratch_.load_offset[static_cast<std::size_t>(idx)]))
      wake_load_[static_cast<std::size_t>(idx)] = 1;
  }
}

}  // namespace lockstep
