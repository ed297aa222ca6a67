// The kernels that build the GPU engine's grids (stage 2 of docs/SPEC.md
// 7.2): the frozen grid's bounds, the grid parameters, the cell keys and
// the cell table.
#pragma once
#include <cstdint>

#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "grid.hpp"

namespace lockstep::gpu {

// The frozen grid's members (not awake, not large): their Bounds; others
// the reduction's identity.
template <class T>
struct FrozenBoundsK {
  BodyArrays<T> b;
  const std::uint8_t* large_flag;
  Bounds<T>* bounds;
  LS_HD void operator()(int i) const {
    const bool member = !is_awake(b.flags[i]) && large_flag[i] == 0;
    bounds[i] = member ? bounds_of(b.pos[i], b.aabb[i]) : Bounds<T>{};
  }
};

template <class T>
struct GridParamsK {
  const Bounds<T>* reduced;
  T tol;
  long long dense_limit;
  unsigned hash_table;
  GridParams<T>* out;
  LS_HD void operator()(int) const { *out = grid_params_for(*reduced, tol, dense_limit, hash_table); }
};

// Keys for a grid: the cell's key. With `list` the members are list[0..n);
// without, every body i is a member when frozen (not awake and not large),
// and others get the key `table` (sorted last).
template <class T>
struct GridKeysK {
  const int* list;
  BodyArrays<T> b;
  const std::uint8_t* large_flag;
  const GridParams<T>* gp;
  unsigned* keys;
  int* vals;
  LS_HD void operator()(int k) const {
    const int i = list != nullptr ? list[k] : k;
    vals[k] = i;
    const GridParams<T> g = *gp;
    if (list == nullptr && (is_awake(b.flags[i]) || large_flag[i] != 0)) { keys[k] = g.table; return; }
    const T4<T> p = b.pos[i];
    keys[k] = grid_key(g, cell_coord(p.x, g.inv_cell), cell_coord(p.y, g.inv_cell), cell_coord(p.z, g.inv_cell));
  }
};

// After the sort: the table ranges and the entries in sorted order.
template <class T>
struct CellTableK {
  const unsigned* keys;
  const int* vals;
  int n;
  BodyArrays<T> b;
  const GridParams<T>* gp;
  CellRange* range;
  GridEntry<T>* ent;
  CellEntry* ent_c;  // written for hashed grids only
  LS_HD void operator()(int s) const {
    const unsigned key = keys[s];
    if (key == gp->table) return;  // not a member
    const int i = vals[s];
    const T4<T> p = b.pos[i];
    const T inv = gp->inv_cell;
    const T4<T> a = b.aabb[i];
    ent[s] = GridEntry<T>{p.x, p.y, p.z, i, a.x, a.y, a.z, T{}};
    if (gp->dense == 0) ent_c[s] = CellEntry{cell_coord(p.x, inv), cell_coord(p.y, inv), cell_coord(p.z, inv), i};
    if (s == 0 || keys[s - 1] != key) range[key].start = s;
    if (s == n - 1 || keys[s + 1] != key) range[key].end = s + 1;
  }
};

}  // namespace lockstep::gpu
