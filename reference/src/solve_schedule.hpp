// The solver's passes on several threads without a barrier per step
// (docs/SPEC.md 7.7 "Threads", eqs 125-127). A pass visits the awake bodies'
// own visits, then the edges colour by colour; within a step no two visits
// touch the same awake body, so what a visit reads (its sides' velocities,
// its own contacts and records) is fixed by the visits of its two bodies
// that come before it in the serial order. Each awake body's visits
// therefore form one chain through all the passes, and any execution that
// runs every chain in order gives the serial order's bits.
//
// Two kinds of work, both in that order:
// - An island (the awake bodies joined by edges, with their visits) that one
//   part holds whole shares no body with any other visit: the part runs all
//   its passes in a row, with no waiting at all; a part that has run out of
//   islands takes one another part has not started (stealing never changes
//   bits, only which thread runs a whole island).
// - An island cut between parts (a pile whose every cube touches another)
//   runs as chains: each part runs its visits of it in the serial order, and
//   a visit runs once each of its bodies has seen the visits before it (a
//   count per body, its ticket), with no barrier between the steps. Every
//   visit a part waits for comes before its own in that order, so the first
//   unfinished visit can always run (no deadlock). The parts run their cut
//   islands first, then their whole ones.
//
// A RunError stops a part's run of that island (or of its chains) at that
// visit; the other parts run on up to it (what they wait for comes before
// it), so the error rethrown is the one a single thread meets first.
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <vector>

#include "lockstep/world.hpp"
#include "thread_pool.hpp"
#include "union_find.hpp"

namespace lockstep {

// The forward pass of eqs 125-127 as the parts run it.
struct PassPlan {
  std::vector<int> order;                // the forward pass's visits, in the serial order
  std::vector<int> pos;                  // per visit: its place in `order`
  std::vector<std::array<int, 2>> body;  // per visit: the awake bodies it changes (-1: none)
  std::vector<std::array<int, 2>> rank;  // per visit and side: how many of that body's visits come before it in a forward pass
  std::vector<int> count;                // per body: its visits in one pass
  std::vector<std::vector<int>> part;    // per part: its visits of cut islands (chains), in the forward order
  std::vector<std::vector<int>> island;  // the whole islands: each one's visits, in the forward order
  std::vector<std::vector<int>> part_islands;  // per part: the whole islands it runs first (indices into `island`)

