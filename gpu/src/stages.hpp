// The GPU engine's kernels, one functor per kernel: operator()(k) is the work
// of thread k. The device backend launches them as CUDA kernels; the host
// build calls them in a loop over k. Each thread owns one element (a body, a
// sorted grid entry) and writes only that element's outputs, reading its
// neighbours' values from buffers that no thread of the same kernel writes;
// the only atomics are integer ones whose order cannot change a result
// (counters, the wake flag and woken list, the longest neighbour list, the
// lowest failing body index).
#pragma once
#include <cstdint>

#include "colouring.hpp"
#include "kernel_support.hpp"
#include "lockstep/gpu/elements.hpp"
#include "lockstep/gpu/soa.hpp"
#include "lockstep/physics/box_box.hpp"

namespace lockstep::gpu {

// ---------------------------------------------------------------------------
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
struct Bounds {
  float amax = 0.0f;
  float gmax = 0.0f;  // oriented-box model: the largest AABB growth of a member (eqs 97, 107); 0 otherwise
  float lo[3] = {3.0e38f, 3.0e38f, 3.0e38f};
  float hi[3] = {-3.0e38f, -3.0e38f, -3.0e38f};
};
struct BoundsOp {
  LS_HD Bounds operator()(const Bounds& a, const Bounds& b) const {
    Bounds r;
    r.amax = Num<float>::max(a.amax, b.amax);
    r.gmax = Num<float>::max(a.gmax, b.gmax);
    for (int k = 0; k < 3; ++k) {
      r.lo[k] = Num<float>::min(a.lo[k], b.lo[k]);
      r.hi[k] = Num<float>::max(a.hi[k], b.hi[k]);
    }
    return r;
  }
};
LS_HD inline Bounds bounds_of(const F4& p, const F4& aabb) {
  Bounds b;
  b.amax = aabb.w;
  b.lo[0] = b.hi[0] = p.x;
  b.lo[1] = b.hi[1] = p.y;
  b.lo[2] = b.hi[2] = p.z;
  return b;
}

struct GridParams {
  float inv_cell = 1.0f;  // 1 / cell size (1/m)
  float reach = 0.0f;     // largest AABB half extent of a member, plus margin (m)
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
struct alignas(32) GridEntry {
  float px, py, pz;  // centre (m)
  int body;
  float ax, ay, az;  // AABB half extents (m)
  float unused;
};
LS_HD inline CellEntry ro(const CellEntry* e) {
#if defined(__CUDA_ARCH__)
  const int4 u = __ldg(reinterpret_cast<const int4*>(e));
  return CellEntry{u.x, u.y, u.z, u.w};
#else
  return *e;
#endif
}
LS_HD inline GridEntry ro(const GridEntry* e) {
#if defined(__CUDA_ARCH__)
  const float4 u = __ldg(reinterpret_cast<const float4*>(e)), v = __ldg(reinterpret_cast<const float4*>(e) + 1);
  return GridEntry{u.x, u.y, u.z, __float_as_int(u.w), v.x, v.y, v.z, v.w};
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

struct GridView {
  const CellRange* range = nullptr;  // per table entry
  const GridEntry* ent = nullptr;    // sorted entries: centre, body, AABB
  const CellEntry* ent_c = nullptr;  // their cells (hashed grids only)
  const GridParams* gp = nullptr;
  bool present = false;
};

// The grid's cells: size 2H for members whose largest AABB half extent is H
// (a floor keeps tiny bodies from making cells tiny). A member overlaps a
// body of half extent a (boxes grown by half the contact tolerance each, eq
// 97) only if its centre is within a + H + tol on every axis: the reach. The
// dense box when it has at most `dense_limit` cells, else a hash table of
// `hash_table` entries.
LS_HD inline GridParams grid_params_for(const Bounds& b, float tol, long long dense_limit, unsigned hash_table) {
  const float cell = Num<float>::max(2.0f * b.amax, 1.0f / 64.0f);
  GridParams g;
  g.inv_cell = 1.0f / cell;
  g.reach = (b.amax + b.gmax + tol) * (1.0f + 1.0f / 1024.0f) + cell / 64.0f;
  g.table = hash_table;
  if (!(b.lo[0] <= b.hi[0])) return g;  // no members
  long long cells = 1;
  for (int k = 0; k < 3; ++k) {
    g.origin[k] = cell_coord(b.lo[k], g.inv_cell);
    g.dims[k] = cell_coord(b.hi[k], g.inv_cell) - g.origin[k] + 1;
    cells *= g.dims[k];
  }
  if (cells <= dense_limit) {
    g.dense = 1;
    g.table = static_cast<unsigned>(cells);
  }
  return g;
}

LS_HD inline unsigned grid_key(const GridParams& g, int x, int y, int z) {
  if (g.dense)
    return static_cast<unsigned>(((x - g.origin[0]) * g.dims[1] + (y - g.origin[1])) * g.dims[2] + (z - g.origin[2]));
  return cell_hash(x, y, z) & (g.table - 1u);
}

// Calls fn(j, p_j, a_j) for every grid member j != self whose centre lies in a
// cell that an overlapping body's centre can lie in: per axis, within
// a_self + reach of p_self (plus a relative margin for rounding). Counts the
// candidates in `tested`.
template <class Fn>
LS_HD void visit_candidates(const GridView& g, int self, const Vec3<float>& p, const Vec3<float>& a, unsigned& tested,
                            Fn&& fn) {
  if (!g.present) return;
  const GridParams gp = *g.gp;
  int lo[3], hi[3];
  for (int ax = 0; ax < 3; ++ax) {
    const float r = a[ax] + gp.reach + Num<float>::abs(p[ax]) * (1.0f / 524288.0f);
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
          const GridEntry en = ro(g.ent + t);
          if (en.body == self) continue;
          ++tested;
          fn(en.body, Vec3<float>{en.px, en.py, en.pz}, Vec3<float>{en.ax, en.ay, en.az});
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
          const GridEntry en = ro(g.ent + t);
          fn(c.body, Vec3<float>{en.px, en.py, en.pz}, Vec3<float>{en.ax, en.ay, en.az});
        }
      }
}

// Scene-wide values the kernels need.
struct SceneConsts {
  Params<float> P{};
  float half_tol = 0;  // contact_tolerance / 2 (eq 97)
  bool gravity = false, damping = false, friction = false, restitution = false, sleep = false;
  bool ground_on = false;
  float ground_y = 0, ground_e = 0, ground_mu = 0;
  int n_sdf = 0;
  const SdfGrid<float>* sdf = nullptr;
  const F4* sdf_material = nullptr;  // x: e, y: mu
  const int* large = nullptr;        // large static bodies, ascending
  int n_large = 0;
  float relaxation = 1.0f;
  bool oriented = false;  // the oriented-box pair model (docs/SPEC.md 2.4, eqs 100-110); false: the source's AABB model
  const float* grow = nullptr;  // oriented-box model: per body, its growth this frame (eqs 97, 107); null: AABB model
  // eqs 97, 107: body i's tolerance for ground corners.
  LS_HD float immovable_tol(int i) const {
    return grow != nullptr ? immovable_tolerance(ro(grow + i), half_tol, P.contact_tolerance) : P.contact_tolerance;
  }
  // Contacts with immovable things per active body: 8 ground corners (when
  // ground_on), then 9 samples per SDF volume.
  LS_HD int ground_slots() const { return ground_on ? 8 : 0; }
  LS_HD int imm_stride() const { return ground_slots() + 9 * n_sdf; }
};

// The body-body contact between self and j as World<T> computes it: body 1
// (a) is the lower index.
LS_HD inline PairContact<float> canonical_pair(const SceneConsts& sc, int self, const Vec3<float>& p,
                                               const Vec3<float>& a, int j, const Vec3<float>& pj,
                                               const Vec3<float>& aj) {
  const float tol = sc.P.contact_tolerance;
  return self < j ? pair_contact(p, a, pj, aj, sc.half_tol, tol) : pair_contact(pj, aj, p, a, sc.half_tol, tol);
}

// Per-contact solver state in two F4s: {j_n, j_t} (accumulated, rewritten by
// each iteration) and {v_n0, e, mu, k_n} (fixed when the solve starts), side
// by side in one 32-byte sector.
struct alignas(32) ContactRecord {
  F4 a, b;
};

LS_HD inline ContactState<float> load_state(const F4& a, const F4& b) {
  ContactState<float> c;
  c.j_n = a.x;
  c.j_t = {a.y, a.z, a.w};
  c.v_n0 = b.x;
  c.e = b.y;
  c.mu = b.z;
  c.k_n = b.w;
  return c;
}
LS_HD inline void store_state(const ContactState<float>& c, F4& a, F4& b) {
  a = {c.j_n, c.j_t.x, c.j_t.y, c.j_t.z};
  b = {c.v_n0, c.e, c.mu, c.k_n};
}

// ---------------------------------------------------------------------------
// The oriented-box pair model (docs/SPEC.md 2.4). Each neighbour-list entry
// of a pair holds the pair's manifold (eqs 100-106) as World<T>'s narrowphase
// computes it, body a the lower index (n from the higher towards the lower),
// and its points' solver state; each body keeps its own copy (equal for two
// active bodies: both compute it with the same arguments, and the coloured
// solver writes both).
struct alignas(32) PairManifold {  // 256 bytes (static_assert below)
  F4 n;                            // xyz: the normal (from the higher index towards the lower)
  F4 pt[kBoxManifoldPoints];       // xyz: the point (m), w: its penetration (m; negative: a speculative gap)
  int feature[kBoxManifoldPoints]; // eq 96's key
  int count = 0;                   // points (0: the grown AABBs overlap but the boxes are apart)
  int deepest = 0;                 // the point that carries the pair's correction (first on ties)
  float depth = 0.0f;              // eq 110: the mean depth of the points
  int unused = 0;
  ContactRecord st[kBoxManifoldPoints];
};

static_assert(sizeof(PairManifold) == 256, "the pair record: eq 113's records live apart (SolverData::conv_pair)");

// eq 97 and 107: the AABB growth of a body at the broadphase, half the
// contact tolerance plus, for an awake body, its speculative reach.
LS_HD inline float body_growth(const SceneConsts& sc, const Vec3<float>& v, const Vec3<float>& w, const Vec3<float>& h) {
  return sc.half_tol + speculative_reach(v, w, h, sc.P.dt);  // eq 107
}

// World<T>'s pair test of the oriented-box model: the broadphase's grown
// boxes (eqs 82-83, 97, 107) and the narrowphase's early-out (eqs 38-39 on
// the grown boxes); body a is the lower index.
LS_HD inline bool grown_overlap(const Vec3<float>& pa, const Vec3<float>& aa, float ga, const Vec3<float>& pb,
                                const Vec3<float>& ab, float gb) {
  for (int ax = 0; ax < 3; ++ax)
    if (pa[ax] + (aa[ax] + ga) < pb[ax] - (ab[ax] + gb) || pb[ax] + (ab[ax] + gb) < pa[ax] - (aa[ax] + ga)) return false;
  return aabb_overlap(pa, aa + Vec3<float>{ga, ga, ga}, pb, ab + Vec3<float>{gb, gb, gb}).hit;
}

// eqs 100-107: the manifold of bodies a < b (growths ga, gb), points up to
// the contact tolerance plus both reaches apart.
LS_HD inline BoxManifold<float> pair_manifold(const SceneConsts& sc, const Vec3<float>& pa, const Mat3<float>& Ra,
                                              const Vec3<float>& ha, float ga, const Vec3<float>& pb,
                                              const Mat3<float>& Rb, const Vec3<float>& hb, float gb) {
  const float pair_tol = (ga - sc.half_tol) + (gb - sc.half_tol) + sc.P.contact_tolerance;
  return box_box_manifold(pa, Ra, ha, pb, Rb, hb, pair_tol);
}

// Bit equality of two floats (NaN included): the fixed-point sweeps stop
// when a sweep reproduces its input exactly.
LS_HD inline bool same_bits(float x, float y) {
#if defined(__CUDA_ARCH__)
  return __float_as_uint(x) == __float_as_uint(y);
#else
  unsigned ux, uy;
  __builtin_memcpy(&ux, &x, sizeof ux);
  __builtin_memcpy(&uy, &y, sizeof uy);
  return ux == uy;
#endif
}
LS_HD inline bool same_bits(const F4& a, const F4& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z) && same_bits(a.w, b.w);
}

// ---------------------------------------------------------------------------
// Stage 1: velocity integration of the awake bodies; also gathers what the
// awake grid needs of each (Bounds).
struct IntegrateVelocityK {
  const int* list;
  BodyArrays b;
  SceneConsts sc;
  Bounds* bounds;  // per slot, or null
  float* grow = nullptr;  // oriented-box model: per body, its AABB growth this frame (eqs 97, 107); null: AABB model
  int integrate_end = 0x7fffffff;  // slots from here on (woken by eq 108 after stage 1) are not integrated
  LS_HD void operator()(int k) const {
    const int i = list[k];
    if ((sc.gravity || sc.damping) && k < integrate_end) {
      Vec3<float> v = xyz(b.vel[i]), w = xyz(b.ang[i]);
      integrate_velocity(v, w, sc.gravity, sc.damping, sc.P);
      b.vel[i] = f4(v, 0.0f);
      b.ang[i] = f4(w, 0.0f);
    }
    if (grow != nullptr) {
      const float g = body_growth(sc, xyz(b.vel[i]), xyz(b.ang[i]), xyz(b.half[i]));
      grow[i] = g;
      if (bounds != nullptr) {  // the grid's reach covers the grown boxes
        Bounds bd = bounds_of(b.pos[i], b.aabb[i]);
        bd.gmax = g;
        bounds[k] = bd;
      }
      return;
    }
    if (bounds != nullptr) bounds[k] = bounds_of(b.pos[i], b.aabb[i]);
  }
};

// The frozen grid's members (not awake, not large): their Bounds; others
// the reduction's identity.
struct FrozenBoundsK {
  BodyArrays b;
  const std::uint8_t* large_flag;
  Bounds* bounds;
  LS_HD void operator()(int i) const {
    const bool member = !is_awake(b.flags[i]) && large_flag[i] == 0;
    bounds[i] = member ? bounds_of(b.pos[i], b.aabb[i]) : Bounds{};
  }
};

struct GridParamsK {
  const Bounds* reduced;
  float tol;
  long long dense_limit;
  unsigned hash_table;
  GridParams* out;
  LS_HD void operator()(int) const { *out = grid_params_for(*reduced, tol, dense_limit, hash_table); }
};

// Keys for a grid: the cell's key. With `list` the members are list[0..n);
// without, every body i is a member when frozen (not awake and not large),
// and others get the key `table` (sorted last).
struct GridKeysK {
  const int* list;
  BodyArrays b;
  const std::uint8_t* large_flag;
  const GridParams* gp;
  unsigned* keys;
  int* vals;
  LS_HD void operator()(int k) const {
    const int i = list != nullptr ? list[k] : k;
    vals[k] = i;
    const GridParams g = *gp;
    if (list == nullptr && (is_awake(b.flags[i]) || large_flag[i] != 0)) { keys[k] = g.table; return; }
    const F4 p = b.pos[i];
    keys[k] = grid_key(g, cell_coord(p.x, g.inv_cell), cell_coord(p.y, g.inv_cell), cell_coord(p.z, g.inv_cell));
  }
};

// After the sort: the table ranges and the entries in sorted order.
struct CellTableK {
  const unsigned* keys;
  const int* vals;
  int n;
  BodyArrays b;
  const GridParams* gp;
  CellRange* range;
  GridEntry* ent;
  CellEntry* ent_c;  // written for hashed grids only
  LS_HD void operator()(int s) const {
    const unsigned key = keys[s];
    if (key == gp->table) return;  // not a member
    const int i = vals[s];
    const F4 p = b.pos[i];
    const float inv = gp->inv_cell;
    const F4 a = b.aabb[i];
    ent[s] = GridEntry{p.x, p.y, p.z, i, a.x, a.y, a.z, 0.0f};
    if (gp->dense == 0) ent_c[s] = CellEntry{cell_coord(p.x, inv), cell_coord(p.y, inv), cell_coord(p.z, inv), i};
    if (s == 0 || keys[s - 1] != key) range[key].start = s;
    if (s == n - 1 || keys[s + 1] != key) range[key].end = s + 1;
  }
};

// The threads of the solver's iterations in an order of their work (a
// scheduling choice: each slot's result does not depend on the thread that
// computes it). A warp runs the union of its threads' paths, so within
// each segment of 2^11 consecutive slots, slots near the ground (a manifold
// to solve: the lowest corner of the AABB within the contact tolerance) are
// put together, then ordered by the length of their neighbour lists. Whole
// segments keep their place, so that the memory a segment touches stays in
// the cache while its threads run. The gather writes the key of each slot,
// sorted with the slots as values (stable: ascending slots within a class).
struct WorkOrder {
  unsigned* key = nullptr;
  int* slot = nullptr;
};
inline constexpr int kWorkClassBits = 5, kWorkSegmentBits = 11;
LS_HD inline unsigned work_key(int slot, bool manifold, int neighbours) {
  const unsigned m = neighbours < 15 ? static_cast<unsigned>(neighbours) : 15u;
  const unsigned segment = static_cast<unsigned>(slot) >> kWorkSegmentBits;
  return (segment << kWorkClassBits) | (manifold ? 0u : 16u) | m;
}
// The key bits to sort for n slots.
inline int work_key_bits(int n) {
  int bits = kWorkClassBits;
  for (unsigned s = static_cast<unsigned>(n - 1) >> kWorkSegmentBits; s != 0; s >>= 1) ++bits;
  return bits;
}

// Where this frame's contacts of body i are, for next frame's warm start (eq
// 96): its slot, written with the frame number (double-buffered by frame parity).
struct ContactIndex {
  int* slot_of;  // per body
  int* stamp;    // per body: frame at which slot_of was written
};

// Stages 2-4: each active body gathers the bodies whose (grown) AABB overlaps
// its own, up to `stride` of them (the count goes on: the host enlarges the
// blocks and gathers again when one overflows), and wakes (eq 81) sleeping
// ones that it touches fast or deeply. Awake bodies look in the awake grid,
// the frozen grid and the large statics; woken bodies (`woken_pass`) only in
// the awake grid: World<T> pairs only bodies of which one was awake at the
// broadphase. `count_work` is off when gathering again.
struct GatherK {
  const int* list;
  int slot0;  // slot of list[0]
  BodyArrays b;
  SceneConsts sc;
  GridView awake_grid, frozen_grid;
  bool woken_pass, count_work;
  NeighbourLists lists;
  int* max_count;
  int* wake_flag;
  int* woken;
  int* n_woken;
  WorkOrder order;  // keys to write, or none
  ContactIndex index;
  int frame;
  Counter* ctr;
  const float* grow = nullptr;  // oriented-box model: per body, its AABB growth (eqs 97, 107); null: AABB model
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    const int slot = slot0 + k;
    index.slot_of[i] = slot;
    index.stamp[i] = frame;
    const Vec3<float> p = xyz(ro(b.pos + i)), a = xyz(ro(b.aabb + i));
    int* out = lists.nbr + slot * lists.stride;
    unsigned tested = 0, contacts = 0;
    int m = 0;
    const bool oriented = grow != nullptr;
    const float gi = oriented ? ro(grow + i) : 0.0f;
    const Vec3<float> reach = oriented ? a + Vec3<float>{gi, gi, gi} : a;  // the candidates of the grown box
    // World<T>'s pair test: the AABBs grown by half the contact tolerance
    // (eqs 38-39, 97), or, oriented-box model, by each body's growth (107).
    auto touches = [&](int j, const Vec3<float>& pj, const Vec3<float>& aj) {
      if (!oriented) return canonical_pair(sc, i, p, a, j, pj, aj).hit;
      const float gj = ro(grow + j);
      return i < j ? grown_overlap(p, a, gi, pj, aj, gj) : grown_overlap(pj, aj, gj, p, a, gi);
    };
    visit_candidates(awake_grid, i, p, reach, tested, [&](int j, const Vec3<float>& pj, const Vec3<float>& aj) {
      if (!touches(j, pj, aj)) return;
      if (m < lists.stride) out[m] = j;
      ++m;
      if (!woken_pass && i < j && !oriented) ++contacts;
    });
    if (!woken_pass) {
      auto other = [&](int j, const Vec3<float>& pj, const Vec3<float>& aj) {
        if (!touches(j, pj, aj)) return;
        if (m < lists.stride) out[m] = j;
        ++m;
        if (!oriented) ++contacts;
        if (count_work && sc.sleep && (ro(b.flags + j) & kFlagAsleep) != 0) {
          const bool i_is_a = i < j;
          const Vec3<float> vi = xyz(ro(b.vel + i)), vj = xyz(ro(b.vel + j));
          const Vec3<float> va = i_is_a ? vi : vj, vb = i_is_a ? vj : vi;
          bool wakes_j = false;
          if (!oriented) {
            const PairContact<float> c = canonical_pair(sc, i, p, a, j, pj, aj);
            wakes_j = wake_test(va, !i_is_a, vb, i_is_a, c.n, c.penetration, sc.P);
          } else {  // eq 81 on each point of the pair's manifold
            const Mat3<float> Ri = rotation_matrix(quat(ro(b.rot + i))), Rj = rotation_matrix(quat(ro(b.rot + j)));
            const Vec3<float> hi = xyz(ro(b.half + i)), hj = xyz(ro(b.half + j));
            const float gj = ro(grow + j);
            const BoxManifold<float> mf = i_is_a ? pair_manifold(sc, p, Ri, hi, gi, pj, Rj, hj, gj)
                                                 : pair_manifold(sc, pj, Rj, hj, gj, p, Ri, hi, gi);
            for (int q = 0; q < mf.count && !wakes_j; ++q)
              wakes_j = wake_test(va, !i_is_a, vb, i_is_a, mf.n, mf.penetration[q], sc.P);
          }
          if (wakes_j && claim_flag(&wake_flag[j])) woken[fetch_add(n_woken, 1)] = j;
        }
      };
      visit_candidates(frozen_grid, i, p, reach, tested, other);
      for (int t = 0; t < sc.n_large; ++t) {
        const int j = sc.large[t];
        ++tested;
        other(j, xyz(ro(b.pos + j)), xyz(ro(b.aabb + j)));
      }
    }
    const int kept = m < lists.stride ? m : lists.stride;
    lists.count[slot] = kept;
    if (m > lists.stride) store_max(max_count, m);
    for (int s = 1; s < kept; ++s) {  // insertion sort: ascending body index
      const int x = out[s];
      int t = s - 1;
      while (t >= 0 && out[t] > x) { out[t + 1] = out[t]; --t; }
      out[t + 1] = x;
    }
    if (order.key != nullptr) {
      order.key[slot] = work_key(slot, sc.ground_on && p.y - a.y < sc.ground_y + sc.P.contact_tolerance, m);
      order.slot[slot] = slot;
    }
    if (count_work) {
      add_counter(&ctr[kCPairsTested], tested);
      add_counter(&ctr[kCBodyContacts], contacts);
    }
  }
};

