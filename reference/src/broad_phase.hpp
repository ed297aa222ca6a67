// Stage 2 of docs/SPEC.md 7.2: the uniform grid (6.1, eqs 25-26, 82-83).
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "lockstep/physics/aabb.hpp"
#include "lockstep/physics/box_box.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

namespace broadphase {
// A body covering more cells than this is tested against every body instead of
// being inserted into each cell (a 50 m box in 4 m cells covers 27^3 cells).
inline constexpr std::int64_t kMaxCellsPerBody = 512;
// Cell coordinates packed into one sortable key (|c| < 2^20 on every axis:
// |p| < 32768 m and cell_size >= 0.25 m).
inline std::uint64_t cell_key(int x, int y, int z) {
  auto u = [](int c) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(c) + (1 << 20)); };
  return (u(x) << 42) | (u(y) << 21) | u(z);
}
}  // namespace broadphase

template <class T>
void World<T>::broad_phase() {
  using namespace broadphase;
  pairs_.clear();
  const std::size_t n = bodies_.size();
  // Every awake body's growth: half the contact tolerance (eq 97) and, with
  // the oriented-box pair model, its speculative reach (eq 107). The
  // narrowphase grows the pair test and the ground and SDF tolerances by it.
  const T half_tol = P_.contact_tolerance * Num<T>::from_double(0.5);
  const bool oriented = scene_.pair_contacts == PairModel::kOrientedBox;
  // eq 125: the solver's height bands, from the largest AABB half extent of
  // the bodies awake now (after eq 108's wake; not those eq 81 wakes later).
  T largest{};
  grow_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Body<T>& b = bodies_[i];
    grow_[i] = oriented && b.awake() ? half_tol + speculative_reach(b.v, b.w, b.half, P_.dt) : half_tol;  // eq 107
    if (b.awake()) largest = Num<T>::max(largest, Num<T>::max(b.aabb_half.x, Num<T>::max(b.aabb_half.y, b.aabb_half.z)));
  }
  scratch_.band_inv = band_inverse(largest);
  if (!scene_.effects.contacts || n < 2) return;
  // A pair needs an awake side (maybe_pair): with every body asleep or static
  // there is none, and the grid is not built (a pile at rest costs nothing here).
  bool any_awake = false;
  for (const Body<T>& b : bodies_) any_awake = any_awake || b.awake();
  if (!any_awake) {
    counters_.broadphase_bodies += n;
    return;
  }
  // Boxes grown by grow_ (eqs 97, 107), as the narrowphase grows them.
  // The grid's buffers are kept from frame to frame (the parts' lists below are a few allocations a frame).
  BroadScratch& g = scratch_.broad;
  g.cmin.resize(n);
  g.cmax.resize(n);
  g.min_x.resize(n);
  g.max_x.resize(n);
  g.entries.clear();
  g.large.clear();
  std::vector<BroadCell>& cmin = g.cmin;
  std::vector<BroadCell>& cmax = g.cmax;
  std::vector<T>& min_x = g.min_x;
  std::vector<T>& max_x = g.max_x;
  using Entry = BroadEntry;
  std::vector<Entry>& entries = g.entries;
  std::vector<int>& large = g.large;
  // Each body's grown box and cells (eqs 29-30, 26), the bodies in parallel
  // on the world's threads; each part lists its bodies' cell entries.
  const int parts = std::max(1, workers_.threads);
  std::vector<std::vector<Entry>>& part_entries = g.part_entries;
  part_entries.resize(static_cast<std::size_t>(parts));
  for (std::vector<Entry>& pe : part_entries) pe.clear();
  std::vector<std::int64_t> cell_count(n);
  parallel_for(n, 64, [&](std::size_t i, int part) {
    const Body<T>& b = bodies_[i];
    const Vec3<T> grow{grow_[i], grow_[i], grow_[i]};
    const Vec3<T> lo = b.p - (b.aabb_half + grow), hi = b.p + (b.aabb_half + grow);  // eqs 29-30
    cmin[i] = {cell_coord(lo.x, P_.inv_cell_size), cell_coord(lo.y, P_.inv_cell_size), cell_coord(lo.z, P_.inv_cell_size)};
    cmax[i] = {cell_coord(hi.x, P_.inv_cell_size), cell_coord(hi.y, P_.inv_cell_size), cell_coord(hi.z, P_.inv_cell_size)};
    min_x[i] = lo.x;
    max_x[i] = hi.x;
    const std::int64_t cells = std::int64_t{cmax[i].x - cmin[i].x + 1} * (cmax[i].y - cmin[i].y + 1) * (cmax[i].z - cmin[i].z + 1);
    cell_count[i] = cells;
    check_faults(static_cast<int>(i), "broad phase (grown box)");
    if (cells > kMaxCellsPerBody) return;
    std::vector<Entry>& out = part_entries[static_cast<std::size_t>(part)];
    for (int x = cmin[i].x; x <= cmax[i].x; ++x)
      for (int y = cmin[i].y; y <= cmax[i].y; ++y)
        for (int z = cmin[i].z; z <= cmax[i].z; ++z) out.push_back({cell_key(x, y, z), static_cast<int>(i)});
  });
  counters_.broadphase_bodies += n;
  for (std::size_t i = 0; i < n; ++i)
    if (cell_count[i] > kMaxCellsPerBody) large.push_back(static_cast<int>(i));
  // Fixed order: by cell, then by body index (keys are unique, so any correct
  // sort agrees): each part's entries sorted in parallel, then merged.
  auto by_cell = [](const Entry& a, const Entry& b) { return a.key != b.key ? a.key < b.key : a.body < b.body; };
  // (parallel_for's cut: the parts that hold entries)
  const std::size_t filled = std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(parts), n / 64));
  parallel_for(filled, 1, [&](std::size_t part, int) {
    std::vector<Entry>& pe = part_entries[part];
    std::sort(pe.begin(), pe.end(), by_cell);
  });
  for (const std::vector<Entry>& pe : part_entries) {
    const auto mid = static_cast<std::ptrdiff_t>(entries.size());
    entries.insert(entries.end(), pe.begin(), pe.end());
    std::inplace_merge(entries.begin(), entries.begin() + mid, entries.end(), by_cell);
  }
  auto maybe_pair = [&](int i, int j, std::vector<std::pair<int, int>>& out) {
    const Body<T>& a = bodies_[static_cast<std::size_t>(i)];
    const Body<T>& b = bodies_[static_cast<std::size_t>(j)];
    if (!a.awake() && !b.awake()) return;
    const T ga = grow_[static_cast<std::size_t>(i)], gb = grow_[static_cast<std::size_t>(j)];
    for (int ax = 1; ax < 3; ++ax)  // x was checked by the sweep
      if (a.p[ax] + (a.aabb_half[ax] + ga) < b.p[ax] - (b.aabb_half[ax] + gb) ||
          b.p[ax] + (b.aabb_half[ax] + gb) < a.p[ax] - (a.aabb_half[ax] + ga)) return;
    out.emplace_back(std::min(i, j), std::max(i, j));
  };
  // The cells swept in parallel: the entries cut into `parts` ranges at cell
  // boundaries, each part's pairs in its own list (pairs_ is sorted at the end).
  const std::size_t sweeps = std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(parts), entries.size() / 256));
  std::vector<std::vector<std::pair<int, int>>>& part_pairs = g.part_pairs;
  std::vector<std::vector<int>>& part_members = g.part_members;
  part_pairs.resize(sweeps);
  part_members.resize(sweeps);
  for (std::vector<std::pair<int, int>>& pp : part_pairs) pp.clear();
  parallel_for(sweeps, 1, [&](std::size_t part, int) {
    std::vector<std::pair<int, int>>& out = part_pairs[part];
    auto cell_start = [&](std::size_t k) {  // the first entry of the cell holding entry k (or entries.size())
      while (k > 0 && k < entries.size() && entries[k - 1].key == entries[k].key) --k;
      return std::min(k, entries.size());
    };
    const std::size_t from = cell_start(entries.size() * part / sweeps);
    const std::size_t to = cell_start(entries.size() * (part + 1) / sweeps);
    std::vector<int>& members = part_members[part];
    for (std::size_t s = from; s < to;) {
      std::size_t e = s;
      while (e < entries.size() && entries[e].key == entries[s].key) ++e;
      members.clear();
      for (std::size_t k = s; k < e; ++k) members.push_back(entries[k].body);
      // Sweep along x inside the cell: sorted by AABB min x, then index.
      std::sort(members.begin(), members.end(), [&](int a, int b) {
        return min_x[static_cast<std::size_t>(a)] != min_x[static_cast<std::size_t>(b)]
                   ? min_x[static_cast<std::size_t>(a)] < min_x[static_cast<std::size_t>(b)] : a < b;
      });
      const std::uint64_t key = entries[s].key;
      for (std::size_t a = 0; a < members.size(); ++a) {
        const auto ia = static_cast<std::size_t>(members[a]);
        for (std::size_t b = a + 1; b < members.size(); ++b) {
          const auto ib = static_cast<std::size_t>(members[b]);
          if (max_x[ia] < min_x[ib]) break;
          // eq 83: the pair's home cell is max(cmin_i, cmin_j): report it there only.
          const std::uint64_t home = cell_key(std::max(cmin[ia].x, cmin[ib].x), std::max(cmin[ia].y, cmin[ib].y),
                                              std::max(cmin[ia].z, cmin[ib].z));
          if (home == key) maybe_pair(members[a], members[b], out);
        }
      }
      s = e;
    }
    std::sort(out.begin(), out.end());
  });
  for (const std::vector<std::pair<int, int>>& out : part_pairs) {  // sorted part by part, then merged
    const auto mid = static_cast<std::ptrdiff_t>(pairs_.size());
    pairs_.insert(pairs_.end(), out.begin(), out.end());
    std::inplace_merge(pairs_.begin(), pairs_.begin() + mid, pairs_.end());
  }
  // Large bodies: against every other body; a pair of two large bodies once.
  for (int L : large) {
    const auto l = static_cast<std::size_t>(L);
    for (std::size_t k = 0; k < n; ++k) {
      if (k == l) continue;
      const bool k_large = std::binary_search(large.begin(), large.end(), static_cast<int>(k));
      if (k_large && k < l) continue;
      if (max_x[l] < min_x[k] || max_x[k] < min_x[l]) continue;
      maybe_pair(L, static_cast<int>(k), pairs_);
    }
  }
  if (!large.empty()) std::sort(pairs_.begin(), pairs_.end());  // (the large bodies' pairs come after the merged ones)
}

}  // namespace lockstep
