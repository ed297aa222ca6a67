// Disjoint sets over body indices (the solver's islands, solve_schedule.hpp;
// the groups of World<T>::items_by_groups, world_impl.hpp): root[b] is b's
// parent, b itself at a root. The lower root joins the other, so a set's
// root is its lowest body whatever the order of the joins.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace lockstep {

// b's root (halving the path on the way).
inline int union_find_root(std::vector<int>& root, int b) {
  while (root[static_cast<std::size_t>(b)] != b) {
    int& up = root[static_cast<std::size_t>(b)];
    up = root[static_cast<std::size_t>(up)];
    b = up;
  }
  return b;
}

// Joins the sets of a and b.
inline void union_find_join(std::vector<int>& root, int a, int b) {
  const int x = union_find_root(root, a), y = union_find_root(root, b);
  if (x != y) root[static_cast<std::size_t>(std::max(x, y))] = std::min(x, y);
}

}  // namespace lockstep