// Each active body's slot, when no gather runs (no body-body contacts).
struct SlotIndexK {
  const int* list;
  ContactIndex index;
  int frame;
  LS_HD void operator()(int k) const {
    index.slot_of[list[k]] = k;
    index.stamp[list[k]] = frame;
  }
};

// Woken bodies join the active set after the awake ones (slots n_awake..).
struct WakeApplyK {
  const int* woken;
  BodyArrays b;
  int* wake_flag;
  int* active;
  int n_awake;
  float* grow = nullptr;  // oriented-box model: a body woken here was asleep at the broadphase (growth half_tol)
  float half_tol = 0.0f;
  LS_HD void operator()(int k) const {
    const int i = woken[k];
    b.flags[i] = static_cast<std::uint8_t>(b.flags[i] & ~kFlagAsleep);
    b.sleep_counter[i] = 0;
    if (grow != nullptr) grow[i] = half_tol;
    wake_flag[i] = 0;
    active[n_awake + k] = i;
  }
};

// Which of the six axis directions a body-body contact normal points most
// nearly along (its largest component, the first on ties; eqs 41-42's
// normals are +-1 on one axis): 2 axis + (negative).
LS_HD inline int direction_of(const Vec3<float>& n) {
  int axis = 0;
  for (int ax = 1; ax < 3; ++ax)
    if (Num<float>::abs(n[ax]) > Num<float>::abs(n[axis])) axis = ax;
  return 2 * axis + (n[axis] < 0.0f ? 1 : 0);
}

