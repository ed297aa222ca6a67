// The GPU engine's uniform grids (docs/GPU.md "Broadphase"): their
// parameters, entries and the candidate search over them.
#pragma once
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"

namespace lockstep::gpu {

// Grids. Each member body is filed under the cell of its centre; entries are
// sorted by cell key and a table gives each occupied cell its range [start,
// end) of sorted entries (start = -1: empty). The key is the cell's linear
// index in the box of cells that holds the members (x, then y, then z
// fastest: "dense"), so that the cells along z are consecutive keys and a
// row of them one contiguous range of entries; when that box has more than
// a few cells per member (a sparse scene), the key is a hash of the cell
// instead and each cell is looked up on its own (hash collisions are
// filtered by the entries' cell coordinates).

// What a grid needs to know of its members: the largest AABB half extent
// and the box of their centres. Reduced with min and max, which are exact,
// so the result does not depend on the order of the reduction.
// The reduction's identity for the box of centres: a value above every
// coordinate (3e38 in float; the largest Q16.16, which no position reaches:
// eq 20's range is guarded by the scene limits).
template <class T>
LS_HD inline T bounds_far() {
  if constexpr (Num<T>::kExact) return T::from_raw(0x7fffffff);
  else return static_cast<T>(3.0e38f);
}
template <class T>
struct Bounds {
  T amax{};
  T gmax{};  // oriented-box model: the largest AABB growth of a member (eqs 97, 107); 0 otherwise
  T lo[3] = {bounds_far<T>(), bounds_far<T>(), bounds_far<T>()};
  T hi[3] = {-bounds_far<T>(), -bounds_far<T>(), -bounds_far<T>()};
};
template <class T>
struct BoundsOp {
  LS_HD Bounds<T> operator()(const Bounds<T>& a, const Bounds<T>& b) const {
    Bounds<T> r;
    r.amax = Num<T>::max(a.amax, b.amax);
    r.gmax = Num<T>::max(a.gmax, b.gmax);
    for (int k = 0; k < 3; ++k) {
      r.lo[k] = Num<T>::min(a.lo[k], b.lo[k]);
      r.hi[k] = Num<T>::max(a.hi[k], b.hi[k]);
    }
    return r;
  }
};
template <class T>
LS_HD inline Bounds<T> bounds_of(const T4<T>& p, const T4<T>& aabb) {
  Bounds<T> b;
  b.amax = max_half_of(aabb);
  b.lo[0] = b.hi[0] = p.x;
  b.lo[1] = b.hi[1] = p.y;
  b.lo[2] = b.hi[2] = p.z;
  return b;
}

template <class T>
struct GridParams {
  T inv_cell = Num<T>::from_int(1);  // 1 / cell size (1/m)
  T reach{};              // largest AABB half extent of a member, plus margin (m)
  int dense = 0;          // 1: linear cell keys; 0: hashed
  int origin[3] = {0, 0, 0};  // dense: the box's lowest cell
  int dims[3] = {1, 1, 1};    // dense: the box's cells per axis
  unsigned table = 1;     // table entries: cells of the box, or the hash table's size
};

// Integer cell coordinates and body index of a sorted grid entry.
struct alignas(16) CellEntry {
  int x, y, z, body;
};

// What the gather reads of a sorted grid entry, in one 32-byte sector.
template <class T>
struct alignas(32) GridEntry {
  T px, py, pz;  // centre (m)
  int body;
  T ax, ay, az;  // AABB half extents (m)
  T unused;
};
LS_HD inline CellEntry ro(const CellEntry* e) {
#if defined(__CUDA_ARCH__)
  const int4 u = __ldg(reinterpret_cast<const int4*>(e));
  return CellEntry{u.x, u.y, u.z, u.w};
#else
  return *e;
#endif
}
template <class T>
LS_HD inline GridEntry<T> ro(const GridEntry<T>* e) {
#if defined(__CUDA_ARCH__)
  static_assert(sizeof(GridEntry<T>) == 2 * sizeof(int4), "two 128-bit loads");
  const int4 u[2] = {__ldg(reinterpret_cast<const int4*>(e)), __ldg(reinterpret_cast<const int4*>(e) + 1)};
  GridEntry<T> r;
  __builtin_memcpy(&r, u, sizeof r);
  return r;
#else
  return *e;
#endif
}

// A cell's range [start, end) of sorted entries; start = -1: empty.
struct alignas(8) CellRange {
  int start, end;
};
LS_HD inline CellRange ro(const CellRange* r) {
#if defined(__CUDA_ARCH__)
  const int2 u = __ldg(reinterpret_cast<const int2*>(r));
  return CellRange{u.x, u.y};
#else
  return *r;
#endif
}

template <class T>
struct GridView {
  const CellRange* range = nullptr;  // per table entry
  const GridEntry<T>* ent = nullptr; // sorted entries: centre, body, AABB
  const CellEntry* ent_c = nullptr;  // their cells (hashed grids only)
  const GridParams<T>* gp = nullptr;
  bool present = false;
};

// The grid's cells: size 2H for members whose largest AABB half extent is H
// (a floor keeps tiny bodies from making cells tiny). A member overlaps a
// body of half extent a (boxes grown by half the contact tolerance each, eq
// 97) only if its centre is within a + H + tol on every axis: the reach. The
// dense box when it has at most `dense_limit` cells, else a hash table of
// `hash_table` entries.
// The cell is eq 125's (band_inverse: max(2 H, 1/64)) and its coordinates
// eq 26's cell_coord, in the number type T, as World<T>'s broadphase computes
// cells: x -> floor(x / cell) rounded is monotonic, so a member whose centre
// lies within the reach lies in a visited cell (Q16.16: the sums are exact).
template <class T>
LS_HD inline GridParams<T> grid_params_for(const Bounds<T>& b, const T& tol, long long dense_limit, unsigned hash_table) {
  const T cell = Num<T>::max(Num<T>::from_int(2) * b.amax, Num<T>::from_double(1.0 / 64.0));
  GridParams<T> g;
  g.inv_cell = Num<T>::from_int(1) / cell;
  g.reach = (b.amax + b.gmax + tol) * Num<T>::from_double(1.0 + 1.0 / 1024.0) + cell / Num<T>::from_int(64);
  g.table = hash_table;
  if (!(b.lo[0] <= b.hi[0])) return g;  // no members
  // The dense box's cells, counted only while they stay within dense_limit
  // (at most 8 members + 4096 < 2^31, and a dimension < 2^31: the product
  // fits in 64 bits); a far-flung scene's box would overflow them.
  long long cells = 1;
  for (int k = 0; k < 3; ++k) {
    g.origin[k] = cell_coord(b.lo[k], g.inv_cell);
    g.dims[k] = cell_coord(b.hi[k], g.inv_cell) - g.origin[k] + 1;
    if (cells <= dense_limit) cells *= g.dims[k];
  }
  if (cells <= dense_limit) {
    g.dense = 1;
    g.table = static_cast<unsigned>(cells);
  }
  return g;
}

template <class T>
LS_HD inline unsigned grid_key(const GridParams<T>& g, int x, int y, int z) {
  if (g.dense)
    return static_cast<unsigned>(((x - g.origin[0]) * g.dims[1] + (y - g.origin[1])) * g.dims[2] + (z - g.origin[2]));
  return cell_hash(x, y, z) & (g.table - 1u);
}

// Calls fn(j, p_j, a_j) for every grid member j != self whose centre lies in a
// cell that an overlapping body's centre can lie in: per axis, within
// a_self + reach of p_self (plus a relative margin for rounding). Counts the
// candidates in `tested`.
template <class T, class Fn>
LS_HD void visit_candidates(const GridView<T>& g, int self, const Vec3<T>& p, const Vec3<T>& a, unsigned& tested,
                            Fn&& fn) {
  if (!g.present) return;
  const GridParams<T> gp = *g.gp;
  int lo[3], hi[3];
  for (int ax = 0; ax < 3; ++ax) {
    const T r = a[ax] + gp.reach + Num<T>::abs(p[ax]) * Num<T>::from_double(1.0 / 524288.0);
    lo[ax] = cell_coord(p[ax] - r, gp.inv_cell);
    hi[ax] = cell_coord(p[ax] + r, gp.inv_cell);
  }
  if (gp.dense) {
    for (int ax = 0; ax < 3; ++ax) {  // to the box's cells
      lo[ax] = lo[ax] < gp.origin[ax] ? 0 : lo[ax] - gp.origin[ax];
      hi[ax] = hi[ax] - gp.origin[ax] >= gp.dims[ax] ? gp.dims[ax] - 1 : hi[ax] - gp.origin[ax];
    }
    for (int x = lo[0]; x <= hi[0]; ++x)
      for (int y = lo[1]; y <= hi[1]; ++y) {
        const int row = (x * gp.dims[1] + y) * gp.dims[2];
        int s = -1, e = -1;
        for (int z = lo[2]; z <= hi[2]; ++z) {  // consecutive cells: one range of entries
          // Both loads issued at once (an empty cell's end is not used).
          const CellRange c = ro(g.range + row + z);
          if (c.start < 0) continue;
          if (s < 0) s = c.start;
          e = c.end;
        }
        for (int t = s; t < e; ++t) {
          const GridEntry<T> en = ro(g.ent + t);
          if (en.body == self) continue;
          ++tested;
          fn(en.body, Vec3<T>{en.px, en.py, en.pz}, Vec3<T>{en.ax, en.ay, en.az});
        }
      }
    return;
  }
  for (int x = lo[0]; x <= hi[0]; ++x)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z) {
        const unsigned h = grid_key(gp, x, y, z);
        const CellRange cr = ro(g.range + h);
        const int s = cr.start, e = cr.end;
        if (s < 0) continue;
        for (int t = s; t < e; ++t) {
          const CellEntry c = ro(g.ent_c + t);
          if (c.x != x || c.y != y || c.z != z) continue;  // another cell with the same hash
          if (c.body == self) continue;
          ++tested;
          const GridEntry<T> en = ro(g.ent + t);
          fn(c.body, Vec3<T>{en.px, en.py, en.pz}, Vec3<T>{en.ax, en.ay, en.az});
        }
      }
}

}  // namespace lockstep::gpu
