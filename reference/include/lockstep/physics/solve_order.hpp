// The solver's order (docs/SPEC.md 7.2 step 5, eqs 125-127), host and device
// (LS_HD): which contacts a pass visits together and in what order. World<T>
// (reference/src/contact_solver.hpp, on any number of threads) and the GPU
// engine (gpu/src/colouring.hpp) call these functions; a pass is
//   1. every awake body's visits of immovable things (its ground manifold,
//      each SDF volume's, then its pairs with static or sleeping bodies by
//      the other body's index), each body on its own velocity: bodies in any
//      order, in parallel;
//   2. the colours of the contact graph's edges (pairs of two awake bodies)
//      in ascending order, the edges of one colour in any order, in parallel:
//      no two share a body.
// Odd passes of the oriented-box model run backwards: the colours
// descending, then each body's visits in reverse.
#pragma once
#include "lockstep/hd.hpp"
#include "lockstep/math/num.hpp"

namespace lockstep {

// eq 125: an edge's height band is the mean height of its two bodies in
// bands of H / kBandsPerExtent, H the largest AABB half extent (eq 31) of
// the bodies awake when the frame's contacts are found (after eq 108's wake).
inline constexpr int kBandsPerExtent = 4;

// eq 125's 1 / band: kBandsPerExtent / H as 2 kBandsPerExtent / max(2 H,
// 1/64 m) (the floor keeps tiny bodies from making bands tiny; the GPU
// engine's awake-grid cell is the same max(2 H, 1/64)).
template <class T>
LS_HD T band_inverse(const T& largest_half) {
  const T cell = Num<T>::max(largest_half * Num<T>::from_int(2), Num<T>::from_double(1.0 / 64.0));
  return (Num<T>::from_int(1) / cell) * Num<T>::from_int(2 * kBandsPerExtent);
}

// eq 125: the band of an edge, floor(clamp(m, -L, L) / band) with m =
// y_lo / 2 + y_hi / 2 (halves first: no sum to overflow Q16.16) and L =
// 16383 band heights (at most 16383 m when a band is over 1 m), so the
// product stays inside Q16.16; a NaN height (float) is band 0, the frame's
// finite check stops the run.
template <class T>
LS_HD int edge_band(const T& y_lo, const T& y_hi, const T& inv_band) {
  const T half = Num<T>::from_double(0.5);
  const T m = y_lo * half + y_hi * half;
  if (!(m == m)) return 0;
  const T one = Num<T>::from_int(1);
  const T limit = Num<T>::from_int(16383);
  const T reach = inv_band > one ? limit / inv_band : limit;
  return Num<T>::floor_int(Num<T>::max(-reach, Num<T>::min(m, reach)) * inv_band);
}

// eq 126: the edge's place in the order, lowest first: its band, then a hash
// of the two body indices (spreading one band's edges over few colours),
// then (lo, hi). Unsigned arithmetic only (wraps by definition).
struct EdgeKey {
  unsigned long long key;  // (band + 2^31) << 32 | hash
  int lo, hi;              // the bodies, lo < hi
  LS_HD bool before(const EdgeKey& o) const {
    if (key != o.key) return key < o.key;
    return lo != o.lo ? lo < o.lo : hi < o.hi;
  }
};
LS_HD inline unsigned long long edge_key(int lo, int hi, int band) {
  unsigned x = static_cast<unsigned>(lo) * 0x9E3779B1u ^ static_cast<unsigned>(hi) * 0x85EBCA77u;
  x ^= x >> 15;
  x *= 0x2C1B3C6Du;
  x ^= x >> 12;
  const unsigned biased = static_cast<unsigned>(band) + 0x80000000u;
  return (static_cast<unsigned long long>(biased) << 32) | x;
}
template <class T>
LS_HD unsigned long long edge_key(int lo, int hi, const T& y_lo, const T& y_hi, const T& inv_band) {
  return edge_key(lo, hi, edge_band(y_lo, y_hi, inv_band));
}

// eq 127: an edge's colour is one more than the largest colour of the edges
// before it in key order that share a body with it (0 when none): the
// longest chain of such edges ending at it. So edges of one colour share no
// body, and of two edges that share a body the first in key order has the
// lower colour (a stack's contacts get one colour each, bottom-up). Visiting
// the edges in key order, `top_lo` and `top_hi` are the largest colours its
// two bodies have so far (-1: none). The GPU engine reaches the same colours
// by rounds (Jones-Plassmann): round r colours the edges that go before every
// edge they share a body with that was uncoloured when the round began.
LS_HD inline int edge_colour(int top_lo, int top_hi) { return (top_lo > top_hi ? top_lo : top_hi) + 1; }

}  // namespace lockstep