// Mass splitting of the Jacobi solver: a body's contacts with other active
// bodies are counted per normal direction (one byte each of dir_count); a
// contact's effective mass is scaled by the larger of its two bodies' counts
// in its direction (n towards body i), over the relaxation. Contacts pushing a
// body the same way share it; opposite ones (a body in a stack) do not.
LS_HD inline float jacobi_split(Counter counts_i, Counter counts_j, const Vec3<float>& n_towards_i, float relaxation) {
  const int d = direction_of(n_towards_i);
  const unsigned mine = static_cast<unsigned>((counts_i >> (8 * d)) & 255u);
  const unsigned theirs = static_cast<unsigned>((counts_j >> (8 * (d ^ 1))) & 255u);
  return Num<float>::from_int(static_cast<int>(mine > theirs ? mine : theirs)) / relaxation;
}

// Support contact of a body (settling eq 75, sleep eq 78).
inline constexpr int kNoSupport = -1;
inline constexpr int kStaticSupport = -2;  // ground or SDF volume: v_s = 0

// c ? x : y, one float at a time (a select of whole structs can put them in
// local memory).
LS_HD inline float pick(bool c, float x, float y) { return c ? x : y; }
LS_HD inline Vec3<float> pick(bool c, const Vec3<float>& x, const Vec3<float>& y) {
  return {pick(c, x.x, y.x), pick(c, x.y, y.y), pick(c, x.z, y.z)};
}
LS_HD inline BodyView<float> pick(bool c, const BodyView<float>& x, const BodyView<float>& y) {
  BodyView<float> r;
  r.v = pick(c, x.v, y.v);
  r.w = pick(c, x.w, y.w);
  r.inv_mass = pick(c, x.inv_mass, y.inv_mass);
  for (int row = 0; row < 3; ++row) r.R.row[row] = pick(c, x.R.row[row], y.R.row[row]);
  r.inv_inertia = pick(c, x.inv_inertia, y.inv_inertia);
  return r;
}

