// Stages 5 and 7 of docs/SPEC.md 7.2: sequential impulses (eqs 48-62, 86-88,
// 94-99; the per-contact and per-manifold steps of physics/solver.hpp) and
// Baumgarte position correction (eqs 63, 89).
#pragma once
#include <algorithm>
#include <type_traits>
#include <utility>
#include <vector>

#include "lockstep/physics/contact.hpp"
#include "lockstep/physics/integrate.hpp"
#include "lockstep/physics/solver.hpp"
#include "lockstep/world.hpp"
#include "solve_schedule.hpp"

namespace lockstep {

namespace solver {
// The contact-side view of body `idx`: the ground, SDF volumes, static and
// sleeping bodies are immovable (inverse mass and inertia 0).
template <class T>
BodyView<T> view_of(const std::vector<Body<T>>& bodies, int idx) {
  if (idx < 0) return immovable_view<T>();
  const Body<T>& b = bodies[static_cast<std::size_t>(idx)];
  if (!b.awake()) return immovable_view<T>();
  return dynamic_view(b.v, b.w, b.inv_mass, b.R, b.inv_inertia);
}

// The most points of one manifold: 8 ground corners, 9 samples of one SDF
// volume (eq 93), 4 box-box points (eq 105).
inline constexpr int kManifoldPoints = 9;
// The fewest visits a part of a parallel step gets (7.7 "Threads"): a visit
// is 0.2 (float) to 0.5 (fixed) microseconds of work on pile1000, a part's
// start and end a microsecond or two; a colour of 16 edges or more is split.
inline constexpr std::size_t kVisitGrain = 8;
// The fewest visits per part of the passes on threads (solve_schedule.hpp):
// a visit whose other body another part runs may wait for it, so a part
// wants a region of its own (pile1000: 4,000-6,000 visits a pass).
inline constexpr std::size_t kPartVisits = 16;
}  // namespace solver

template <class T>
void World<T>::solve_contacts() {
  const Effects& fx = scene_.effects;
  auto tally = [this](const SolveCounts& n) {
    counters_.solver_contacts += n.solver_contacts;
    counters_.normal_impulses += n.normal_impulses;
    counters_.restitution_bounces += n.restitution_bounces;
    counters_.friction_steps += n.friction_steps;
  };
  auto material = [&](int idx, T& e, T& mu) {
    if (idx >= 0) { e = bodies_[static_cast<std::size_t>(idx)].restitution; mu = bodies_[static_cast<std::size_t>(idx)].friction; }
    else if (idx == -1) { e = ground_e_; mu = ground_mu_; }
    else { e = sdf_e_[static_cast<std::size_t>(-2 - idx)]; mu = sdf_mu_[static_cast<std::size_t>(-2 - idx)]; }
  };
  // A parallel region's counts: one per part, added up after (integers, in
  // any order).
  struct alignas(64) PartCounts : SolveCounts {};  // a cache line each: every visit adds to its part's
  std::vector<PartCounts> part_counts(static_cast<std::size_t>(workers_.threads));
  auto region = [&](std::size_t count, std::size_t grain, auto&& item) {
    for (PartCounts& c : part_counts) c = PartCounts{};
    parallel_each(count, grain, [&](std::size_t k, int part) { item(k, part_counts[static_cast<std::size_t>(part)]); });
    for (const SolveCounts& c : part_counts) tally(c);
  };
  // Prepare: lever arms, then approach speed, restitution, friction and
  // effective mass (eqs 48-50, 58, 76, 86); each contact alone.
  region(contacts_.size(), 64, [&](std::size_t k, SolveCounts& counts) {
    Contact<T>& c = contacts_[k];
    const BodyView<T> A = solver::view_of(bodies_, c.a);
    const BodyView<T> B = solver::view_of(bodies_, c.b);
    c.r1 = c.point - bodies_[static_cast<std::size_t>(c.a)].p;
    c.r2 = c.b >= 0 ? c.point - bodies_[static_cast<std::size_t>(c.b)].p : Vec3<T>{};
    T e1, mu1, e2, mu2;
    material(c.a, e1, mu1);
    material(c.b, e2, mu2);
    c.state = prepare_contact(A, c.r1, B, c.r2, c.n, e1, mu1, e2, mu2, fx.restitution, fx.friction, P_, counts);
    c.row = contact_rows(A, c.r1, B, c.r2, c.n, c.state.k_n);  // eqs 114, 128-129: once per frame
    check_faults(c.a, "contact preparation");
  });
  // eq 96: warm start from last frame's normal impulse of the same contact
  // (same bodies, same feature), applied in contact order: each contact's
  // impulse and its velocity changes (which the velocities do not enter),
  // then each body adds its contacts' changes in contact order (the
  // additions of the serial loop, in its order). A Q16 fault is reported
  // for the first contact that raised one, as the serial loop would.
  if (!warm_.empty()) {
    scratch_.warm_delta.resize(contacts_.size());
    scratch_.warm_faults.assign(contacts_.size() * 3, 0u);
    std::vector<char>& warmed = scratch_.warmed;
    warmed.assign(contacts_.size(), 0);
    parallel_each(contacts_.size(), 64, [&](std::size_t k, int) {
      Contact<T>& c = contacts_[k];
      const auto it = std::lower_bound(warm_.begin(), warm_.end(), c, [](const CachedImpulse& w, const Contact<T>& x) {
        return w.a != x.a ? w.a < x.a : (w.b != x.b ? w.b < x.b : w.feature < x.feature);
      });
      if (it == warm_.end() || it->a != c.a || it->b != c.b || it->feature != c.feature) return;
      const BodyView<T> A = solver::view_of(bodies_, c.a), B = solver::view_of(bodies_, c.b);
      warmed[k] = warm_start_delta(A, c.r1, B, c.r2, c.n, c.state, it->j_n, P_, scratch_.warm_delta[k]) ? 1 : 0;
      scratch_.warm_faults[3 * k] = Num<T>::take_faults();
    });
    parallel_each(bodies_.size(), 64, [&](std::size_t i, int) {
      Body<T>& b = bodies_[i];
      if (!b.awake() || !(b.inv_mass > T{})) return;
      for (int k = scratch_.body_contact_begin[i]; k < scratch_.body_contact_begin[i + 1]; ++k) {
        const auto ci = static_cast<std::size_t>(scratch_.body_contacts[static_cast<std::size_t>(k)]);
        if (!warmed[ci]) continue;
        const ImpulseDelta<T>& d = scratch_.warm_delta[ci];
        const bool side_a = contacts_[ci].a == static_cast<int>(i);
        if (side_a) {  // apply_delta's additions on this side
          b.v += d.va;
          b.w += d.wa;
        } else {
          b.v -= d.vb;
          b.w -= d.wb;
        }
        scratch_.warm_faults[3 * ci + (side_a ? 1 : 2)] = Num<T>::take_faults();
      }
    });
    for (std::size_t k = 0; k < contacts_.size(); ++k) {
      const std::uint32_t f = scratch_.warm_faults[3 * k] | scratch_.warm_faults[3 * k + 1] | scratch_.warm_faults[3 * k + 2];
      if (f != 0) throw RunError(frame_, contacts_[k].a, "warm start impulse", q16_flag_name(f));
    }
  }
  // Iterations (eqs 94, 95, 97). A body's contacts with one environment
  // object (its ground corners, its samples of one SDF) and a body pair's
  // box-box points (eqs 100-106) form a manifold that is solved Jacobi-style
  // (eq 99, solve_manifold); with the source's AABB pair model a body pair is
  // one contact (solve_contact, effective masses unscaled). The visits follow
  // each other Gauss-Seidel-style in the order of eqs 125-127
  // (physics/solve_order.hpp), parallel by construction.
  const T one = Num<T>::from_int(1);
  const bool oriented = scene_.pair_contacts == PairModel::kOrientedBox;
  // The visits: a manifold (consecutive contacts of one body with one other
  // side) or a single AABB pair contact, as [begin, end) in the list.
  std::vector<std::pair<std::size_t, std::size_t>>& visits = scratch_.visits;
  visits.clear();
  for (std::size_t s = 0; s < contacts_.size();) {
    std::size_t e = s + 1;
    if (contacts_[s].b < 0 || oriented)
      while (e < contacts_.size() && contacts_[e].a == contacts_[s].a && contacts_[e].b == contacts_[s].b) ++e;
    visits.emplace_back(s, e);
    s = e;
  }
  // Eq 99's split of each manifold visit, once for the whole solve: the
  // sides' masses and the points' k_n do not change in it (solve_manifold_rows
  // would form the same value at every pass). A visit whose first point has
  // k_n = 0 (both sides immovable) is skipped by the solve and has none.
  scratch_.visit_split.assign(visits.size(), one);
  parallel_each(visits.size(), 64, [&](std::size_t vi, int) {  // each visit alone
    const std::size_t s = visits[vi].first, e = visits[vi].second;
    if (!(contacts_[s].b < 0 || oriented) || !(contacts_[s].state.k_n > T{})) return;
    const T inv_a = solver::view_of(bodies_, contacts_[s].a).inv_mass;
    const T inv_b = solver::view_of(bodies_, contacts_[s].b).inv_mass;
    T o{};
    for (std::size_t k = s; k < e; ++k) o += split_share(inv_a, inv_b, contacts_[k].state.k_n);
    scratch_.visit_split[vi] = manifold_split(o, static_cast<int>(e - s));
    check_faults(contacts_[s].a, "contact preparation");
  });
  // eqs 125-127: each awake body's own visits (immovable other side: the
  // environment, then static and sleeping bodies by index), and the edges
  // (two awake bodies) coloured in key order.
  auto awake = [&](int idx) { return idx >= 0 && bodies_[static_cast<std::size_t>(idx)].awake(); };
  scratch_.own_visits.clear();
  scratch_.edges.clear();
  for (std::size_t vi = 0; vi < visits.size(); ++vi) {
    const Contact<T>& c = contacts_[visits[vi].first];
    if (!(c.state.k_n > T{})) continue;  // both sides immovable: no visit
    if (awake(c.a) && awake(c.b)) {
      const Body<T>& A = bodies_[static_cast<std::size_t>(c.a)];
      const Body<T>& B = bodies_[static_cast<std::size_t>(c.b)];
      scratch_.edges.push_back({EdgeKey{edge_key(c.a, c.b, A.p.y, B.p.y, scratch_.band_inv), c.a, c.b}, static_cast<int>(vi)});  // eqs 125-126
      continue;
    }
    const int self = awake(c.a) ? c.a : c.b, other = self == c.a ? c.b : c.a;
    // environment (other < 0) first in list order, then bodies by index
    const std::uint64_t rank = other < 0 ? 0u : static_cast<std::uint64_t>(other) + 1u;
    scratch_.own_visits.emplace_back((static_cast<std::uint64_t>(self) << 32) | rank, static_cast<int>(vi));
  }
  std::sort(scratch_.own_visits.begin(), scratch_.own_visits.end());
  scratch_.visit_bodies.clear();
  scratch_.body_visit_begin.clear();
  scratch_.body_visits.clear();
  for (std::size_t k = 0; k < scratch_.own_visits.size(); ++k) {
    const int body = static_cast<int>(scratch_.own_visits[k].first >> 32);
    if (scratch_.visit_bodies.empty() || scratch_.visit_bodies.back() != body) {
      scratch_.visit_bodies.push_back(body);
      scratch_.body_visit_begin.push_back(static_cast<int>(k));
    }
    scratch_.body_visits.push_back(scratch_.own_visits[k].second);
  }
  scratch_.body_visit_begin.push_back(static_cast<int>(scratch_.body_visits.size()));
  std::sort(scratch_.edges.begin(), scratch_.edges.end(), [](const SolveEdge& x, const SolveEdge& y) { return x.key.before(y.key); });
  scratch_.colour_top.assign(bodies_.size(), -1);
  int colours = 0;
  std::vector<int>& colour_of = scratch_.colour_visits;  // first the colour of each edge, then the edges by colour
  colour_of.resize(scratch_.edges.size());
  for (std::size_t k = 0; k < scratch_.edges.size(); ++k) {
    int& top_lo = scratch_.colour_top[static_cast<std::size_t>(scratch_.edges[k].key.lo)];
    int& top_hi = scratch_.colour_top[static_cast<std::size_t>(scratch_.edges[k].key.hi)];
    const int colour = edge_colour(top_lo, top_hi);  // eq 127
    top_lo = top_hi = colour;
    colour_of[k] = colour;
    colours = std::max(colours, colour + 1);
  }
  scratch_.colour_begin.assign(static_cast<std::size_t>(colours) + 1, 0);
  for (int c : colour_of) ++scratch_.colour_begin[static_cast<std::size_t>(c) + 1];
  for (int c = 0; c < colours; ++c) scratch_.colour_begin[static_cast<std::size_t>(c) + 1] += scratch_.colour_begin[static_cast<std::size_t>(c)];
  {
    std::vector<int> at(scratch_.colour_begin.begin(), scratch_.colour_begin.end() - 1);
    std::vector<int> by_colour(scratch_.edges.size());
    for (std::size_t k = 0; k < scratch_.edges.size(); ++k)
      by_colour[static_cast<std::size_t>(at[static_cast<std::size_t>(colour_of[k])]++)] = scratch_.edges[k].visit;
    scratch_.colour_visits.swap(by_colour);
  }
  // A visit is a function of its two sides' velocities and its contacts'
  // states alone; one that applied no impulse changed neither, so while
  // neither side's velocity has changed since, visiting it again would apply
  // none again: it is skipped (the same bits), counted as the visit it
  // repeats. scratch_.velocity_version[i] counts the visits that changed awake body
  // i (an immovable side's velocity never changes: version 0).
  scratch_.velocity_version.assign(bodies_.size(), {});
  auto version = [&](int idx) { return awake(idx) ? scratch_.velocity_version[static_cast<std::size_t>(idx)].n : 0u; };
  const bool skip_converged = oriented && P_.converged_speed > T{};  // eq 113
  scratch_.idle_visits.assign(visits.size(), IdleVisit{});
  // One visit of pass `it`; its counts go to `total` (one per part of a
  // parallel region, summed after: integers, in any order).
  auto visit_at = [&](std::size_t at, int it, SolveCounts& total) {
    const std::pair<std::size_t, std::size_t>& visit = visits[at];
    const std::size_t s = visit.first, e = visit.second;  // (not a structured binding: lambdas capture s)
    const bool manifold = contacts_[s].b < 0 || oriented;
    const int ia = contacts_[s].a, ib = contacts_[s].b;
    const unsigned version_a = version(ia), version_b = version(ib);
    IdleVisit& idle = scratch_.idle_visits[at];
    // eq 113 (oriented-box model, converged_speed > 0): from pass
    // converged_pass on, a visit that last changed its sides' velocities
    // by less than converged_speed with no step of eq 99 shortened below
    // 1/2, and whose sides have moved by less than that since, is
    // converged and skipped (it would apply almost nothing again). Checked
    // before the idle skip, as the GPU engine (which has none) does.
    if (skip_converged && it >= P_.converged_pass && idle.small) {
      const BodyView<T> A = solver::view_of(bodies_, ia), B = solver::view_of(bodies_, ib);
      if (visit_converged(idle.va, idle.wa, A.v, A.w, P_.converged_speed) &&
          visit_converged(idle.vb, idle.wb, B.v, B.w, P_.converged_speed))
        return;
    }
    if (idle.idle && idle.version_a == version_a && idle.version_b == version_b) {
      total.solver_contacts += idle.solver_contacts;  // the visit it repeats: no impulse
      return;
    }
    BodyView<T> A = solver::view_of(bodies_, ia);
    BodyView<T> B = solver::view_of(bodies_, ib);
    const Vec3<T> va0 = A.v, wa0 = A.w, vb0 = B.v, wb0 = B.w;
    SolveCounts counts;
    if (manifold) {
      const auto points = static_cast<int>(e - s);  // <= kManifoldPoints by construction (narrow_phase)
      auto point = [&](int k, Vec3<T>& r1, Vec3<T>& r2, Vec3<T>& n, T& penetration) {
        if (k >= points) return false;
        const Contact<T>& c = contacts_[s + static_cast<std::size_t>(k)];
        r1 = c.r1;
        r2 = c.r2;
        n = c.n;
        penetration = c.penetration;
        return true;
      };
      auto load = [&](int k) { return contacts_[s + static_cast<std::size_t>(k)].state; };
      auto store = [&](int k, const ContactState<T>& st) { contacts_[s + static_cast<std::size_t>(k)].state = st; };
      auto row = [&](int k) -> const ContactRows<T>& { return contacts_[s + static_cast<std::size_t>(k)].row; };
      // B immovable (the ground, an SDF volume, a body asleep: immovable_view):
      // its terms are exact zeros, left out in an exact number type (kStillSide).
      auto solve = [&](auto immovable_b) {
        solve_manifold_rows<solver::kManifoldPoints, false, decltype(immovable_b)::value>(
            A, B, point, row, load, store, fx.friction, fx.gravity, one, P_, counts, &scratch_.visit_split[at]);
      };
      if (ib < 0 || !awake(ib)) solve(std::true_type{});
      else solve(std::false_type{});
    } else {
      Contact<T>& c = contacts_[s];
      solve_contact(A, c.r1, B, c.r2, c.n, c.penetration, c.state, fx.friction, fx.gravity, one, P_, counts, &c.row);
    }
    total.solver_contacts += counts.solver_contacts;
    total.normal_impulses += counts.normal_impulses;
    total.friction_steps += counts.friction_steps;
    if (A.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(ia)]; b.v = A.v; b.w = A.w; }
    if (B.inv_mass > T{}) { Body<T>& b = bodies_[static_cast<std::size_t>(ib)]; b.v = B.v; b.w = B.w; }
    check_faults(ia, ib >= 0 ? "contact impulse (with another body)" : "contact impulse");
    idle.idle = counts.normal_impulses == 0 && counts.friction_steps == 0;
    if (!idle.idle) {
      if (awake(ia)) ++scratch_.velocity_version[static_cast<std::size_t>(ia)].n;
      if (awake(ib)) ++scratch_.velocity_version[static_cast<std::size_t>(ib)].n;
    }
    idle.version_a = version(ia);
    idle.version_b = version(ib);
    idle.solver_contacts = counts.solver_contacts;
    if (!skip_converged) return;  // eq 113 off (the default): no record is kept
    idle.small = counts.shortened_steps == 0 &&  // a shortened step (eq 99) made partial progress
                 visit_converged(va0, wa0, A.v, A.w, P_.converged_speed) &&
                 visit_converged(vb0, wb0, B.v, B.w, P_.converged_speed);
    idle.va = A.v;
    idle.wa = A.w;
    idle.vb = B.v;
    idle.wb = B.w;
  };
  // Step 1 of a pass: each awake body's own visits, in order (backwards on
  // odd passes of the oriented-box model); bodies are independent.
  auto own_visits = [&](int it, bool reverse) {
    region(scratch_.visit_bodies.size(), solver::kVisitGrain, [&](std::size_t b, SolveCounts& total) {
      const int lo = scratch_.body_visit_begin[b], hi = scratch_.body_visit_begin[b + 1];
      if (!reverse)
        for (int k = lo; k < hi; ++k) visit_at(static_cast<std::size_t>(scratch_.body_visits[static_cast<std::size_t>(k)]), it, total);
      else
        for (int k = hi; k-- > lo;) visit_at(static_cast<std::size_t>(scratch_.body_visits[static_cast<std::size_t>(k)]), it, total);
    });
  };
  // Step 2: colour c's edges, no two sharing a body.
  auto colour = [&](int it, int c) {
    const int lo = scratch_.colour_begin[static_cast<std::size_t>(c)], hi = scratch_.colour_begin[static_cast<std::size_t>(c) + 1];
    region(static_cast<std::size_t>(hi - lo), solver::kVisitGrain, [&](std::size_t k, SolveCounts& total) {
      visit_at(static_cast<std::size_t>(scratch_.colour_visits[static_cast<std::size_t>(lo) + k]), it, total);
    });
  };
  // 7.2 step 5 (oriented-box model): even passes go forwards, odd passes
  // backwards (symmetric Gauss-Seidel), so an impact on top of a stack
  // reaches the ground within one pass and the ground's answer climbs back
  // in the next. The source's AABB model: every pass forwards.
  // On several threads (7.7 "Threads"), when the visits are many: each
  // awake body's visits form one chain through the passes, and the parts run
  // them without a barrier per step (solve_schedule.hpp), the same bits.
#if !defined(LOCKSTEP_NO_THREADS)
  const std::size_t visit_count = scratch_.body_visits.size() + scratch_.colour_visits.size();
  const int parts = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(workers_.threads), visit_count / solver::kPartVisits));
  if (parts > 1) {
    PassPlan plan;  // (a few vectors per frame: microseconds beside the passes)
    // The forward pass (eqs 125-127): the bodies' own visits, then the edges colour by colour.
    plan.order.assign(scratch_.body_visits.begin(), scratch_.body_visits.end());
    plan.order.insert(plan.order.end(), scratch_.colour_visits.begin(), scratch_.colour_visits.end());
    plan.body.assign(visits.size(), {-1, -1});
    for (int v : plan.order) {
      const Contact<T>& c = contacts_[visits[static_cast<std::size_t>(v)].first];
      plan.body[static_cast<std::size_t>(v)] = {awake(c.a) ? c.a : -1, awake(c.b) ? c.b : -1};
    }
    plan.rank_visits(visits.size(), bodies_.size());
    plan.cut(
        parts, bodies_.size(),
        [&](int v) { return static_cast<std::int64_t>(visits[static_cast<std::size_t>(v)].second - visits[static_cast<std::size_t>(v)].first); },
        [&](int a, int b) {
          const T xa = bodies_[static_cast<std::size_t>(a)].p.x, xb = bodies_[static_cast<std::size_t>(b)].p.x;
          return xa < xb || (xa == xb && a < b);
        });
    if (!workers_.pool) workers_.pool = std::make_shared<ThreadPool>(workers_.threads);
    for (PartCounts& c : part_counts) c = PartCounts{};
    run_passes(
        *workers_.pool, plan, P_.solver_iterations, oriented,
        [&](std::size_t v, int it, int part) { visit_at(v, it, part_counts[static_cast<std::size_t>(part)]); },
        [](int part) {
          if (part != 0) Num<T>::take_faults();  // a worker's faults: none left from an earlier region
        });
    for (const SolveCounts& c : part_counts) tally(c);
  } else
