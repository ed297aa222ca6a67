// The coloured solver's schedule (gpu/src/colouring.hpp): init_edge (as
// ContactsK calls it) and ColourRoundK on random contact graphs, run as the
// host build runs them.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <vector>

#include "colouring.hpp"

namespace lockstep::gpu {
namespace {

// A contact graph as the pipeline holds it: the awake bodies have slots (in
// ascending index order) with sorted neighbour lists; sleeping bodies appear
// only in their awake neighbours' lists.
struct Graph {
  int n = 0;
  std::vector<F4> pos;
  std::vector<std::uint8_t> flags;
  std::vector<int> list, slot_of, nbr, count;
  int stride = 1;
};

Graph random_graph() {
  Graph g;
  g.n = *rc::gen::inRange(2, 40);
  const int percent = *rc::gen::inRange(5, 60);
  for (int i = 0; i < g.n; ++i) {
    // Heights on a coarse lattice, so that bands tie and the hash decides.
    g.pos.push_back(F4{0.0f, static_cast<float>(*rc::gen::inRange(0, 12)) * 0.5f, 0.0f, 1.0f});
    g.flags.push_back(*rc::gen::inRange(0, 5) == 0 ? kFlagAsleep : 0);
  }
  std::vector<std::vector<int>> adj(static_cast<std::size_t>(g.n));
  for (int i = 0; i < g.n; ++i)
    for (int j = i + 1; j < g.n; ++j)
      if (*rc::gen::inRange(0, 100) < percent) {
        adj[static_cast<std::size_t>(i)].push_back(j);
        adj[static_cast<std::size_t>(j)].push_back(i);
      }
  g.slot_of.assign(static_cast<std::size_t>(g.n), -1);
  for (int i = 0; i < g.n; ++i)
    if (is_awake(g.flags[static_cast<std::size_t>(i)])) {
      g.slot_of[static_cast<std::size_t>(i)] = static_cast<int>(g.list.size());
      g.list.push_back(i);
      g.stride = std::max(g.stride, static_cast<int>(adj[static_cast<std::size_t>(i)].size()));
    }
  g.nbr.assign(g.list.size() * static_cast<std::size_t>(g.stride), -1);
  for (std::size_t k = 0; k < g.list.size(); ++k) {
    const auto& a = adj[static_cast<std::size_t>(g.list[k])];  // ascending
    std::copy(a.begin(), a.end(), g.nbr.begin() + static_cast<std::ptrdiff_t>(k) * g.stride);
    g.count.push_back(static_cast<int>(a.size()));
  }
  return g;
}

struct Colouring {
  std::vector<int> mate, colour, edges;  // edges: the owner entries by colour
  std::vector<int> offset;               // colour c's are edges[offset[c], offset[c + 1])
  int colours = 0;
};

// The pipeline's colour_edges with each kernel's threads in the given order.
Colouring colour(Graph& g, bool reversed) {
  const int slots = static_cast<int>(g.list.size());
  const NeighbourLists lists{g.nbr.data(), g.count.data(), g.stride};
  const float inv_cell = 0.5f;  // H = 1 m: bands of 1 / kBandsPerExtent m
  const std::size_t entries = g.nbr.size() + 1;
  Colouring c;
  c.mate.assign(entries, -1);
  c.colour.assign(entries, 0);
  std::vector<unsigned long long> key(entries);
  std::vector<int> pending[2] = {std::vector<int>(entries), std::vector<int>(entries)}, edges(entries, -1);
  std::vector<int> round_end(entries + 1, 0);
  int pending_count[3] = {0, 0, 0}, placed[3] = {0, 0, 0};
  auto launch = [&](int n, const auto& f) {
    for (int t = 0; t < n; ++t) f(reversed ? n - 1 - t : t);
  };
  EdgeArrays<float> arrays;
  arrays.slot_of = g.slot_of.data();
  arrays.inv_cell = &inv_cell;
  arrays.mate = c.mate.data();
  arrays.key = key.data();
  arrays.word = c.colour.data();
  arrays.pending = pending[0].data();
  arrays.pending_count = &pending_count[0];
  launch(slots, [&](int k) {  // ContactsK's part: every entry of slot k
    const int i = g.list[static_cast<std::size_t>(k)];
    for (int t = lists.begin(k); t < lists.end(k); ++t) {
      const int j = g.nbr[static_cast<std::size_t>(t)];
      init_edge(arrays, lists, i, t, j, is_awake(g.flags[static_cast<std::size_t>(j)]),
                g.pos[static_cast<std::size_t>(i)].y, g.pos[static_cast<std::size_t>(j)].y);
    }
  });
  int round = 0;
  for (; pending_count[round % 3] > 0 && round < 10000; ++round)
    launch(slots, ColourRoundK{g.list.data(), lists, g.slot_of.data(), c.mate.data(), key.data(), c.colour.data(),
                               round, pending_count, placed, round_end.data(), pending[round % 2].data(),
                               pending[(round + 1) % 2].data(), edges.data(), slots});
  c.colours = round;
  c.offset.assign(1, 0);
  for (int r = 0; r < round; ++r)  // the last round's end: where it started plus what it placed
    c.offset.push_back(r + 1 < round ? round_end[static_cast<std::size_t>(r)] : c.offset.back() + placed[r % 3]);
  c.edges.assign(edges.begin(), edges.begin() + c.offset.back());
  return c;
}

// Every contact between two awake bodies is an edge with one colour on both
// copies; no two edges of a colour share a body; of two edges that share a
// body, the one first in the order (lower band, then hash) has the lower
// colour; the colours are 0 .. colours-1; the edge list holds each edge once,
// under its colour; the colours do not depend on the order of the threads.
RC_GTEST_PROP(Colouring, IsAMatchingPerColourInTheEdgesOrder, ()) {
  Graph g = random_graph();
  const Colouring c = colour(g, false);
  RC_ASSERT(colour(g, true).colour == c.colour);
  for (int k = 0; k < c.colours; ++k)
    for (int e = c.offset[static_cast<std::size_t>(k)]; e < c.offset[static_cast<std::size_t>(k) + 1]; ++e)
      RC_ASSERT(c.colour[static_cast<std::size_t>(c.edges[static_cast<std::size_t>(e)])] == k);
  std::vector<int> listed = c.edges;
  std::sort(listed.begin(), listed.end());
  RC_ASSERT(std::adjacent_find(listed.begin(), listed.end()) == listed.end());
  struct Edge { int lo, hi, colour; unsigned long long key; };
  std::vector<Edge> edges;
  for (std::size_t k = 0; k < g.list.size(); ++k) {
    const int i = g.list[k];
    for (int t = static_cast<int>(k) * g.stride; t < static_cast<int>(k) * g.stride + g.count[k]; ++t) {
      const auto ut = static_cast<std::size_t>(t);
      const int j = g.nbr[ut];
      if (!is_awake(g.flags[static_cast<std::size_t>(j)])) {
        RC_ASSERT(c.colour[ut] == kNoEdge);
        continue;
      }
      const int m = c.mate[ut];
      RC_ASSERT(m >= 0);
      RC_ASSERT(g.nbr[static_cast<std::size_t>(m)] == i);
      RC_ASSERT(c.colour[static_cast<std::size_t>(m)] == c.colour[ut]);
      RC_ASSERT(c.colour[ut] >= 0);
      RC_ASSERT(c.colour[ut] < c.colours);
      if (i < j) RC_ASSERT(std::binary_search(listed.begin(), listed.end(), t));
      if (i < j)
        edges.push_back({i, j, c.colour[ut],
                         edge_key(i, j, g.pos[static_cast<std::size_t>(i)].y, g.pos[static_cast<std::size_t>(j)].y,
                                  static_cast<float>(kBandsPerExtent))});
    }
  }
  std::vector<bool> used(static_cast<std::size_t>(c.colours), false);
  RC_ASSERT(listed.size() == edges.size());
  for (const Edge& e : edges) used[static_cast<std::size_t>(e.colour)] = true;
  RC_ASSERT(std::all_of(used.begin(), used.end(), [](bool u) { return u; }));
  for (std::size_t a = 0; a < edges.size(); ++a)
    for (std::size_t b = a + 1; b < edges.size(); ++b) {
      const Edge &e = edges[a], &f = edges[b];
      if (e.lo != f.lo && e.lo != f.hi && e.hi != f.lo && e.hi != f.hi) continue;  // no shared body
      RC_ASSERT(e.colour != f.colour);
      const bool e_first = EdgeKey{e.key, e.lo, e.hi}.before(EdgeKey{f.key, f.lo, f.hi});
      RC_ASSERT(e_first == (e.colour < f.colour));
    }
}

// A chain of contacts one above the other (a stack) gets one colour per
// contact, bottom-up, whatever the body indices: the solver carries the
// support up the stack in one iteration, as World<T> does for a stack built
// bottom-up.
TEST(Colouring, AStackIsColouredBottomUp) {
  Graph g;
  g.n = 6;
  const int order[6] = {3, 0, 5, 1, 4, 2};  // body order[h] is h-th from the ground
  g.pos.resize(6);
  for (int h = 0; h < 6; ++h) g.pos[static_cast<std::size_t>(order[h])] = F4{0.0f, 0.5f + static_cast<float>(h), 0.0f, 1.0f};
  g.flags.assign(6, 0);
  g.stride = 2;
  g.slot_of.resize(6);
  for (int i = 0; i < 6; ++i) {
    g.list.push_back(i);
    g.slot_of[static_cast<std::size_t>(i)] = i;
    int h = 0;
    while (order[h] != i) ++h;
    std::vector<int> a;
    if (h > 0) a.push_back(order[h - 1]);
    if (h < 5) a.push_back(order[h + 1]);
    std::sort(a.begin(), a.end());
    a.resize(2, -1);
    g.nbr.insert(g.nbr.end(), a.begin(), a.end());
    g.count.push_back(h == 0 || h == 5 ? 1 : 2);
  }
  const Colouring c = colour(g, false);
  EXPECT_EQ(c.colours, 5);
  for (int h = 0; h < 5; ++h) {  // the contact between heights h and h + 1
    const int i = order[h], j = order[h + 1];
    const auto k = static_cast<std::size_t>(i);
    const int t = g.nbr[k * 2] == j ? static_cast<int>(k) * 2 : static_cast<int>(k) * 2 + 1;
    EXPECT_EQ(c.colour[static_cast<std::size_t>(t)], h) << "contact " << h;
  }
}

}  // namespace
}  // namespace lockstep::gpu