// The contact-side view of body j (dynamic when awake, else immovable). For
// kernels that write none of the arrays it reads.
LS_HD inline BodyView<float> view_of(const BodyArrays& b, int j, const F4* vel, const F4* ang) {
  if (!is_awake(ro(b.flags + j))) return immovable_view<float>();
  const F4 pj = ro(b.pos + j);
  return dynamic_view(xyz(ro(vel + j)), xyz(ro(ang + j)), pj.w, rotation_matrix(quat(ro(b.rot + j))),
                      xyz(ro(b.inert + j)));
}

// Everything the solver kernels share.
struct SolverData {
  const int* list;
  BodyArrays b;
  SceneConsts sc;
  NeighbourLists lists;
  const Counter* dir_count;
  const F4* sdf_c0;
  const F4* sdf_c1;
  ContactRecord* imm;   // immovable contacts' state, imm_stride() per slot
  ContactRecord* pair;  // body-body contacts' state, one per neighbour-list entry (each body keeps its own copy)
  PairManifold* man = nullptr;  // oriented-box model: the pair's manifold and state, per entry (instead of `pair`)
  // eq 113's records, only with the skip on (converged_speed > 0; null
  // otherwise: none is read or written, and the pair record stays 256 bytes):
  // 4 F4 per visit, the sides' v, w (lower index first) its last visit left,
  // [0].w = 1 when it changed them by < converged_speed.
  F4* conv_imm = nullptr;   // each slot's ground and SDF manifolds
  F4* conv_pair = nullptr;  // each neighbour-list entry's pair (oriented-box model)
  LS_HD F4* conv_of_pair(int t) const { return conv_pair != nullptr ? conv_pair + 4 * static_cast<long>(t) : nullptr; }
};

// eq 113 (7.2 step 5, oriented-box model): a visit is skipped, converged,
// from pass converged_pass on (never the first) when its last visit changed
// its sides' velocities by less than converged_speed and they have moved by
// less than that since. `st`: the 4 F4 of its record, A the lower index
// (null, and never read, with the skip off).
LS_HD inline bool visit_is_converged(const F4* st, const BodyView<float>& A, const BodyView<float>& B,
                                     const Params<float>& P, int pass) {
  if (!(P.converged_speed > 0.0f) || pass == 0 || pass < P.converged_pass || st[0].w == 0.0f) return false;
  return visit_converged(xyz(st[0]), xyz(st[1]), A.v, A.w, P.converged_speed) &&
         visit_converged(xyz(st[2]), xyz(st[3]), B.v, B.w, P.converged_speed);
}
// The record of a visit that took its sides from (va0, wa0, vb0, wb0) to A, B
// with `shortened` steps of eq 99 (alpha < 1: partial progress, not small).
LS_HD inline void record_visit(F4* st, const Vec3<float>& va0, const Vec3<float>& wa0, const Vec3<float>& vb0,
                               const Vec3<float>& wb0, const BodyView<float>& A, const BodyView<float>& B,
                               const Params<float>& P, unsigned shortened) {
  if (!(P.converged_speed > 0.0f)) return;  // the skip is off (the default): no record is read, none is kept
  const bool small = shortened == 0 && visit_converged(va0, wa0, A.v, A.w, P.converged_speed) &&
                     visit_converged(vb0, wb0, B.v, B.w, P.converged_speed);
  st[0] = f4(A.v, small ? 1.0f : 0.0f);
  st[1] = f4(A.w, 0.0f);
  st[2] = f4(B.v, 0.0f);
  st[3] = f4(B.w, 0.0f);
}

// Last frame's contacts, for the warm start (eq 96): the accumulated normal
// impulse is the x of each contact's first state F4.
struct PreviousContacts {
  int frame;  // the previous frame's number
  const int* slot_of;
  const int* stamp;
  NeighbourLists lists;
  const ContactRecord* imm;
  const int* ground_mask;  // per slot: bit c set when ground corner c was a contact
  const ContactRecord* pair;
  const PairManifold* man = nullptr;  // oriented-box model
  LS_HD bool had(int i) const { return ro(stamp + i) == frame; }
  // The entry of pair (i, j) in j's previous list (j active last frame), or -1.
  LS_HD int entry_of(int j, int i) const { return had(j) ? lists.find(ro(slot_of + j), i) : -1; }
  // The accumulated impulses of pair (i, j) from j's copy (j active last
  // frame); j_n = 0 when there is none.
  LS_HD F4 from(int j, int i) const {
    if (!had(j)) return F4{};
    const int t = lists.find(ro(slot_of + j), i);
    return t >= 0 ? ro(&pair[t].a) : F4{};
  }
};

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