  // `order` and `body` given, and `visit_points(v)` the contact points of
  // visit v: the parts. The islands (awake bodies joined by edges) are taken
  // heaviest first (contact points; ties: lowest body). One heavier than a
  // part's share (a pile whose every cube touches another) is cut: its
  // bodies ordered by `before` (World<T>: x, then index: neighbours in space
  // share few edges) and cut into `parts` runs of about equal contact
  // points, a visit going to the part of its first awake body (its chains).
  // Every other island goes whole to the part with the fewest contact points
  // so far (ties: the lowest part). (Which part runs a visit never changes
  // its bits, only how long the parts wait.)
  template <class Points, class Before>
  void cut(int parts, std::size_t bodies, const Points& visit_points, const Before& before) {
    // The islands: union-find over the edges (both sides awake), the larger root joining the smaller.
    std::vector<int> root(bodies, -1);  // -1: not (yet) a member
    auto find = [&](int b) { return union_find_root(root, b); };
    std::vector<int> members;  // the awake bodies that have visits
    std::vector<std::int64_t> weight(bodies, 0);  // per body: the contact points of the visits it is the first side of
    for (int v : order) {
      const std::array<int, 2>& b = body[static_cast<std::size_t>(v)];
      for (int s : b)
        if (s >= 0 && root[static_cast<std::size_t>(s)] < 0) {
          root[static_cast<std::size_t>(s)] = s;
          members.push_back(s);
        }
      weight[static_cast<std::size_t>(b[0] >= 0 ? b[0] : b[1])] += visit_points(v);
      if (b[0] >= 0 && b[1] >= 0) union_find_join(root, b[0], b[1]);
    }
    // The islands, each with its weight (its bodies' contact points) and
    // its members; taken heaviest first (ties: lowest root, its lowest body).
    std::vector<int> island_at(bodies, -1);  // per root: its island's place in `roots`
    std::vector<int> roots;
    std::vector<std::int64_t> island_weight;
    std::vector<int> member_island(members.size());
    std::int64_t total = 0;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const int r = find(members[m]);
      int& at = island_at[static_cast<std::size_t>(r)];
      if (at < 0) {
        at = static_cast<int>(roots.size());
        roots.push_back(r);
        island_weight.push_back(0);
      }
      member_island[m] = at;
      island_weight[static_cast<std::size_t>(at)] += weight[static_cast<std::size_t>(members[m])];
      total += weight[static_cast<std::size_t>(members[m])];
    }
    std::vector<int> by_weight(roots.size());
    for (std::size_t k = 0; k < roots.size(); ++k) by_weight[k] = static_cast<int>(k);
    std::sort(by_weight.begin(), by_weight.end(), [&](int x, int y) {
      const std::int64_t wx = island_weight[static_cast<std::size_t>(x)], wy = island_weight[static_cast<std::size_t>(y)];
      return wx != wy ? wx > wy : roots[static_cast<std::size_t>(x)] < roots[static_cast<std::size_t>(y)];
    });
    std::vector<int> owner(bodies, -1);   // per body of a cut island: its part
    std::vector<int> island_of(bodies, -1);  // per root of a whole island: its index in `island`
    std::vector<std::int64_t> load(static_cast<std::size_t>(parts), 0);
    std::vector<int> cut_members;
    island.clear();
    part.assign(static_cast<std::size_t>(parts), {});
    part_islands.assign(static_cast<std::size_t>(parts), {});
    for (const int at : by_weight) {
      const int r = roots[static_cast<std::size_t>(at)];
      const std::int64_t w = island_weight[static_cast<std::size_t>(at)];
      if (w * parts > total) {  // cut: its bodies in `before` order, in runs of about equal weight
        cut_members.clear();
        for (std::size_t m = 0; m < members.size(); ++m)
          if (member_island[m] == at) cut_members.push_back(members[m]);
        std::sort(cut_members.begin(), cut_members.end(), before);
        std::int64_t so_far = 0;
        for (const int b : cut_members) {
          const int p = static_cast<int>(std::min<std::int64_t>(parts - 1, so_far * parts / std::max<std::int64_t>(w, 1)));
          owner[static_cast<std::size_t>(b)] = p;
          so_far += weight[static_cast<std::size_t>(b)];
          load[static_cast<std::size_t>(p)] += weight[static_cast<std::size_t>(b)];
        }
      } else {  // whole
        const auto p = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
        load[p] += w;
        island_of[static_cast<std::size_t>(r)] = static_cast<int>(island.size());
        part_islands[p].push_back(static_cast<int>(island.size()));
        island.emplace_back();
      }
    }
    for (int v : order) {
      const std::array<int, 2>& b = body[static_cast<std::size_t>(v)];
      const int first = b[0] >= 0 ? b[0] : b[1];
      const int r = find(first);
      if (island_of[static_cast<std::size_t>(r)] >= 0) island[static_cast<std::size_t>(island_of[static_cast<std::size_t>(r)])].push_back(v);
      else part[static_cast<std::size_t>(owner[static_cast<std::size_t>(first)])].push_back(v);
    }
  }

