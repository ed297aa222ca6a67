// Everything the GPU engine's following frames read from the previous ones,
// on the host (docs/SNAPSHOTS.md "The GPU engine"): what Pipeline::save
// downloads and Pipeline::load uploads, by the same code on either backend;
// gpu_snapshot.cpp turns it into the snapshot's bytes and back.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "lockstep/gpu/soa.hpp"
#include "lockstep/world.hpp"

namespace lockstep::gpu {

inline constexpr int kSnapshotManifoldPoints = 4;  // a pair's points (kBoxManifoldPoints)

template <class T>
struct GpuState {
  using F4 = T4<T>;
  int frame = 0;
  StageCounters counters;
  // Per body (scene order).
  std::vector<F4> pos, rot, aabb, vel, ang;  // pos.w (inverse mass) and aabb are as the engine keeps them
  std::vector<std::uint8_t> flags;
  std::vector<int> sleep_counter, sleep_frame;
  std::vector<T> grow;                       // oriented-box model: eqs 97, 107
  std::vector<int> rest_count;               // oriented-box model: eq 108's records
  std::vector<int> rest_body;                // kMaxRests per body
  std::vector<F4> rest_local, rest_point, rest_last;
  // oriented-box model with the sleep effect: eq 124's records (read while a
  // body sleeps): its load parent, its support points' count and lever arms
  // (kMaxSupportPoints per body, their horizontal parts).
  std::vector<int> sleep_parent, sleep_count;
  std::vector<F4> sleep_arms;
  std::vector<int> awake;                    // the awake list, in the engine's order
  // The last frame's contacts, by slot (the warm start, eq 96).
  std::array<int, 2> stride{16, 16};         // neighbour-list blocks of the two frame parities
  int colours = 0;                           // the last frame's colouring rounds
  bool frozen_dirty = true;                  // the sleeping/static grid is to be rebuilt
  std::vector<int> slot_body;                // per slot: its body
  std::vector<int> ground_mask;              // per slot
  std::vector<F4> imm;                       // per slot, imm_stride entries: {j_n, j_t} of each ground/SDF point
  std::vector<int> nbr_begin;                // per slot + 1: where its entries start in nbr
  std::vector<int> nbr;                      // the neighbour lists, ascending per slot
  std::vector<F4> pair;                      // aabb model, per entry: {j_n, j_t}
  std::vector<int> man_count;                // oriented-box model, per entry: the points
  std::vector<int> man_feature;              // kSnapshotManifoldPoints per entry
  std::vector<F4> man_impulse;               // kSnapshotManifoldPoints per entry: {j_n, j_t}
  // The id table (run-time inputs, lockstep/body_ids.hpp): empty when body i
  // is slot i at generation 0; else per slot its generation, per body its slot.
  std::vector<std::uint32_t> generations, slot_of_body;
};

}  // namespace lockstep::gpu