// Stage 5, one iteration for every active body (docs/GPU.md "Contact
// resolution"). Contacts with immovable things (the ground and SDF manifolds
// of eq 99, sleeping and static bodies) are visited one after the other on
// the body's own velocity, as World<T> visits them. Contacts with other
// active bodies are Jacobi: both bodies visit the contact, each against the
// velocities at the start of the iteration (vin/win), so both compute the
// same impulse and keep equal copies of its accumulated state; each adds its
// own velocity change, and the effective masses are scaled by the larger
// of the two bodies' contact counts in the contact's direction (mass
// splitting) over the relaxation. With `edge_colour` (the coloured solver,
// colouring.hpp) the body visits only its immovable contacts, in place (vin
// = vout): the contacts with active bodies are SolveEdgeK's.
struct SolveK {
  SolverData d;
  const int* order;  // thread -> slot (WorkOrder), or null: thread k is slot k
  const int* edge_colour;  // the coloured solver's colours per entry, or null: Jacobi
  const int* has_immovable;  // per slot (ContactsK): the coloured solver skips bodies without immovable contacts
  const F4* vin;
  const F4* win;
  F4* vout;
  F4* wout;
  Counter* ctr;
  bool reverse = false;  // oriented-box model, odd passes: the body's visits in reverse (7.2 step 5)
  int pass = 0;          // the solver pass (eq 113)
  LS_HD void operator()(int thread) const {
    const BodyArrays& b = d.b;
    const SceneConsts& sc = d.sc;
    const int k = order != nullptr ? ro(order + thread) : thread;
    const bool coloured = edge_colour != nullptr;
    if (coloured && ro(has_immovable + k) == 0) return;  // nothing to visit; the velocity stays in place
    const int i = ro(d.list + k);
    const F4 pi4 = ro(b.pos + i), h4 = ro(b.half + i);
    const Vec3<float> p = xyz(pi4), a = xyz(ro(b.aabb + i)), h = xyz(h4);
    const Mat3<float> R = rotation_matrix(quat(ro(b.rot + i)));
    const Vec3<float> I = xyz(ro(b.inert + i));
    const Vec3<float> v0 = xyz(coloured ? vin[i] : ro(vin + i)), w0 = xyz(coloured ? win[i] : ro(win + i));
    BodyView<float> self = dynamic_view(v0, w0, pi4.w, R, I);
    const float tol = sc.immovable_tol(i);  // eqs 97, 107
    const int stride = sc.imm_stride();
    SolveCounts counts;
    const Vec3<float> up{0.0f, Num<float>::from_int(1), 0.0f};
    // Ground corners and each SDF volume's samples: manifolds (eq 99); the
    // points' state is read and written where it lives.
    BodyView<float> env = immovable_view<float>();
    auto loader = [&](int base) {
      return [&, base](int e) {
        const ContactRecord& r = d.imm[k * stride + base + e];
        return load_state(r.a, r.b);
      };
    };
    auto storer = [&](int base) {
      return [&, base](int e, const ContactState<float>& c) {
        d.imm[k * stride + base + e].a = F4{c.j_n, c.j_t.x, c.j_t.y, c.j_t.z};
      };
    };
    if (sc.oriented) {
      // The oriented-box model: the ground manifold, each SDF volume's, then
      // the pairs with immovable bodies (and, Jacobi, with active ones) as
      // manifolds (eq 99), in World<T>'s order; odd passes in reverse.
      // eq 113: each immovable manifold's record, 4 F4 (the environment side zero).
      auto imm_visit = [&](int m, auto&& solve) {
        F4* st = d.conv_imm != nullptr ? d.conv_imm + (static_cast<long>(k) * (sc.ground_slots() / 8 + sc.n_sdf) + m) * 4
                                       : nullptr;
        if (visit_is_converged(st, self, env, sc.P, pass)) return;
        const Vec3<float> v0s = self.v, w0s = self.w;
        const unsigned shortened0 = counts.shortened_steps;
        solve();
        record_visit(st, v0s, w0s, env.v, env.w, self, env, sc.P, counts.shortened_steps - shortened0);
      };
      auto ground = [&] {
        auto corner_point = [&](int c, Vec3<float>& r1, Vec3<float>& r2, Vec3<float>& n, float& penetration) {
          r2 = Vec3<float>{};
          Vec3<float> corner;
          penetration = ground_corner_depth(p, R, h, c, sc.ground_y, corner);
          r1 = corner - p;
          n = up;
          return penetration > -tol;
        };
        imm_visit(0, [&] {
          solve_manifold<8>(self, env, corner_point, loader(0), storer(0), sc.friction, sc.gravity, sc.P, counts);
        });
      };
      auto volume = [&](int v) {
        const int base = sc.ground_slots() + 9 * v;
        auto sample = [&](int s, Vec3<float>& r1, Vec3<float>& r2, Vec3<float>& n, float& penetration) {
          r2 = Vec3<float>{};
          const int g = (k * sc.n_sdf + v) * 9 + s;
          const F4 c1 = ro(d.sdf_c1 + g), c0 = ro(d.sdf_c0 + g);
          r1 = xyz(c1) - p;
          n = xyz(c0);
          penetration = c0.w;
          return c1.w != 0.0f;
        };
        imm_visit(sc.ground_slots() / 8 + v, [&] {
          solve_manifold<9>(self, env, sample, loader(base), storer(base), sc.friction, sc.gravity, sc.P, counts);
        });
      };
      Vec3<float> dv{}, dw{};
      auto pair = [&](int t) {
        const int j = ro(d.lists.nbr + t);
        if (coloured && ro(edge_colour + t) != kNoEdge) return;  // SolveEdgeK's
        PairManifold& rec = d.man[t];
        const int count = rec.count;
        if (count == 0) return;
        const Vec3<float> pj = xyz(ro(b.pos + j));
        const bool lower = i < j;
        const bool jacobi = !coloured && is_awake(ro(b.flags + j));
        BodyView<float> me = self;
        if (jacobi) { me.v = v0; me.w = w0; }
        const BodyView<float> other = coloured ? immovable_view<float>() : view_of(b, j, vin, win);
        const Vec3<float> n = xyz(rec.n);
        const float split =
            jacobi ? jacobi_split(ro(d.dir_count + i), ro(d.dir_count + j), lower ? n : -n, sc.relaxation) : 1.0f;
        BodyView<float> A = pick(lower, me, other), B = pick(lower, other, me);
        F4* conv = d.conv_of_pair(t);
        if (visit_is_converged(conv, A, B, sc.P, pass)) return;  // eq 113
        const Vec3<float> va0 = A.v, wa0 = A.w, vb0 = B.v, wb0 = B.w;
        const Vec3<float> pa = lower ? p : pj, pb = lower ? pj : p;
        auto point = [&](int c, Vec3<float>& r1, Vec3<float>& r2, Vec3<float>& nc, float& penetration) {
          if (c >= count) return false;
          const F4 pt = rec.pt[c];
          r1 = xyz(pt) - pa;
          r2 = xyz(pt) - pb;
          nc = n;
          penetration = pt.w;
          return true;
        };
        auto load = [&](int c) { return load_state(rec.st[c].a, rec.st[c].b); };
        auto store = [&](int c, const ContactState<float>& cs) { rec.st[c].a = F4{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z}; };
        SolveCounts here;
        solve_manifold<kBoxManifoldPoints>(A, B, point, load, store, sc.friction, sc.gravity, split, sc.P, here);
        record_visit(conv, va0, wa0, vb0, wb0, A, B, sc.P, here.shortened_steps);
        const Vec3<float> mv = pick(lower, A.v, B.v), mw = pick(lower, A.w, B.w);
        if (jacobi) {
          dv += mv - v0;
          dw += mw - w0;
        } else {
          self.v = mv;
          self.w = mw;
        }
        if (lower || !jacobi) {
          counts.solver_contacts += here.solver_contacts;
          counts.normal_impulses += here.normal_impulses;
          counts.friction_steps += here.friction_steps;
        }
      };
      const int beg = d.lists.begin(k), end = d.lists.end(k);
      if (!reverse) {
        if (sc.ground_on) ground();
        for (int v = 0; v < sc.n_sdf; ++v) volume(v);
        for (int t = beg; t < end; ++t) pair(t);
      } else {
        for (int t = end - 1; t >= beg; --t) pair(t);
        for (int v = sc.n_sdf - 1; v >= 0; --v) volume(v);
        if (sc.ground_on) ground();
      }
      vout[i] = f4(coloured ? self.v : self.v + dv, 0.0f);  // (no + 0: keeps a -0 component)
      wout[i] = f4(coloured ? self.w : self.w + dw, 0.0f);
      add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
      add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
      add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
      return;
    }
    if (sc.ground_on) {
      auto corner_point = [&](int c, Vec3<float>& r1, Vec3<float>& r2, Vec3<float>& n, float& penetration) {
        r2 = Vec3<float>{};
        Vec3<float> corner;
        penetration = ground_corner_depth(p, R, h, c, sc.ground_y, corner);
        r1 = corner - p;
        n = up;
        return penetration > -tol;
      };
      solve_manifold<8>(self, env, corner_point, loader(0), storer(0), sc.friction, sc.gravity, sc.P, counts);
    }
    for (int v = 0; v < sc.n_sdf; ++v) {
      const int base = sc.ground_slots() + 9 * v;
      auto sample = [&](int s, Vec3<float>& r1, Vec3<float>& r2, Vec3<float>& n, float& penetration) {
        r2 = Vec3<float>{};
        const int g = (k * sc.n_sdf + v) * 9 + s;
        const F4 c1 = ro(d.sdf_c1 + g), c0 = ro(d.sdf_c0 + g);
        r1 = xyz(c1) - p;
        n = xyz(c0);
        penetration = c0.w;
        return c1.w != 0.0f;
      };
      solve_manifold<9>(self, env, sample, loader(base), storer(base), sc.friction, sc.gravity, sc.P, counts);
    }
    Vec3<float> dv{}, dw{};
    const int beg = d.lists.begin(k), end = d.lists.end(k);
    for (int t = beg; t < end; ++t) {
      const int j = ro(d.lists.nbr + t);
      // The coloured solver's edges are SolveEdgeK's; an awake j that is no
      // edge (its list lacks i: cannot happen, the pair test is symmetric) is
      // met as immovable, so that no velocity is read that another thread writes.
      if (coloured && ro(edge_colour + t) != kNoEdge) continue;
      const F4 pj4 = ro(b.pos + j);
      const Vec3<float> pj = xyz(pj4);
      const bool lower = i < j;
      const PairContact<float> pc = canonical_pair(sc, i, p, a, j, pj, xyz(ro(b.aabb + j)));
      const Vec3<float> r1 = pc.point - (lower ? p : pj), r2 = pc.point - (lower ? pj : p);
      ContactState<float> c = load_state(d.pair[t].a, d.pair[t].b);
      // One call of solve_contact for every kind of pair (the threads of a
      // warp stay together): body 1 is the lower index; an immovable j is
      // solved on the body's own current velocity (self), an active j
      // (Jacobi) on both bodies' velocities at the start of the iteration.
      const bool jacobi = !coloured && is_awake(ro(b.flags + j));
      BodyView<float> me = self;
      if (jacobi) { me.v = v0; me.w = w0; }
      const BodyView<float> other = coloured ? immovable_view<float>() : view_of(b, j, vin, win);
      const float split =
          jacobi ? jacobi_split(ro(d.dir_count + i), ro(d.dir_count + j), lower ? pc.n : -pc.n, sc.relaxation) : 1.0f;
      BodyView<float> A = pick(lower, me, other), B = pick(lower, other, me);
      SolveCounts here;
      solve_contact(A, r1, B, r2, pc.n, pc.penetration, c, sc.friction, sc.gravity, split, sc.P, here);
      const Vec3<float> mv = pick(lower, A.v, B.v), mw = pick(lower, A.w, B.w);
      if (jacobi) {
        dv += mv - v0;
        dw += mw - w0;
      } else {
        self.v = mv;
        self.w = mw;
      }
      if (lower || !jacobi) {
        counts.solver_contacts += here.solver_contacts;
        counts.normal_impulses += here.normal_impulses;
        counts.friction_steps += here.friction_steps;
      }
      d.pair[t].a = F4{c.j_n, c.j_t.x, c.j_t.y, c.j_t.z};
    }
    vout[i] = f4(self.v + dv, 0.0f);
    wout[i] = f4(self.w + dw, 0.0f);
    add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
    add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
    add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
  }
};