#endif
  {
    for (int it = 0; it < P_.solver_iterations; ++it) {
      const bool reverse = oriented && (it & 1) != 0;
      if (!reverse) {
        own_visits(it, false);
        for (int c = 0; c < colours; ++c) colour(it, c);
      } else {
        for (int c = colours; c-- > 0;) colour(it, c);
        own_visits(it, true);
      }
    }
  }
  // The cache (eq 96), sorted by (a, b, feature) (a unique key): each
  // body's entries (its contacts as side a with j_n > 0, from its list of
  // contacts) formed and sorted on their own, placed by a running sum of
  // their counts, so in body order.
  auto by_key = [](const CachedImpulse& x, const CachedImpulse& y) {
    return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.feature < y.feature);
  };
  auto cached = [&](std::size_t i, int k) {
    const Contact<T>& c = contacts_[static_cast<std::size_t>(scratch_.body_contacts[static_cast<std::size_t>(k)])];
    return c.a == static_cast<int>(i) && c.state.j_n > T{};
  };
  std::vector<int>& first = scratch_.warm_first;
  first.assign(bodies_.size() + 1, 0);
  parallel_each(bodies_.size(), 64, [&](std::size_t i, int) {
    for (int k = scratch_.body_contact_begin[i]; k < scratch_.body_contact_begin[i + 1]; ++k) first[i + 1] += cached(i, k) ? 1 : 0;
  });
  for (std::size_t i = 0; i < bodies_.size(); ++i) first[i + 1] += first[i];
  warm_.resize(static_cast<std::size_t>(first.back()));
  parallel_each(bodies_.size(), 64, [&](std::size_t i, int) {
    auto at = warm_.begin() + first[i];
    for (int k = scratch_.body_contact_begin[i]; k < scratch_.body_contact_begin[i + 1]; ++k) {
      if (!cached(i, k)) continue;
      const Contact<T>& c = contacts_[static_cast<std::size_t>(scratch_.body_contacts[static_cast<std::size_t>(k)])];
      *at++ = {c.a, c.b, c.feature, c.state.j_n};
    }
    std::sort(warm_.begin() + first[i], at, by_key);
  });
}