  // `order` and `body` given: the places, ranks and counts.
  void rank_visits(std::size_t visits, std::size_t bodies) {
    pos.assign(visits, -1);
    rank.assign(visits, {0, 0});
    count.assign(bodies, 0);
    for (std::size_t k = 0; k < order.size(); ++k) {
      const auto v = static_cast<std::size_t>(order[k]);
      pos[v] = static_cast<int>(k);
      for (int s = 0; s < 2; ++s)
        if (body[v][static_cast<std::size_t>(s)] >= 0)
          rank[v][static_cast<std::size_t>(s)] = count[static_cast<std::size_t>(body[v][static_cast<std::size_t>(s)])]++;
    }
  }
};

#if defined(LOCKSTEP_NO_THREADS)
// Builds without threads run the passes on the caller's thread, in order.
inline constexpr bool kPassesOnThreads = false;
#else
inline constexpr bool kPassesOnThreads = true;

// Runs `passes` passes of plan's visits on pool's threads (plan.part.size()
// parts): `visit(v, pass, part)`. Odd passes run backwards when `alternate`
// (eq 125's symmetric Gauss-Seidel). `begin_part(part)` runs first on each part.
template <class Visit, class Begin>
void run_passes(ThreadPool& pool, const PassPlan& plan, int passes, bool alternate, const Visit& visit,
                const Begin& begin_part) {
  const auto parts = static_cast<int>(plan.part.size());
  const auto V = static_cast<std::int64_t>(plan.order.size());
  // Per body: its visits done (the low 20 bits; a body has at most
  // passes x its visits, far fewer), plus kFailure for each part that
  // failed, and how many parts block on it; a cache line each. Packed 16 to
  // a line, the counts of bodies that two parts run side by side (their
  // indices interleave) moved between the cores at every visit, and every
  // visit notified (through libstdc++'s shared table of waiters):
  // pile1000's frames 31-40, one island cut in two, took 0.70x the single
  // thread's time on 2 threads, 1.29x with a line each and a notify only
  // when a part blocks on the count. A waiting part spins, then yields and
  // spins on (blocking cost those frames as much as the lines gained);
  // with more threads than cores it blocks instead (spinning or yielding
  // took the cores from the parts with work).
  constexpr int kCountMask = (1 << 20) - 1, kFailure = 1 << 20;
  constexpr int kSpins = 256;  // pauses (about 40 ns each) before a waiting part blocks: a visit takes 0.2-1 us
  struct alignas(64) Done {
    std::atomic<int> n{0};
    std::atomic<int> blocked{0};
  };
  const std::unique_ptr<Done[]> done(new Done[plan.count.size()]);
  constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::max();
  std::atomic<std::int64_t> first_failed{kNone};  // the lowest place (pass * V + place) of a RunError
  std::vector<std::int64_t> failed(static_cast<std::size_t>(parts), kNone);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(parts));
  // Records a RunError at `place` and wakes every waiting part to look at
  // first_failed again (a change above the counts' bits; those past it
  // stop, the others wait on).
  auto fail = [&](int p, std::int64_t place) {
    failed[static_cast<std::size_t>(p)] = place;
    errors[static_cast<std::size_t>(p)] = std::current_exception();
    std::int64_t low = first_failed.load(std::memory_order_relaxed);
    while (place < low && !first_failed.compare_exchange_weak(low, place, std::memory_order_relaxed)) {
    }
    for (std::size_t b = 0; b < plan.count.size(); ++b) {
      done[b].n.fetch_add(kFailure);
      done[b].n.notify_all();
    }
  };
  auto place_of = [&](std::size_t v, int it, bool back) {
    return std::int64_t{it} * V + (back ? V - 1 - plan.pos[v] : plan.pos[v]);
  };
  // Runs step(v, pass, back, place) over `list`'s visits pass after pass
  // (backwards on odd passes when alternating), in the serial order; a step
  // that returns false ends the list.
  auto each_visit = [&](const std::vector<int>& list, const auto& step) {
    const std::size_t n = list.size();
    for (int it = 0; it < passes; ++it) {
      const bool back = alternate && (it & 1) != 0;
      for (std::size_t k = 0; k < n; ++k) {
        const auto v = static_cast<std::size_t>(list[back ? n - 1 - k : k]);
        if (!step(v, it, back, place_of(v, it, back))) return;
      }
    }
  };
  // Runs visit v, or records its RunError (false).
  auto run_visit = [&](std::size_t v, int it, int p, std::int64_t place) {
    try {
      visit(v, it, p);
      return true;
    } catch (const RunError&) {
      fail(p, place);
      return false;
    }
  };
  // Cut islands: the part's chains, pass after pass.
  auto run_chains = [&](int p) {
    each_visit(plan.part[static_cast<std::size_t>(p)], [&](std::size_t v, int it, bool back, std::int64_t place) {
      int need[2] = {-1, -1};
      for (std::size_t s = 0; s < 2; ++s) {
        const int b = plan.body[v][s];
        if (b < 0) continue;
        const int c = plan.count[static_cast<std::size_t>(b)], r = plan.rank[v][s];
        need[s] = it * c + (back ? c - 1 - r : r);  // the body's visits before this one
        Done& d = done[static_cast<std::size_t>(b)];
        for (int spins = 0;; ++spins) {
          const int now = d.n.load(std::memory_order_acquire);
          if ((now & kCountMask) >= need[s]) break;
          if (place > first_failed.load(std::memory_order_relaxed)) return false;
          if (spins < kSpins) {
            spin_pause();
            continue;
          }
          if (pool.may_spin()) {
            std::this_thread::yield();
            spins = 0;
            continue;
          }
          // Block: announced first, then the count read again (seq_cst
          // both, as the visit's increment and its look at `blocked`: one
          // of the two sees the other), so no increment is missed.
          d.blocked.fetch_add(1);
          const int again = d.n.load();
          if ((again & kCountMask) < need[s] && !(place > first_failed.load(std::memory_order_relaxed))) d.n.wait(again);
          d.blocked.fetch_sub(1);
        }
      }
      if (place > first_failed.load(std::memory_order_relaxed) || !run_visit(v, it, p, place)) return false;
      for (std::size_t s = 0; s < 2; ++s) {
        if (need[s] < 0) continue;
        Done& d = done[static_cast<std::size_t>(plan.body[v][s])];
        d.n.fetch_add(1);  // this visit held the body's count: need -> need + 1
        if (d.blocked.load() != 0) d.n.notify_all();
      }
      return true;
    });
  };
  // A whole island: all its passes in a row. Its visits' places rise in
  // this order, so one past first_failed ends the island.
  const std::unique_ptr<std::atomic<bool>[]> taken(new std::atomic<bool>[plan.island.size()]());
  auto run_island = [&](int p, std::size_t i) {
    if (taken[i].exchange(true, std::memory_order_relaxed)) return;  // another part runs it
    each_visit(plan.island[i], [&](std::size_t v, int it, bool, std::int64_t place) {
      return place <= first_failed.load(std::memory_order_relaxed) && run_visit(v, it, p, place);
    });
  };
  pool.run(parts, [&](int p) {
    begin_part(p);
    run_chains(p);
    for (int i : plan.part_islands[static_cast<std::size_t>(p)]) run_island(p, static_cast<std::size_t>(i));
    // Then the islands other parts have not started, from the ends of their lists.
    for (int q = 1; q < parts; ++q) {
      const std::vector<int>& other = plan.part_islands[static_cast<std::size_t>((p + q) % parts)];
      for (std::size_t k = other.size(); k-- > 0;) run_island(p, static_cast<std::size_t>(other[k]));
    }
  });
  int first = -1;
  for (int p = 0; p < parts; ++p)
    if (errors[static_cast<std::size_t>(p)] && (first < 0 || failed[static_cast<std::size_t>(p)] < failed[static_cast<std::size_t>(first)])) first = p;
  if (first >= 0) std::rethrow_exception(errors[static_cast<std::size_t>(first)]);
}
#endif

}  // namespace lockstep