// One colour of one iteration, a thread per edge: the contact (body 1 = the
// lower index, its owner, as World<T>) solved on both bodies' current
// velocities, which it updates in place (no other edge of the colour touches
// either body); both copies of the contact state are rewritten.
struct SolveEdgeK {
  SolverData d;
  const int* edges;  // this colour's
  const int* mate;
  F4* vel;
  F4* ang;
  Counter* ctr;
  int pass = 0;  // the solver pass (eq 113)
  LS_HD void operator()(int e) const {
    const BodyArrays& b = d.b;
    const SceneConsts& sc = d.sc;
    const int t = ro(edges + e);
    const int i = ro(d.list + t / d.lists.stride), j = ro(d.lists.nbr + t);
    const F4 pi4 = ro(b.pos + i), pj4 = ro(b.pos + j);
    const Vec3<float> p = xyz(pi4), pj = xyz(pj4);
    if (sc.oriented) {  // the pair's manifold (eq 99), i < j
      PairManifold& rec = d.man[t];
      PairManifold& twin = d.man[ro(mate + t)];
      BodyView<float> A = dynamic_view(xyz(vel[i]), xyz(ang[i]), pi4.w, rotation_matrix(quat(ro(b.rot + i))),
                                       xyz(ro(b.inert + i)));
      BodyView<float> B = dynamic_view(xyz(vel[j]), xyz(ang[j]), pj4.w, rotation_matrix(quat(ro(b.rot + j))),
                                       xyz(ro(b.inert + j)));
      const int count = rec.count;
      const Vec3<float> n = xyz(rec.n);
      auto point = [&](int c, Vec3<float>& r1, Vec3<float>& r2, Vec3<float>& nc, float& penetration) {
        if (c >= count) return false;
        const F4 pt = rec.pt[c];
        r1 = xyz(pt) - p;
        r2 = xyz(pt) - pj;
        nc = n;
        penetration = pt.w;
        return true;
      };
      auto load = [&](int c) { return load_state(rec.st[c].a, rec.st[c].b); };
      auto store = [&](int c, const ContactState<float>& cs) {
        const F4 state{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z};
        rec.st[c].a = state;
        twin.st[c].a = state;
      };
      F4* conv = d.conv_of_pair(t);
      if (visit_is_converged(conv, A, B, sc.P, pass)) return;  // eq 113
      const Vec3<float> va0 = A.v, wa0 = A.w, vb0 = B.v, wb0 = B.w;
      SolveCounts counts;
      solve_manifold<kBoxManifoldPoints>(A, B, point, load, store, sc.friction, sc.gravity, sc.P, counts);
      record_visit(conv, va0, wa0, vb0, wb0, A, B, sc.P, counts.shortened_steps);
      if (F4* twin_conv = d.conv_of_pair(ro(mate + t)); conv != nullptr && twin_conv != nullptr)
        for (int q = 0; q < 4; ++q) twin_conv[q] = conv[q];
      vel[i] = f4(A.v, 0.0f);
      ang[i] = f4(A.w, 0.0f);
      vel[j] = f4(B.v, 0.0f);
      ang[j] = f4(B.w, 0.0f);
      add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
      add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
      add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
      return;
    }
    const PairContact<float> pc = canonical_pair(sc, i, p, xyz(ro(b.aabb + i)), j, pj, xyz(ro(b.aabb + j)));  // i < j
    BodyView<float> A = dynamic_view(xyz(vel[i]), xyz(ang[i]), pi4.w, rotation_matrix(quat(ro(b.rot + i))),
                                     xyz(ro(b.inert + i)));
    BodyView<float> B = dynamic_view(xyz(vel[j]), xyz(ang[j]), pj4.w, rotation_matrix(quat(ro(b.rot + j))),
                                     xyz(ro(b.inert + j)));
    ContactState<float> cs = load_state(d.pair[t].a, d.pair[t].b);
    SolveCounts counts;
    solve_contact(A, pc.point - p, B, pc.point - pj, pc.n, pc.penetration, cs, sc.friction, sc.gravity, 1.0f, sc.P,
                  counts);
    vel[i] = f4(A.v, 0.0f);
    ang[i] = f4(A.w, 0.0f);
    vel[j] = f4(B.v, 0.0f);
    ang[j] = f4(B.w, 0.0f);
    const F4 state{cs.j_n, cs.j_t.x, cs.j_t.y, cs.j_t.z};
    d.pair[t].a = state;
    d.pair[ro(mate + t)].a = state;
    add_counter(&ctr[kCSolverContacts], counts.solver_contacts);
    add_counter(&ctr[kCNormalImpulses], counts.normal_impulses);
    add_counter(&ctr[kCFrictionSteps], counts.friction_steps);
  }
};

