// The solver's order (eqs 125-127, lockstep/physics/solve_order.hpp): height
// bands inside Q16.16 at any height, the colour rule against its definition
// (the longest chain of edges before it in key order), and what the order
// promises the solver: no two edges of a colour share a body.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "lockstep/fixed/q16_vec.hpp"
#include "lockstep/physics/solve_order.hpp"

namespace lockstep {
namespace {

// eq 125: a unit cube's bands are a quarter of its half extent (H = 0.5 m:
// 1/band = 8); float's band is the floor of the mean height times 8.
TEST(SolveOrderTest, Eq125BandsOfAQuarterExtent) {
  const float inv = band_inverse(0.5f);
  EXPECT_EQ(inv, 8.0f);
  EXPECT_EQ(edge_band(0.5f, 1.5f, inv), 8);      // mean 1.0 m
  EXPECT_EQ(edge_band(-0.5f, -0.25f, inv), -3);  // mean -0.375 m: floor(-3)
  EXPECT_EQ(edge_band(0.0f, 0.2f, inv), 0);
  // tiny bodies: the 1/64 m floor of the cell
  EXPECT_EQ(band_inverse(0.001f), 512.0f);
  // the same in Q16.16, exactly
  const Q16 q = band_inverse(Q16::from_double(0.5));
  EXPECT_EQ(q, Q16::from_int(8));
  EXPECT_EQ(edge_band(Q16::from_double(0.5), Q16::from_double(1.5), q), 8);
}

// eq 125 at the edges of Q16.16: two bodies near +-32000 m under bands of
// 1/512 m would overflow the sum and the product; the halves and the clamp
// keep every step in range, so no fault is raised and the band is clamped.
TEST(SolveOrderTest, Eq125NoQ16OverflowAtAnyHeight) {
  Num<Q16>::take_faults();
  const Q16 inv = band_inverse(Q16::from_double(0.001));
  const Q16 top = Q16::from_int(32000), bottom = Q16::from_int(-32000);
  const int hi = edge_band(top, top, inv), lo = edge_band(bottom, bottom, inv);
  EXPECT_EQ(Num<Q16>::take_faults(), 0u);
  EXPECT_GT(hi, 16000);
  EXPECT_LE(hi, 16383);
  EXPECT_LT(lo, -16000);
  EXPECT_GE(lo, -16384);
  EXPECT_EQ(edge_band(Q16::from_int(100), Q16::from_int(101), Q16::from_double(0.25)), 25);  // 1/band <= 1: no clamp below 16383 m
}

// eq 126: the band orders first (lower first, negative bands included), the
// hash then spreads; ties by (lo, hi).
TEST(SolveOrderTest, Eq126BandThenHashThenIndices) {
  const EdgeKey low{edge_key(7, 9, -2), 7, 9}, high{edge_key(1, 2, 5), 1, 2};
  EXPECT_TRUE(low.before(high));
  EXPECT_FALSE(high.before(low));
  const EdgeKey a{42, 1, 5}, b{42, 1, 6};
  EXPECT_TRUE(a.before(b));
  EXPECT_FALSE(a.before(a));
}

struct Edge {
  EdgeKey key;
  int colour = -1;
};

// Colours by the sweep World<T> runs (edges in key order, eq 127's rule).
void colour_by_sweep(std::vector<Edge>& edges, int bodies) {
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key.before(y.key); });
  std::vector<int> top(static_cast<std::size_t>(bodies), -1);
  for (Edge& e : edges) {
    int& a = top[static_cast<std::size_t>(e.key.lo)];
    int& b = top[static_cast<std::size_t>(e.key.hi)];
    e.colour = edge_colour(a, b);
    a = b = e.colour;
  }
}

// eq 127 by its definition: 1 + the largest colour of the earlier edges it
// shares a body with (quadratic), and by the GPU engine's rounds
// (Jones-Plassmann: round r colours every uncoloured edge that goes before
// all the still-uncoloured edges it shares a body with).
RC_GTEST_PROP(SolveOrderProp, Eq127SweepIsTheLongestChainAndTheRounds, ()) {
  const int bodies = *rc::gen::inRange(2, 40);
  const int count = *rc::gen::inRange(0, 120);
  std::vector<Edge> edges;
  for (int k = 0; k < count; ++k) {
    int lo = *rc::gen::inRange(0, bodies), hi = *rc::gen::inRange(0, bodies);
    if (lo == hi) continue;
    if (lo > hi) std::swap(lo, hi);
    bool seen = false;
    for (const Edge& e : edges) seen = seen || (e.key.lo == lo && e.key.hi == hi);
    if (seen) continue;
    const int band = *rc::gen::inRange(-3, 4);  // few bands: many ties of the band
    edges.push_back({EdgeKey{edge_key(lo, hi, band), lo, hi}});
  }
  colour_by_sweep(edges, bodies);
  auto share = [](const Edge& x, const Edge& y) {
    return x.key.lo == y.key.lo || x.key.lo == y.key.hi || x.key.hi == y.key.lo || x.key.hi == y.key.hi;
  };
  // The definition.
  for (std::size_t i = 0; i < edges.size(); ++i) {
    int expect = 0;
    for (std::size_t j = 0; j < i; ++j)
      if (share(edges[i], edges[j])) expect = std::max(expect, edges[j].colour + 1);
    RC_ASSERT(edges[i].colour == expect);
  }
  // What the solver relies on.
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j)
      if (share(edges[i], edges[j])) RC_ASSERT(edges[i].colour < edges[j].colour);
  // The GPU engine's rounds.
  std::vector<int> word(edges.size(), -1);
  for (int round = 0;; ++round) {
    std::vector<int> now = word;
    bool pending = false;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (word[i] != -1) continue;
      pending = true;
      bool first = true;
      for (std::size_t j = 0; j < edges.size() && first; ++j)
        if (j != i && word[j] == -1 && share(edges[i], edges[j]) && edges[j].key.before(edges[i].key)) first = false;
      if (first) now[i] = round;
    }
    word = now;
    if (!pending) break;
  }
  for (std::size_t i = 0; i < edges.size(); ++i) RC_ASSERT(word[i] == edges[i].colour);
}

// A stack: its contacts are one band or more apart, bottom-up, so they get
// one colour each in that order (the support climbs in one pass).
TEST(SolveOrderTest, Eq127AStackIsColouredBottomUp) {
  const float inv = band_inverse(0.5f);
  std::vector<Edge> edges;
  for (int k = 0; k + 1 < 10; ++k)
    edges.push_back({EdgeKey{edge_key(k, k + 1, 0.5f + static_cast<float>(k), 1.5f + static_cast<float>(k), inv), k, k + 1}});
  std::reverse(edges.begin(), edges.end());
  colour_by_sweep(edges, 10);
  for (const Edge& e : edges) EXPECT_EQ(e.colour, e.key.lo);
}

}  // namespace
}  // namespace lockstep
