// The solver's passes on several threads without a barrier per step
// (docs/SPEC.md 7.7 "Threads", eqs 125-127). A pass visits the awake bodies'
// own visits, then the edges colour by colour; within a step no two visits
// touch the same awake body, so what a visit reads (its sides' velocities,
// its own contacts and records) is fixed by the visits of its two bodies
// that come before it in the serial order. Each awake body's visits
// therefore form one chain through all the passes, and any execution that
// runs every chain in order gives the serial order's bits: a visit runs once
// each of its bodies has seen the visits before it (a count per body, its
// ticket), with no barrier between the steps.
//
// Each part (thread) runs its visits in the serial order; every visit it
// waits for comes before its own in that order, so the first unfinished
// visit can always run (no deadlock). A RunError stops a part at that
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

namespace lockstep {

// The forward pass of eqs 125-127 as the parts run it.
struct PassPlan {
  std::vector<int> order;                // the forward pass's visits, in the serial order
  std::vector<int> pos;                  // per visit: its place in `order`
  std::vector<std::array<int, 2>> body;  // per visit: the awake bodies it changes (-1: none)
  std::vector<std::array<int, 2>> rank;  // per visit and side: how many of that body's visits come before it in a forward pass
  std::vector<int> count;                // per body: its visits in one pass
  std::vector<std::vector<int>> part;    // per part: its visits, in the forward order

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
  // passes x its visits, far fewer), plus kFailure for each part that failed.
  constexpr int kCountMask = (1 << 20) - 1, kFailure = 1 << 20;
  constexpr int kSpins = 256;  // pauses (about 40 ns each) before a waiting part blocks: a visit takes 0.2-1 us
  const std::unique_ptr<std::atomic<int>[]> done(new std::atomic<int>[plan.count.size()]());
  constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::max();
  std::atomic<std::int64_t> first_failed{kNone};  // the lowest place (pass * V + place) of a RunError
  std::vector<std::int64_t> failed(static_cast<std::size_t>(parts), kNone);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(parts));
  pool.run(parts, [&](int p) {
    begin_part(p);
    const std::vector<int>& list = plan.part[static_cast<std::size_t>(p)];
    const std::size_t n = list.size();
    for (int it = 0; it < passes; ++it) {
      const bool back = alternate && (it & 1) != 0;
      for (std::size_t k = 0; k < n; ++k) {
        const auto v = static_cast<std::size_t>(list[back ? n - 1 - k : k]);
        const std::int64_t place = std::int64_t{it} * V + (back ? V - 1 - plan.pos[v] : plan.pos[v]);
        int need[2] = {-1, -1};
        for (std::size_t s = 0; s < 2; ++s) {
          const int b = plan.body[v][s];
          if (b < 0) continue;
          const int c = plan.count[static_cast<std::size_t>(b)], r = plan.rank[v][s];
          need[s] = it * c + (back ? c - 1 - r : r);  // the body's visits before this one
          std::atomic<int>& d = done[static_cast<std::size_t>(b)];
          for (int spins = 0;; ++spins) {
            const int now = d.load(std::memory_order_acquire);
            if ((now & kCountMask) >= need[s]) break;
            if (place > first_failed.load(std::memory_order_relaxed)) return;
            if (spins < kSpins) spin_pause();
            else d.wait(now, std::memory_order_acquire);  // (more threads than cores: block, do not spin)
          }
        }
        if (place > first_failed.load(std::memory_order_relaxed)) return;
        try {
          visit(v, it, p);
        } catch (const RunError&) {
          failed[static_cast<std::size_t>(p)] = place;
          errors[static_cast<std::size_t>(p)] = std::current_exception();
          std::int64_t low = first_failed.load(std::memory_order_relaxed);
          while (place < low && !first_failed.compare_exchange_weak(low, place, std::memory_order_relaxed)) {
          }
          // Wake every waiting part to look at first_failed again (a change
          // above the counts' bits; those past it stop, the others wait on).
          for (std::size_t b = 0; b < plan.count.size(); ++b) {
            done[b].fetch_add(kFailure, std::memory_order_release);
            done[b].notify_all();
          }
          return;
        }
        for (std::size_t s = 0; s < 2; ++s) {
          if (need[s] < 0) continue;
          std::atomic<int>& d = done[static_cast<std::size_t>(plan.body[v][s])];
          d.fetch_add(1, std::memory_order_release);  // this visit held the body's count: need -> need + 1
          d.notify_all();
        }
      }
    }
  });
  int first = -1;
  for (int p = 0; p < parts; ++p)
    if (errors[static_cast<std::size_t>(p)] && (first < 0 || failed[static_cast<std::size_t>(p)] < failed[static_cast<std::size_t>(first)])) first = p;
  if (first >= 0) std::rethrow_exception(errors[static_cast<std::size_t>(first)]);
}
#endif

}  // namespace lockstep