// ---------------------------------------------------------------------------
// Stage 6: settling sweeps. World<T> settles supported bodies lowest first
// (height, then index), so eq 75 sees a lower support's settled velocity and
// a higher one's unsettled velocity. Sweep k reads the supports' values of
// sweep k-1 (sin; sweep 0 reads the solver's result) and writes its own;
// after as many sweeps as the longest chain of supports, the result is
// World<T>'s. The last sweep, which also settles the angular velocity (eqs
// 64-74), runs in CorrectIntegrateK.
struct SettleSweep {
  const int* support_idx;
  const F4* support_n;
  const F4* vpost;  // solver result
  const F4* sin;    // the previous sweep's (sweep 0: vpost)
  bool relative = false;  // the oriented-box model: eq 77 relative to the support's velocity
  const int* over = nullptr;  // the oriented-box model: per body, over its support (eq 112); one that is not does not settle
  const int* leaning = nullptr;  // the oriented-box model: per body, it leans (eq 115): not righted
  const float* limit = nullptr;  // per body: eq 77 damps a relative speed up to this (eq 116)
  LS_HD bool settles(int i) const { return over == nullptr || ro(over + i) != 0; }
  LS_HD bool leans(int i) const { return leaning != nullptr && ro(leaning + i) != 0; }
  // Eqs 75, 77 on v (the solver's velocity of body i); returns |v| after eq 75
  // (what righting uses), or a negative value for a body with no support
  // (v unchanged). `final`: the result is World<T>'s (it read no support's
  // settled velocity, or a final one: a sweep's output carries w = 1 when
  // final, and the solver's velocities w = 0).
  LS_HD float linear(const BodyArrays& b, int i, const Params<float>& P, Vec3<float>& v, bool& final) const {
    final = true;
    const int s = ro(support_idx + i);
    if (s == kNoSupport || !settles(i)) return -1.0f;
    Vec3<float> v_s{};
    if (s >= 0 && is_awake(ro(b.flags + s))) {
      if (settles_before(ro(b.pos + s).y, s, ro(b.pos + i).y, i) && ro(support_idx + s) != kNoSupport && settles(s)) {
        const F4 settled = ro(sin + s);
        v_s = xyz(settled);
        final = settled.w != 0.0f;
      } else {
        v_s = xyz(ro(vpost + s));
      }
    }
    const F4 sn = ro(support_n + i);  // the support normal, w: the support gap
    return settle_linear_velocity(v, v_s, xyz(sn), sn.w, P, relative,
                                  limit == nullptr ? P.settle_speed : ro(limit + i));  // eqs 75, 77, 116
  }
};

// One settling sweep but the last: the linear velocity of every supported
// body, w = 1 where final. With `unsettled`, counts the bodies whose result
// is not final yet (an integer atomic, order-free).
struct SettleK {
  const int* list;
  BodyArrays b;
  SceneConsts sc;
  SettleSweep sweep;
  F4* sout;
  int* unsettled;
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    Vec3<float> v = xyz(ro(sweep.vpost + i));
    bool final = true;
    if (sweep.linear(b, i, sc.P, v, final) >= 0.0f) sout[i] = f4(v, final ? 1.0f : 0.0f);
    if (unsettled != nullptr) add_to(unsettled, final ? 0 : 1);
  }
};