template <class T>
void World<T>::correct_positions() {
  scratch_.corrected_from.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) scratch_.corrected_from[i] = bodies_[i].p;
  // One correction (eqs 63, 89) of contact c, its penetration less what this
  // stage has already moved its two sides apart along n. A bouncing contact
  // (e_eff > 0, eq 76) is not corrected: its rebound separates it, and pushing
  // it out as well adds m g penetration of energy per bounce, which kept a
  // cube bouncing at 0.6 m/s for ever. `lower_fixed`: eq 110's support pair,
  // whose lower side does not move unless the upper one cannot.
  // A ground point that bounces is not corrected, unless another of the
  // body's ground points is as deep and does not bounce (eq 89's tie rule:
  // which tied corner is "first" depends on the corner numbering, which a
  // mirror image permutes; this keeps the choice sign-symmetric).
  auto tied_point_rests = [&](const Contact<T>& c) {
    if (c.b != -1) return false;
    std::size_t lo = static_cast<std::size_t>(&c - contacts_.data()), hi = lo + 1;
    while (lo > 0 && contacts_[lo - 1].a == c.a && contacts_[lo - 1].b == -1) --lo;
    while (hi < contacts_.size() && contacts_[hi].a == c.a && contacts_[hi].b == -1) ++hi;
    auto bounces = [&](int m) { return contacts_[lo + static_cast<std::size_t>(m)].state.e > T{}; };
    auto point = [&](int m, T& depth) {
      depth = contacts_[lo + static_cast<std::size_t>(m)].penetration;
      return true;
    };
    T depth{};
    const int k = ground_correction_point(static_cast<int>(hi - lo), point, bounces, depth);  // eq 89
    return k >= 0 && !bounces(k);
  };
  // Returns whether it corrected (counted by the caller).
  auto correct = [&](const Contact<T>& c, bool lower_fixed) {
    if (!c.corrects || (c.state.e > T{} && !tied_point_rests(c))) return false;
    Body<T>& A = bodies_[static_cast<std::size_t>(c.a)];
    T inv_a = A.awake() ? A.inv_mass : T{};
    Vec3<T> ground_p;
    Body<T>* B = c.b >= 0 ? &bodies_[static_cast<std::size_t>(c.b)] : nullptr;
    T inv_b = (B != nullptr && B->awake()) ? B->inv_mass : T{};
    if (inv_a == T{} && inv_b == T{}) return false;
    if (B != nullptr && scratch_.oriented_correction) {  // eq 110 (physics/contact.hpp, shared with the GPU engine)
      manifold_correction(A.p, scratch_.corrected_from[static_cast<std::size_t>(c.a)], B->p,
                          scratch_.corrected_from[static_cast<std::size_t>(c.b)], c.n, c.correct_depth, inv_a, inv_b,
                          lower_fixed, P_.slop, P_.baumgarte);
      check_faults(c.a, "position correction");
      return true;
    }
    Vec3<T>& pb = B != nullptr ? B->p : ground_p;
    Vec3<T> moved = A.p - scratch_.corrected_from[static_cast<std::size_t>(c.a)];
    if (B != nullptr) moved -= B->p - scratch_.corrected_from[static_cast<std::size_t>(c.b)];
    const T pen = B != nullptr ? c.penetration : c.penetration - dot(moved, c.n);  // pairs: the AABB model's eq 89
    baumgarte_correction(A.p, pb, c.n, pen, inv_a, inv_b, P_.slop, P_.baumgarte);  // eqs 63, 89
    check_faults(c.a, "position correction");
    return true;
  };
  if (scene_.pair_contacts == PairModel::kAabb) {
    // eq 89's order: body pairs first, in contact order; then the contacts with
    // the immovable world (ground, SDF, each body's deepest one), each with its
    // penetration less what the pairs already moved the body along its normal.
    // The world has the last word: a light body under a heavy one is not left
    // pushed into the ground by the pair's share of the correction.
    scratch_.oriented_correction = false;
    for (int pass = 0; pass < 2; ++pass)
      for (const Contact<T>& c : contacts_)
        if ((c.b >= 0) == (pass == 0) && correct(c, false)) ++counters_.corrections;
    return;
  }
  // eq 110 (oriented-box model): the world first (ground and SDF contacts, in
  // contact order), then the body pairs, each by the mean depth of its
  // points (correct_depth), from the bottom up: in ascending
  // (y of the lower side before this stage, contact index) order. A support
  // pair (|n.y| >= support_normal_min) moves only its upper side, by the
  // whole correction, so a stack is set right in one pass from the ground up
  // (with the mass split of eq 89 each pair pushed the cube under it down
  // again, and 20-high columns ended 8 mm deep at every contact); other
  // pairs split by inverse mass as eq 89.
  scratch_.oriented_correction = true;
  scratch_.order.clear();
  for (std::size_t ci = 0; ci < contacts_.size(); ++ci) {
    const Contact<T>& c = contacts_[ci];
    if (c.b < 0) {
      if (correct(c, false)) ++counters_.corrections;
      continue;
    }
    if (c.corrects) scratch_.order.push_back(static_cast<int>(ci));
  }
  std::vector<std::pair<T, int>>& keys = scratch_.order_keys;  // (the lower side's y, the contact)
  keys.clear();
  for (const int ci : scratch_.order) {
    const Contact<T>& c = contacts_[static_cast<std::size_t>(ci)];
    const T ya = scratch_.corrected_from[static_cast<std::size_t>(c.a)].y, yb = scratch_.corrected_from[static_cast<std::size_t>(c.b)].y;
    keys.emplace_back(Num<T>::min(ya, yb), ci);
  }
  std::sort(keys.begin(), keys.end(), [](const std::pair<T, int>& x, const std::pair<T, int>& y) {
    return settles_before(x.first, x.second, y.first, y.second);
  });
  for (std::size_t k = 0; k < keys.size(); ++k) scratch_.order[k] = keys[k].second;
  // Eq 110 over the pairs in this order, then eq 111 over them again. A
  // pair touches its two bodies alone (their positions and eq 111's turns),
  // so the bodies joined by pairs (asleep and static ones included) form
  // groups that run on the world's threads, each in this order: the serial
  // sweep's bits.
  const std::size_t m = scratch_.order.size();
  if (m == 0) return;
  scratch_.turn.assign(bodies_.size(), Vec3<T>{});
  std::vector<char>& corrected = scratch_.pair_corrected;
  corrected.assign(m, 0);
  auto pair_at = [&](std::size_t k) -> const Contact<T>& { return contacts_[static_cast<std::size_t>(scratch_.order[k % m])]; };
  items_by_groups(2 * m, [&](std::size_t k) { return std::array<int, 2>{pair_at(k).a, pair_at(k).b}; }, [&](std::size_t k) {
    const Contact<T>& c = pair_at(k);
    if (k < m) {  // eq 110
      corrected[k] = correct(c, is_support_pair(c.n, P_.support_normal_min)) ? 1 : 0;
      return;
    }
    // eq 111: every point of the pair pushed out of what it still
    // penetrates by turning as well as moving its sides.
    const std::size_t ci = static_cast<std::size_t>(&c - contacts_.data());
    const auto ia = static_cast<std::size_t>(c.a), ib = static_cast<std::size_t>(c.b);
    Body<T>& A = bodies_[ia];
    Body<T>& B = bodies_[ib];
    BodyView<T> va{A.p - scratch_.corrected_from[ia], scratch_.turn[ia], A.awake() ? A.inv_mass : T{}, A.R, A.awake() ? A.inv_inertia : Vec3<T>{}};
    BodyView<T> vb{B.p - scratch_.corrected_from[ib], scratch_.turn[ib], B.awake() ? B.inv_mass : T{}, B.R, B.awake() ? B.inv_inertia : Vec3<T>{}};
    if (va.inv_mass == T{} && vb.inv_mass == T{}) return;
    hold_lower_side(va, vb, c.n, P_.support_normal_min);  // eq 111: only the upper side moves, if it can
    std::size_t lo = ci, hi = lo + 1;
    while (lo > 0 && contacts_[lo - 1].a == c.a && contacts_[lo - 1].b == c.b) --lo;
    while (hi < contacts_.size() && contacts_[hi].a == c.a && contacts_[hi].b == c.b) ++hi;
    for (std::size_t j = lo; j < hi; ++j) {
      const Contact<T>& p = contacts_[j];
      if (p.state.e > T{}) continue;  // a bouncing point separates by its rebound (eq 89)
      correct_manifold_point(va, p.r1, vb, p.r2, p.n, p.penetration, P_.slop, P_.baumgarte);  // eq 111
    }
    A.p = scratch_.corrected_from[ia] + va.v;
    B.p = scratch_.corrected_from[ib] + vb.v;
    scratch_.turn[ia] = va.w;
    scratch_.turn[ib] = vb.w;
    check_faults(c.a, "position correction");
  });
  for (const char x : corrected) counters_.corrections += static_cast<unsigned char>(x);
  const T half = Num<T>::from_double(0.5);
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (!(scratch_.turn[i] == Vec3<T>{})) bodies_[i].q = integrate_orientation(bodies_[i].q, scratch_.turn[i], half);  // eqs 7-10, a turn
}

}  // namespace lockstep