// ---------------------------------------------------------------------------
// Stages 6 (the last settling sweep), 7-8: the final velocity (the
// solver's, settled when settling is on: eqs 75, 77, 64-74), position
// correction (eqs 63, 89) from the contacts of the frame (measured at the
// start-of-frame positions), then integration (eqs 2, 7-10). Poses go to
// per-slot buffers, committed by the next kernel, since other threads read
// the start-of-frame positions.
struct CorrectIntegrateK {
  const int* list;
  BodyArrays b;
  SceneConsts sc;
  NeighbourLists lists;
  const F4* sdf_c0;
  const F4* sdf_c1;
  const ContactRecord* imm;   // the contacts' solver state: b.y is e_eff (eq 76); a bouncing contact is not corrected
  const ContactRecord* pair;
  const F4* vpost;  // the solver's velocities
  const F4* wpost;
  bool settle;       // settling on: the last sweep
  SettleSweep sweep;
  F4* p_out;
  F4* q_out;
  Counter* ctr;
  F4* p_world = nullptr;  // oriented-box model: the position after the world's corrections, per slot (eq 110 goes on)
  LS_HD void operator()(int k) const {
    const int i = ro(list + k);
    const F4 pi4 = ro(b.pos + i);
    const Vec3<float> p0 = xyz(pi4), a = xyz(ro(b.aabb + i));
    const float inv_self = pi4.w;
    Vec3<float> p = p0, dummy{};
    const Quat<float> q0 = quat(ro(b.rot + i));
    Vec3<float> vf = xyz(ro(vpost + i)), wf = xyz(ro(wpost + i));
    if (settle) {
      bool final = true;
      const float speed = sweep.linear(b, i, sc.P, vf, final);  // eqs 75, 77
      if (speed >= 0.0f) {
        // eqs 64-74: the AABB model damps by the regimes on every support; the
        // oriented-box model on an immovable one only (a support body that is
        // not awake, the ground, an SDF volume).
        const int s = ro(sweep.support_idx + i);
        const bool movable = sc.oriented && s >= 0 && is_awake(ro(b.flags + s));
        if (movable)  // eqs 72-74 relative to the support's spin as the solver left it
          wf = settle_angular_velocity_on(wf, xyz(ro(wpost + s)), rotation_matrix(q0), xyz(ro(sweep.support_n + i)),
                                          speed, sweep.leans(i), sc.P);
        else
          wf = settle_angular_velocity(wf, rotation_matrix(q0), xyz(ro(sweep.support_n + i)), speed, true,
                                       sweep.leans(i), sc.P);
        add_counter(&ctr[kCSettlingBodies], 1u);
      }
    }
    b.vel[i] = f4(vf, 0.0f);
    b.ang[i] = f4(wf, 0.0f);
    unsigned corrections = 0;
    const float slop = sc.P.slop, percent = sc.P.baumgarte, tol = sc.immovable_tol(i);  // eqs 97, 107
    // eq 89's order: the body pairs first, then the ground and SDF contacts
    // with their penetration less what the pairs moved this body along n.
    const int beg = lists.begin(k), end = sc.oriented ? beg : lists.end(k);  // oriented: eq 110 (PairCorrectK)
    for (int t = beg; t < end; ++t) {
      const int j = ro(lists.nbr + t);
      const F4 pj4 = ro(b.pos + j);
      const bool j_awake = is_awake(ro(b.flags + j));
      const float inv_j = j_awake ? pj4.w : 0.0f;
      const bool lower = i < j;
      const PairContact<float> c = canonical_pair(sc, i, p0, a, j, xyz(pj4), xyz(ro(b.aabb + j)));
      const float inv_a = lower ? inv_self : inv_j, inv_b = lower ? inv_j : inv_self;
      if (ro(&pair[t].b).y > 0.0f || (inv_a == 0.0f && inv_b == 0.0f)) continue;
      if (lower) baumgarte_correction(p, dummy, c.n, c.penetration, inv_a, inv_b, slop, percent);
      else baumgarte_correction(dummy, p, c.n, c.penetration, inv_a, inv_b, slop, percent);
      if (lower || !j_awake) ++corrections;
    }
    if (sc.ground_on) {  // the deepest corner (first on ties, a resting one before a bouncing one) carries the correction
      const Mat3<float> R = rotation_matrix(q0);
      const Vec3<float> h = xyz(ro(b.half + i));
      auto corner_depth = [&](int c, float& depth) {
        Vec3<float> corner;
        depth = ground_corner_depth(p0, R, h, c, sc.ground_y, corner);
        return depth > -tol;
      };
      auto bounces = [&](int c) { return ro(&imm[k * sc.imm_stride() + c].b).y > 0.0f; };
      float deepest_depth = 0.0f;
      const int deepest = ground_correction_point(8, corner_depth, bounces, deepest_depth);  // eq 89's tie rule
      if (deepest >= 0 && !bounces(deepest) && inv_self != 0.0f) {
        const Vec3<float> up{0.0f, Num<float>::from_int(1), 0.0f};
        baumgarte_correction(p, dummy, up, deepest_depth - dot(p - p0, up), inv_self, 0.0f, slop, percent);
        ++corrections;
      }
    }
    for (int v = 0; v < sc.n_sdf; ++v) {  // per volume, the deepest sample
      int deepest = -1, deepest_s = 0;
      for (int s = 0; s < 9; ++s) {
        const int g = (k * sc.n_sdf + v) * 9 + s;
        if (sdf_c1[g].w == 0.0f) continue;
        if (deepest < 0 || sdf_c0[g].w > sdf_c0[deepest].w) { deepest = g; deepest_s = s; }
      }
      if (deepest < 0 || imm[k * sc.imm_stride() + sc.ground_slots() + 9 * v + deepest_s].b.y > 0.0f ||
          inv_self == 0.0f)
        continue;
      const F4 c0 = sdf_c0[deepest];
      baumgarte_correction(p, dummy, xyz(c0), c0.w - dot(p - p0, xyz(c0)), inv_self, 0.0f, slop, percent);
      ++corrections;
    }
    if (p_world != nullptr) {  // the pairs' corrections (eq 110) and the integration follow
      p_world[k] = f4(p, inv_self);
      add_counter(&ctr[kCCorrections], corrections);
      return;
    }
    Quat<float> q = q0;
    integrate_pose(p, q, vf, wf, sc.P);  // eqs 2, 7-10
    p_out[k] = f4(p, inv_self);
    q_out[k] = f4(q);
    add_counter(&ctr[kCCorrections], corrections);
  }
};

// Error codes of the finite check (World<T>::check_finite's order).
inline constexpr int kErrPosition = 0, kErrVelocity = 1, kErrAngular = 2, kErrOrientation = 3;

// Stage 8 commit and stage 9: new pose, derived AABB (eq 31), sleep update
// (eqs 78-80); keep[k] = 1 for a body still awake. A non-finite awake body
// records 4 i + code in *error (the lowest wins, as World<T> reports the
// lowest index).
struct CommitSleepK {
  const int* list;
  BodyArrays b;
  SceneConsts sc;
  const F4* p_in;
  const F4* q_in;
  const int* support_idx;
  const F4* support_n;
  int frame;
  int* keep;
  int* error;
  Counter* ctr;
  int* ready = nullptr;  // oriented-box model: per slot, 1 when its counter reached sleep_frames (eq 109 decides)
  const int* over = nullptr;  // oriented-box model: per body, over its support (eq 112)
  const int* leaning = nullptr;  // oriented-box model: per body, it leans (eq 115): its alignment is not asked
  const int* can_rest = nullptr;  // per body: statics lets it rest (eqs 116, 117)
  LS_HD void operator()(int k) const {
    const int i = list[k];
    const F4 p4 = p_in[k];
    const Quat<float> q = quat(q_in[k]);
    b.pos[i] = p4;
    b.rot[i] = q_in[k];
    const Mat3<float> R = rotation_matrix(q);
    const Vec3<float> a = rotated_half_extents(R, xyz(b.half[i]));  // eq 31
    b.aabb[i] = f4(a, Num<float>::max(a.x, Num<float>::max(a.y, a.z)));
    Vec3<float> v = xyz(b.vel[i]), w = xyz(b.ang[i]);
    bool asleep = false;
    if (sc.sleep) {
      int counter = b.sleep_counter[i];
      const bool supported = support_idx[i] != kNoSupport;
      const Vec3<float> up = supported ? xyz(support_n[i]) : Vec3<float>{0.0f, Num<float>::from_int(1), 0.0f};
      const bool is_over = over == nullptr || over[i] != 0;  // eq 112: one not over its support may be tipping
      const bool leaning_i = leaning != nullptr && leaning[i] != 0;  // eq 115
      asleep = update_sleep(v, w, counter, supported, is_over, leaning_i, !sc.oriented, can_rest == nullptr || can_rest[i] != 0, R, up,
                            length(xyz(b.half[i])),
                            sc.P);
      b.sleep_counter[i] = counter;
      if (ready != nullptr) ready[k] = counter >= sc.P.sleep_frames ? 1 : 0;
      b.vel[i] = f4(v, 0.0f);
      b.ang[i] = f4(w, 0.0f);
      if (asleep) {
        b.flags[i] = static_cast<std::uint8_t>(b.flags[i] | kFlagAsleep);
        b.sleep_frame[i] = frame;
      }
    }
    keep[k] = asleep ? 0 : 1;
    if (!asleep) {
      auto fin = [](const Vec3<float>& x) { return Num<float>::finite(x.x) && Num<float>::finite(x.y) && Num<float>::finite(x.z); };
      const int code = !fin(xyz(p4)) ? kErrPosition : !fin(v) ? kErrVelocity : !fin(w) ? kErrAngular
                     : !(Num<float>::finite(q.w) && Num<float>::finite(q.x) && Num<float>::finite(q.y) && Num<float>::finite(q.z)) ? kErrOrientation
                     : -1;
      if (code >= 0) store_min(error, 4 * i + code);
    }
    if (sc.sleep) add_counter(&ctr[kCSleepUpdates], 1u);
  }
};

struct SetIntK {
  int* target;
  int value;
  LS_HD void operator()(int) const { *target = value; }
};

// Stream compaction: out[scan[k]] = in[k] where keep[k].
struct ScatterK {
  const int* in;
  const int* keep;
  const int* scan;
  int* out;
  LS_HD void operator()(int k) const {
    if (keep[k] != 0) out[scan[k]] = in[k];
  }
};

}  // namespace lockstep::gpu
