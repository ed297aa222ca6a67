// The frame of the GPU engine (docs/GPU.md), written once over a backend B
// that supplies buffers, a parallel for over n elements (a CUDA kernel or a
// host loop), a stable radix sort, a prefix sum and a maximum. The kernels
// are the functors of stages.hpp. The number type T is float ("gpu") or Q16
// ("gpu-fixed", docs/GPU.md "gpu-fixed"): instantiated for both with
// HostBackend (host.cpp) and, when built with CUDA, DeviceBackend (device.cu).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "colouring.hpp"
#include "load_stages.hpp"
#include "sleeper_load_stages.hpp"
#include "oriented_stages.hpp"
#include "pipeline_base.hpp"
#include "stages.hpp"

namespace lockstep::gpu {

template <class B, class T>
class Pipeline final : public PipelineBase<T> {
  template <class U>
  using Buf = typename B::template Buf<U>;
  using F4 = T4<T>;
  using Base = PipelineBase<T>;
  using Base::n_, Base::frame_, Base::n_awake_, Base::on_device_, Base::description_, Base::counters_, Base::times_;

 public:
  Pipeline(const InitialState<T>& s, const GpuOptions& options, std::string description, bool on_device)
      : be_(options.stage_timing), opt_(options) {
    n_ = s.n;
    on_device_ = on_device;
    description_ = std::move(description);
    const auto n = static_cast<std::size_t>(s.n);
    auto up = [&](auto& buf, const auto& host) {
      buf.resize(std::max<std::size_t>(host.size(), 1));
      be_.upload(buf.data(), host.data(), host.size());
    };
    up(pos_, s.pos); up(rot_, s.rot); up(aabb_, s.aabb); up(half_, s.half); up(inert_, s.inert);
    up(vel_[0], s.vel); up(ang_[0], s.ang);
    up(flags_, s.flags); up(sleep_counter_, s.sleep_counter); up(sleep_frame_, s.sleep_frame);
    for (int b = 1; b < 3; ++b) { vel_[b].resize(n + 1); ang_[b].resize(n + 1); }
    std::vector<std::uint8_t> large_flag(n, 0);
    for (int i : s.large) large_flag[static_cast<std::size_t>(i)] = 1;
    up(large_flag_, large_flag);
    up(large_, s.large);
    n_large_ = static_cast<int>(s.large.size());
    n_static_ = s.n_static;
    n_static_small_ = s.n_static_small;
    up(sdf_values_, s.sdf_values);
    std::vector<SdfGrid<T>> grids = s.sdf_grids;
    for (std::size_t k = 0; k < grids.size(); ++k) grids[k].values = sdf_values_.data() + s.sdf_offsets[k];
    up(sdf_grids_, grids);
    up(sdf_material_, s.sdf_material);
    n_sdf_ = static_cast<int>(grids.size());
    for (auto* l : {&list_[0], &list_[1], &woken_, &woken_tmp_, &keep_, &keep_scan_, &count_[0], &count_[1],
                    &slot_of_[0], &slot_of_[1], &stamp_[0], &stamp_[1]})
      l->resize(n + 1);
    dir_count_.resize(n + 1);

    be_.fill_int(stamp_[0].data(), -1, n + 1);
    be_.fill_int(stamp_[1].data(), -1, n + 1);
    up(list_[0], s.awake);
    n_awake_ = static_cast<int>(s.awake.size());
    wake_flag_.resize(n + 1);
    be_.fill_int(wake_flag_.data(), 0, n + 1);
    support_idx_.resize(n + 1);
    over_support_.resize(n + 1);
    leaning_.resize(n + 1);
    settle_limit_.resize(n + 1);
    can_rest_.resize(n + 1);
    be_.fill_int(can_rest_.data(), 1, n + 1);
    for (auto& c : over_chain_) c.resize(n + 1);
    support_n_.resize(n + 1);
    for (auto& b : settle_) b.resize(n + 1);
    p_tmp_.resize(n + 1);
    q_tmp_.resize(n + 1);
    if (n_sdf_ > 0) { sdf_c0_.resize(9 * n * static_cast<std::size_t>(n_sdf_) + 1); sdf_c1_.resize(9 * n * static_cast<std::size_t>(n_sdf_) + 1); }
    ctr_.resize(kCounterCount);
    be_.fill_zero(ctr_.data(), kCounterCount);
    scal_.resize(4);
    sc_.P = s.P;
    sc_.half_tol = s.P.contact_tolerance * Num<T>::from_double(0.5);
    sc_.gravity = s.fx.gravity;
    sc_.damping = s.fx.damping;
    sc_.friction = s.fx.friction;
    sc_.restitution = s.fx.restitution;
    sc_.sleep = s.fx.sleep;
    sc_.ground_on = s.ground_on;
    sc_.ground_y = s.ground_y;
    sc_.ground_e = s.ground_e;
    sc_.ground_mu = s.ground_mu;
    sc_.n_sdf = n_sdf_;
    sc_.sdf = n_sdf_ > 0 ? sdf_grids_.data() : nullptr;
    sc_.sdf_material = n_sdf_ > 0 ? sdf_material_.data() : nullptr;
    sc_.large = large_.data();
    sc_.n_large = n_large_;
    sc_.relaxation = Num<T>::from_double(options.relaxation);  // float -> double -> float: exact
    sc_.oriented = s.oriented;
    if constexpr (Num<T>::kExact) {  // Q16 faults (kernel_support.hpp), reset each frame
      fault_code_.resize(1);
      fault_flags_.resize(1);
      sc_.faults = FaultSink{fault_code_.data(), fault_flags_.data()};
    }
    oriented_ = s.oriented;
    if (oriented_) {  // eqs 97, 107: every body's growth starts at half the tolerance; eq 108's records
      up(grow_, std::vector<T>(n, sc_.half_tol));
      sc_.grow = grow_.data();  // eqs 97, 107: the ground tolerance grows with the reach
      for (auto* l : {&ready_, &sleep_sw_[0], &sleep_sw_[1], &wake_sw_[0], &wake_sw_[1], &rest_count_}) l->resize(n + 1);
      be_.fill_int(rest_count_.data(), 0, n + 1);
      rest_body_.resize(kMaxRests * n + 1);
      rest_local_.resize(kMaxRests * n + 1);
      rest_point_.resize(kMaxRests * n + 1);
      rest_last_.resize(kMaxRests * n + 1);
      p_world_.resize(n + 1);
      p_pairs_.resize(n + 1);
      turn_slot_.resize(n + 1);
      if (s.fx.sleep) {  // eq 124's records and scratch
        for (auto* l : {&sl_parent_, &sl_count_, &sl_flag_, &sl_scan_, &sl_begin_, &sl_end_, &sl_child_[0],
                        &sl_child_[1], &sl_head_, &sl_head_scan_, &sl_heads_, &sl_wake_})
          l->resize(n + 1);
        for (auto* l : {&sl_key_, &sl_keys_[0], &sl_keys_[1]}) l->resize(n + 1);
        for (auto* l : {&sl_load_[0], &sl_load_[1]}) l->resize(n + 1);
        sl_arms_.resize(static_cast<std::size_t>(kMaxSupportPoints) * n + 1);
        be_.fill_int(sl_parent_.data(), kLoadNone, n + 1);
        be_.fill_int(sl_count_.data(), 0, n + 1);
      }
    }
    fx_ = s.fx;
    body_.pos = pos_.data(); body_.rot = rot_.data(); body_.aabb = aabb_.data(); body_.half = half_.data();
    body_.inert = inert_.data(); body_.vel = vel_[0].data(); body_.ang = ang_[0].data(); body_.flags = flags_.data();
    body_.sleep_counter = sleep_counter_.data(); body_.sleep_frame = sleep_frame_.data();
    be_.sync();
  }

  void download(HostState<T>& out, bool full = false) override {
    const auto n = static_cast<std::size_t>(n_);
    out.pos.resize(n); out.rot.resize(n); out.vel.resize(n); out.ang.resize(n);
    out.flags.resize(n); out.sleep_frame.resize(n);
    be_.download(out.pos.data(), pos_.data(), n);
    be_.download(out.rot.data(), rot_.data(), n);
    be_.download(out.vel.data(), vel_[0].data(), n);
    be_.download(out.ang.data(), ang_[0].data(), n);
    be_.download(out.flags.data(), flags_.data(), n);
    be_.download(out.sleep_frame.data(), sleep_frame_.data(), n);
    if (full) {
      out.sleep_counter.resize(n);
      be_.download(out.sleep_counter.data(), sleep_counter_.data(), n);
      out.rest_count.assign(oriented_ ? n : 0, 0);
      out.rest_body.assign(oriented_ ? kMaxRests * n : 0, -1);
      if (oriented_) {
        be_.download(out.rest_count.data(), rest_count_.data(), n);
        be_.download(out.rest_body.data(), rest_body_.data(), kMaxRests * n);
      }
    }
    be_.sync();
  }

  void step() override;
  void save(GpuState<T>& out) override;
  void load(const GpuState<T>& in) override;
  int imm_stride() const override { return sc_.imm_stride(); }

 private:
  struct Grid {
    Buf<unsigned> keys[2];
    Buf<int> vals[2];
    Buf<CellRange> range;
    Buf<GridEntry<T>> ent;
    Buf<CellEntry> ent_c;
    Buf<Bounds<T>> bounds, reduced;
    Buf<GridParams<T>> gp;
    bool present = false;
    bool dense = false;
    unsigned cells = 0;
    GridView<T> view() {
      GridView<T> v;
      if (!present) return v;
      v.range = range.data(); v.ent = ent.data(); v.ent_c = ent_c.data();
      v.gp = gp.data(); v.present = true;
      return v;
    }
  };

  // Builds a grid over n entries: list[0..n) when list is given, else every
  // body (frozen members keyed, others sorted last). g.bounds must hold each
  // entry's Bounds. One synchronisation: the table's size.
  void build_grid(Grid& g, const int* list, int n, int members) {
    unsigned hash_table = 64;
    while (hash_table < 2u * static_cast<unsigned>(members)) hash_table <<= 1;
    const long long dense_limit = 8LL * members + 4096;
    const auto un = static_cast<std::size_t>(n);
    for (int b = 0; b < 2; ++b) { g.keys[b].resize(un); g.vals[b].resize(un); }
    g.ent.resize(un); g.ent_c.resize(un);
    g.reduced.resize(1); g.gp.resize(1);
    be_.reduce_bounds(g.bounds.data(), n, g.reduced.data());
    be_.for_n(1, GridParamsK<T>{g.reduced.data(), sc_.P.contact_tolerance, dense_limit, hash_table, g.gp.data()});
    GridParams<T> gp;
    be_.download(&gp, g.gp.data(), 1);
    be_.sync();
    int bits = 1;
    while (bits < 32 && (1ull << bits) <= gp.table) ++bits;  // the keys and the sentinel `table`
    g.range.resize(gp.table);
    be_.for_n(n, GridKeysK<T>{list, body_, large_flag_.data(), g.gp.data(), g.keys[0].data(), g.vals[0].data()});
    const int r = be_.sort_pairs(g.keys[0].data(), g.vals[0].data(), g.keys[1].data(), g.vals[1].data(), n, bits);
    be_.fill_minus_one(g.range.data(), gp.table);  // every cell empty
    be_.for_n(n, CellTableK<T>{g.keys[r].data(), g.vals[r].data(), n, body_, g.gp.data(), g.range.data(),
                            g.ent.data(), g.ent_c.data()});
    g.present = true;
    g.dense = gp.dense != 0;
    g.cells = gp.table;
  }

  // The coloured solver's per-entry state, set up by ContactsK (init_edge):
  // no arrays (mate null) without body-body contacts or with the Jacobi
  // solver.
  EdgeArrays<T> prepare_edges(int n_active, const NeighbourLists& nl, int par, bool coloured) {
    coloured_ = coloured;
    EdgeArrays<T> e;
    if (!coloured) return e;
    const auto entries = static_cast<std::size_t>(n_active) * static_cast<std::size_t>(nl.stride) + 1;
    mate_.resize(entries);
    edge_key_.resize(entries);
    edge_word_.resize(entries);
    edges_.resize(entries);
    for (auto& p : pending_) p.resize(entries);
    colour_scal_.resize(6);  // [0..2]: pending counts, [3..5]: edges placed (rotating over rounds)
    be_.fill_int(colour_scal_.data(), 0, 6);
    e.slot_of = slot_of_[par].data();
    e.inv_cell = &awake_grid_.gp.data()->inv_cell;
    e.mate = mate_.data();
    e.key = edge_key_.data();
    e.word = edge_word_.data();
    e.pending = pending_[0].data();
    e.pending_count = colour_scal_.data();
    return e;
  }

  // The colouring of the edges that ContactsK set up (colouring.hpp): rounds
  // in batches (the first as long as last frame's colouring, then 4), each
  // round over the edges still pending, until none is (one synchronisation
  // per batch); colour r is round r, and its edges are
  // edges_[colour_offset_[r], colour_offset_[r + 1]). Sets colours_ and
  // colour_offset_; returns the colour of each list entry.
  const int* colour_edges(int n_active, const int* active, const NeighbourLists& nl, int par) {
    const int previous = colours_;
    colours_ = 0;
    colour_offset_.assign(1, 0);
    if (!coloured_) {  // empty lists (no body-body contacts): nothing to colour
      edge_word_.resize(1);
      return edge_word_.data();
    }
    int* pending_count = colour_scal_.data();
    int* placed = colour_scal_.data() + 3;
    int round = 0;
    for (int batch = std::max(1, previous);; batch = 4) {
      round_end_.resize(static_cast<std::size_t>(round + batch));  // after a synchronisation: no kernel uses it
      for (int r = 0; r < batch; ++r, ++round)
        be_.for_n(n_active, ColourRoundK{active, nl, slot_of_[par].data(), mate_.data(), edge_key_.data(),
                                         edge_word_.data(), round, pending_count, placed, round_end_.data(),
                                         pending_[round % 2].data(), pending_[(round + 1) % 2].data(),
                                         edges_.data(), n_active});
      // Where every round's edges end: rounds 0 .. round-2 recorded them;
      // the last ends where it started plus what it placed.
      std::vector<int> ends(static_cast<std::size_t>(round));
      int counts[6] = {};
      if (round >= 2) be_.download(ends.data(), round_end_.data(), static_cast<std::size_t>(round - 1));
      be_.download(counts, colour_scal_.data(), 6);
      be_.sync();
      const int last = round - 1;
      ends[static_cast<std::size_t>(last)] = (last >= 1 ? ends[static_cast<std::size_t>(last - 1)] : 0) + counts[3 + last % 3];
      for (int r = static_cast<int>(colour_offset_.size()) - 1; r < round; ++r)  // rounds that coloured an edge
        if (ends[static_cast<std::size_t>(r)] > colour_offset_.back()) colour_offset_.push_back(ends[static_cast<std::size_t>(r)]);
      if (counts[round % 3] == 0) break;  // nothing pending for the next round
    }
    colours_ = static_cast<int>(colour_offset_.size()) - 1;
    return edge_word_.data();
  }

  // Host copy of a device int (the backend synchronises).
  int read_int(const int* p) {
    int v = 0;
    be_.download(&v, p, 1);
    be_.sync();
    return v;
  }

  B be_;
  GpuOptions opt_;
  Effects fx_;
  SceneConsts<T> sc_;
  BodyArrays<T> body_;
  Buf<F4> pos_, rot_, aabb_, half_, inert_, vel_[3], ang_[3];
  Buf<std::uint8_t> flags_, large_flag_;
  Buf<int> sleep_counter_, sleep_frame_, large_;
  Buf<SdfGrid<T>> sdf_grids_;
  Buf<T> sdf_values_;
  Buf<F4> sdf_material_;
  int n_sdf_ = 0, n_large_ = 0, n_static_ = 0, n_static_small_ = 0;
  Buf<int> list_[2];  // list_[cur_]: awake bodies, then (during a frame) woken ones
  int cur_ = 0;
  Buf<int> woken_, woken_tmp_, wake_flag_;
  // Double-buffered by frame parity: this frame's contacts and last frame's (warm start, eq 96).
  Buf<int> nbr_[2], count_[2], slot_of_[2], stamp_[2];
  int stride_[2] = {16, 16};  // neighbour-list block per slot
  Buf<ContactRecord<T>> pair_[2], imm_[2];
  Buf<F4> conv_imm_;   // eq 113, with the skip on: per slot, its ground and SDF manifolds' last visits (this frame's solve only)
  Buf<F4> conv_pair_;  // eq 113, with the skip on: per neighbour-list entry, its pair's last visit (this frame's solve only)
  Buf<int> ground_mask_[2];  // per slot: the ground corners in contact
  Buf<unsigned> work_key_[2];  // the contact stage's and solver's thread order (WorkOrder), sorted from 0 into r
  Buf<int> work_slot_[2];
  Buf<Counter> dir_count_;
  Buf<F4> sdf_c0_, sdf_c1_, support_n_;
  Buf<int> support_idx_;
  Buf<int> over_support_;  // eq 112, per body (written by ContactsK for the active ones)
  Buf<int> leaning_;       // eq 115, per body (written by ContactsK with over_support_)
  Buf<T> settle_limit_;  // eq 116, per body (ContactsK): eq 77 damps a relative speed up to this
  Buf<int> can_rest_;      // eqs 116-117, per body (ContactsK, LoadOverK): statics lets it rest
  Buf<int> load_parent_;   // eq 117, per body (ContactsK)
  Buf<int> load_tips_[2];  // eq 117's tips: its sweeps, per body
  Buf<F4> load_[2];        // eq 117's sweeps, per body: the load's offset (xyz) and mass (w)
  Buf<F4> arms_;           // eq 117, per slot: the support points' lever arms (kMaxSupportPoints each)
  Buf<int> n_arms_;        // eq 117, per slot: how many arms
  Buf<F4> hold_arms_, hold_n_;  // eq 112, per slot: what holds it, lever arms and normals (kMaxHolds each)
  Buf<int> n_holds_;       // eq 112, per slot: how many
  Buf<int> over_chain_[2];  // eq 112's chain: its sweeps, per body
  Buf<F4> settle_[2];
  Buf<F4> p_tmp_, q_tmp_;
  Buf<int> keep_, keep_scan_;
  Grid awake_grid_, frozen_grid_;
  Buf<Counter> ctr_;
  Buf<int> fault_code_;         // Q16: the frame's lowest fault (FaultSink::code)
  Buf<unsigned> fault_flags_;   // Q16: the frame's fault flags
  // The coloured solver's edges (colouring.hpp): per list entry its mate,
  // key and colour; the pending lists of the colouring rounds; the edges
  // (owner entries) by colour; where each round's edges end; the counters.
  Buf<int> mate_, edge_word_, pending_[2], edges_, round_end_, colour_scal_;
  Buf<unsigned long long> edge_key_;
  std::vector<int> colour_offset_;   // host: colour c's edges are edges_[offset[c], offset[c + 1])
  Buf<int> immovable_;               // per slot: contacts with immovable things (ContactsK)
  // gpu-fixed (kRowsOnce): the rows of the ground and SDF points (imm_stride()
  // per slot, ImmRowsK) and of the coloured edges' manifold points (EdgeRowsK).
  Buf<ContactRows<T>> imm_rows_, edge_rows_;
  Buf<int> scal_;  // [0]: woken count, [1]: error (4 i + code, or INT_MAX), [2]: longest neighbour list,
                   // [3]: bodies whose settled velocity is not final yet (settling batches)
  // The oriented-box model (oriented_stages.hpp): per body its growth (eqs
  // 97, 107) and eq 108's records; per entry the pair manifolds (double-
  // buffered by frame parity, eq 96) and the eq 110-111 sweeps' positions
  // and eq 111's turns; per slot the readiness and the sweeps of eq 109; per
  // body the sweeps of eq 108.
  bool oriented_ = false;
  Buf<T> grow_;
  Buf<PairManifold<T>> man_[2];
  Buf<F4> before_[2], turn_[2], p_world_, p_pairs_, turn_slot_;
  Buf<int> ready_, sleep_sw_[2], wake_sw_[2];
  Buf<int> rest_count_, rest_body_;
  Buf<F4> rest_local_, rest_point_, rest_last_;
  // eq 124 (sleeper_load_stages.hpp): per body the records; the pairs'
  // flags, keys and children; the parents' ranges, heads and loads; per
  // head whether it wakes; how many heads this frame.
  Buf<int> sl_parent_, sl_count_, sl_flag_, sl_scan_, sl_begin_, sl_end_, sl_child_[2], sl_head_, sl_head_scan_,
      sl_heads_, sl_wake_;
  Buf<unsigned> sl_key_, sl_keys_[2];
  Buf<F4> sl_arms_, sl_load_[2];
  int sl_n_heads_ = 0;
  SleepSupportArrays<T> sleep_records() { return SleepSupportArrays<T>{sl_parent_.data(), sl_count_.data(), sl_arms_.data()}; }
  RestArrays<T> rests() {
    return RestArrays<T>{rest_count_.data(), rest_body_.data(), rest_local_.data(), rest_point_.data(),
                      rest_last_.data()};
  }
  // Runs sweep(in, out, changed) until a sweep changes nothing (batches of
  // settle_batch, one synchronisation each; at most `limit` sweeps: the
  // longest chain of a well-formed order is shorter); returns the buffer
  // holding the result.
  template <class Sweep>
  int sweep_until_fixed(int limit, const Sweep& sweep) {
    const int batch = std::max(1, opt_.settle_batch);
    int cur = 0;
    for (int done = 0;;) {
      for (int k = 0; k < batch; ++k, ++done) {
        const bool last = k + 1 == batch;
        if (last) be_.fill_int(scal_.data() + 3, 0, 1);
        sweep(cur, 1 - cur, last ? scal_.data() + 3 : nullptr);
        cur = 1 - cur;
      }
      if (read_int(scal_.data() + 3) == 0 || done >= limit) return cur;
    }
  }
  // eq 124 (stage 3, after eq 117): with an awake body on a sleeper, the
  // sleepers' loads and whether each is over its recorded support points.
  void sleeper_loads(int n_active, const F4* awake_loads) {
    sl_n_heads_ = 0;
    if (!fx_.sleep || n_ - n_static_ - n_active <= 0) return;
    be_.fill_int(scal_.data() + 3, 0, 1);
    be_.for_n(n_, SleeperChildK<T>{body_, load_parent_.data(), sleep_records(), n_, sl_flag_.data(), sl_key_.data(),
                                scal_.data() + 3});
    if (read_int(scal_.data() + 3) == 0) return;
    be_.exclusive_scan(sl_flag_.data(), sl_scan_.data(), n_);
    const int m = read_int(sl_scan_.data() + n_);
    be_.for_n(n_, SleeperPairsK{sl_flag_.data(), sl_scan_.data(), sl_key_.data(), sl_keys_[0].data(), sl_child_[0].data()});
    int bits = 1;
    while (bits < 31 && (1 << bits) <= n_) ++bits;
    const int s = be_.sort_pairs(sl_keys_[0].data(), sl_child_[0].data(), sl_keys_[1].data(), sl_child_[1].data(), m,
                                 bits);
    be_.fill_int(sl_begin_.data(), -1, static_cast<std::size_t>(n_) + 1);
    be_.for_n(m, SleeperRangeK{sl_keys_[s].data(), m, sl_begin_.data(), sl_end_.data(), sl_head_.data()});
    be_.exclusive_scan(sl_head_.data(), sl_head_scan_.data(), m);
    const int heads = read_int(sl_head_scan_.data() + m);
    be_.for_n(m, SleeperHeadsK{sl_keys_[s].data(), sl_head_.data(), sl_head_scan_.data(), sl_heads_.data()});
    be_.fill_zero(sl_load_[0].data(), static_cast<std::size_t>(n_) + 1);
    const int r = sweep_until_fixed(heads + 2, [&](int in, int out, int* changed) {
      be_.for_n(heads, SleeperLoadK<T>{sl_heads_.data(), body_, sl_keys_[s].data(), sl_child_[s].data(), sl_begin_.data(),
                                    sl_end_.data(), awake_loads, sl_load_[in].data(), sl_load_[out].data(), changed,
                                    sc_.faults});
    });
    be_.for_n(heads, SleeperTestK<T>{sl_heads_.data(), sleep_records(), sl_load_[r].data(), sl_wake_.data(), sc_.faults});
    sl_n_heads_ = heads;
  }
  // eq 124, end of stage 9: the sleepers found beyond their support wake and
  // join the awake list (list_[cur_], after its `n_awake`); returns how many.
  int wake_loaded(int n_awake) {
    if (sl_n_heads_ == 0) return 0;
    be_.fill_int(scal_.data(), 0, 1);
    be_.for_n(sl_n_heads_, SleeperWakeK<T>{sl_heads_.data(), sl_wake_.data(), body_, rests(), woken_.data(), scal_.data()});
    const int n_woken = read_int(scal_.data());
    sl_n_heads_ = 0;
    if (n_woken == 0) return 0;
    be_.sort_ints(woken_.data(), woken_tmp_.data(), n_woken);
    be_.for_n(n_woken, CopyIntsK{woken_.data(), list_[cur_].data() + n_awake});
    counters_.wakes += static_cast<std::uint64_t>(n_woken);
    frozen_dirty_ = true;
    return n_woken;
  }
  bool frozen_dirty_ = true;
  bool coloured_ = false;  // this frame's body-body contacts are coloured
  int colours_ = 0;        // the coloured solver's colours (= colouring rounds) this frame
};

template <class B, class T>
void Pipeline<B, T>::step() {
  ++frame_;
  be_.begin_frame();
  if constexpr (Num<T>::kExact) {
    be_.for_n(1, SetIntK{fault_code_.data(), 0x7fffffff});
    be_.fill_zero(fault_flags_.data(), 1);
  }
  int n_awake = n_awake_;
  int* active = list_[cur_].data();
  const bool contacts = fx_.contacts && n_ >= 2;

  // 1: velocity integration.
  be_.mark(kStageIntegrate);
  const int integrated = n_awake;
  // 2a (oriented-box model, eq 108, after stage 1 in World<T>; it reads
  // poses only): sleeping bodies whose support moved wake and join the awake
  // list after the integrated bodies.
  if (oriented_ && fx_.sleep && contacts && n_awake > 0 && n_ - n_static_ - n_awake > 0) {
    be_.fill_int(wake_sw_[0].data(), 0, static_cast<std::size_t>(n_));
    const int r = sweep_until_fixed(n_ + 2, [&](int in, int out, int* changed) {
      be_.for_n(n_, SupportWakeK<T>{body_, sc_, rests(), wake_sw_[in].data(), wake_sw_[out].data(), changed});
    });
    be_.fill_int(scal_.data(), 0, 1);
    be_.for_n(n_, SupportWakeApplyK<T>{body_, wake_sw_[r].data(), woken_.data(), scal_.data()});
    be_.for_n(n_, RestLastK<T>{body_, rests(), sc_.faults});  // eq 108's speed: where the points are now
    const int n_woken = read_int(scal_.data());
    if (n_woken > 0) {
      be_.sort_ints(woken_.data(), woken_tmp_.data(), n_woken);
      be_.for_n(n_woken, CopyIntsK{woken_.data(), active + n_awake});
      n_awake += n_woken;
      counters_.wakes += static_cast<std::uint64_t>(n_woken);
      frozen_dirty_ = true;
    }
  }
  if (n_awake > 0 && (fx_.gravity || fx_.damping || contacts || oriented_)) {
    awake_grid_.bounds.resize(static_cast<std::size_t>(n_awake));
    IntegrateVelocityK<T> iv{active, body_, sc_, contacts ? awake_grid_.bounds.data() : nullptr};
    iv.grow = oriented_ ? grow_.data() : nullptr;  // eqs 97, 107: also the ground tolerance
    iv.integrate_end = integrated;
    be_.for_n(n_awake, iv);
  }
  if (fx_.gravity) counters_.integrate_velocity += static_cast<std::uint64_t>(integrated);
  if (fx_.damping) counters_.damping += static_cast<std::uint64_t>(integrated);

  // 2: grids. The awake grid each frame; the frozen grid (sleeping and small
  // static bodies, which do not move) only when that set has changed.
  const int n_frozen = n_static_small_ + (n_ - n_static_ - n_awake);
  be_.mark(kStageBroadphase);
  awake_grid_.present = false;
  if (contacts && n_awake > 0) {
    build_grid(awake_grid_, active, n_awake, n_awake);
    counters_.broadphase_bodies += static_cast<std::uint64_t>(n_awake);
  }
  be_.mark(kStageFrozenGrid);
  if (!contacts || n_frozen == 0) {
    frozen_grid_.present = false;
  } else if (frozen_dirty_ && n_awake > 0) {  // with no awake body nothing looks it up
    frozen_grid_.bounds.resize(static_cast<std::size_t>(n_));
    be_.for_n(n_, FrozenBoundsK<T>{body_, large_flag_.data(), frozen_grid_.bounds.data()});
    build_grid(frozen_grid_, nullptr, n_, n_frozen);
    counters_.broadphase_bodies += static_cast<std::uint64_t>(n_frozen);
    frozen_dirty_ = false;
  }

  // 2-4: neighbour lists and the wake (81); the woken bodies' lists.
  const int par = frame_ & 1, pp = par ^ 1;
  be_.mark(kStagePairs);
  int n_active = n_awake;
  int& stride = stride_[par];
  count_[par].resize(static_cast<std::size_t>(n_) + 1);
  auto lists = [&] {
    nbr_[par].resize(static_cast<std::size_t>(n_active) * static_cast<std::size_t>(stride) + 1);
    return NeighbourLists{nbr_[par].data(), count_[par].data(), stride};
  };
  // Gathers the lists of slots [0, n_awake) and [n_awake, n_active), the
  // first time with the work counted and the wakes decided.
  // The threads of the contact stage and the solver's iterations in work
  // order (the gather writes the keys, sorted before the contact stage) when
  // there are enough of them.
  const bool ordered = contacts && n_awake > 0 && n_awake >= opt_.work_order_min;
  WorkOrder work;
  const int* work_order = nullptr;  // thread -> slot of the contact stage and the solver, sorted by the keys
  if (ordered) {
    for (int buf = 0; buf < 2; ++buf) {
      work_key_[buf].resize(static_cast<std::size_t>(n_));
      work_slot_[buf].resize(static_cast<std::size_t>(n_));
    }
    work = WorkOrder{work_key_[0].data(), work_slot_[0].data()};
  }
  const ContactIndex index{slot_of_[par].data(), stamp_[par].data()};
  T* grow = oriented_ ? grow_.data() : nullptr;
  auto gather = [&](bool first, bool awake_part, bool woken_part) {
    const NeighbourLists l = lists();
    if (awake_part) {
      GatherK<T> g{active, 0, body_, sc_, awake_grid_.view(), frozen_grid_.view(), false, first, l,
                scal_.data() + 2, wake_flag_.data(), woken_.data(), scal_.data(), work, index, frame_, ctr_.data()};
      g.grow = grow;
      be_.for_n(n_awake, g);
    }
    if (woken_part) {
      GatherK<T> g{active + n_awake, n_awake, body_, sc_, awake_grid_.view(), frozen_grid_.view(), true, first, l,
                scal_.data() + 2, wake_flag_.data(), woken_.data(), scal_.data(), work, index, frame_, ctr_.data()};
      g.grow = grow;
      be_.for_n(n_active - n_awake, g);
    }
  };
  // The largest list found (when above the stride): the blocks grow and all
  // lists are gathered again.
  auto fits = [&](int most) {
    if (most <= stride) return true;
    while (stride < most) stride *= 2;
    return false;
  };
  if (contacts && n_awake > 0) {
    be_.fill_int(scal_.data(), 0, 3);  // woken count, (error), longest list
    gather(true, true, false);
    int found[3] = {0, 0, 0};  // one synchronisation: woken count and longest list
    be_.download(found, scal_.data(), 3);
    be_.sync();
    const int n_woken = found[0];
    if (!fits(found[2])) gather(false, true, false);
    if (n_woken > 0) {
      be_.sort_ints(woken_.data(), woken_tmp_.data(), n_woken);
      be_.for_n(n_woken, WakeApplyK<T>{woken_.data(), body_, wake_flag_.data(), active, n_awake, grow, sc_.half_tol});
      n_active = n_awake + n_woken;
      gather(true, false, true);
      if (!fits(read_int(scal_.data() + 2))) gather(false, true, true);
      counters_.wakes += static_cast<std::uint64_t>(n_woken);
      frozen_dirty_ = true;
    }
  } else if (n_awake > 0) {  // no gather: empty lists, and the slots for the warm start
    be_.fill_int(count_[par].data(), 0, static_cast<std::size_t>(n_awake));
    be_.for_n(n_awake, SlotIndexK{active, index, frame_});
  }
  const NeighbourLists nl = lists();

  // 3 and 5 (preparation): sorted neighbour lists, contacts, supports; each
  // contact prepared and the velocities warm-started into buffer 1.
  be_.mark(kStageContacts);
  const auto entries = static_cast<std::size_t>(n_active) * static_cast<std::size_t>(stride) + 1;
  pair_[par].resize(oriented_ ? 1 : entries);  // the oriented-box model keeps the state in the manifolds
  if (oriented_) man_[par].resize(entries);
  const auto imm = static_cast<std::size_t>(n_active) * static_cast<std::size_t>(sc_.imm_stride()) + 1;
  imm_[par].resize(imm);
  const bool skip = oriented_ && sc_.P.converged_speed > T{};  // eq 113's records exist only with the skip on
  if (skip) conv_imm_.resize(static_cast<std::size_t>(n_active) * static_cast<std::size_t>(sc_.ground_slots() / 8 + sc_.n_sdf) * 4 + 1);
  if (skip) conv_pair_.resize(entries * 4);
  ground_mask_[par].resize(static_cast<std::size_t>(n_active) + 1);
  immovable_.resize(static_cast<std::size_t>(n_active) + 1);
  PairManifold<T>* man = oriented_ ? man_[par].data() : nullptr;
  const SolverData<T> d{active, body_, sc_, nl, dir_count_.data(), sdf_c0_.data(), sdf_c1_.data(),
                     imm_[par].data(), pair_[par].data(), man, skip ? conv_imm_.data() : nullptr,
                     skip ? conv_pair_.data() : nullptr};
  if (n_active > 0) {
    const PreviousContacts<T> prev{frame_ - 1, slot_of_[pp].data(), stamp_[pp].data(),
                                NeighbourLists{nbr_[pp].data(), count_[pp].data(), stride_[pp]}, imm_[pp].data(),
                                ground_mask_[pp].data(), pair_[pp].data(), oriented_ ? man_[pp].data() : nullptr};
    if (ordered) {
      const int r = be_.sort_pairs(work_key_[0].data(), work_slot_[0].data(), work_key_[1].data(),
                                   work_slot_[1].data(), n_active, work_key_bits(n_active));
      work_order = work_slot_[r].data();
    }
    const EdgeArrays<T> edges = prepare_edges(n_active, nl, par, contacts && n_awake > 0 &&
                                                                   opt_.pair_solver == GpuOptions::PairSolver::kColoured);
    if (oriented_)  // eqs 100-107: each pair's manifold, once
      be_.for_n(n_active, PairManifoldK<T>{d, slot_of_[par].data(), grow, work_order});
    ContactsK<T> ck{d, prev, edges, sdf_c0_.data(), sdf_c1_.data(), support_idx_.data(), support_n_.data(),
                 dir_count_.data(), ground_mask_[par].data(), immovable_.data(), vel_[1].data(),
                 ang_[1].data(), ctr_.data()};
    ck.order = work_order;
    ck.over_support = over_support_.data();
    ck.leaning = leaning_.data();
    ck.settle_limit = settle_limit_.data();
    ck.can_rest = can_rest_.data();
    if (oriented_) {
      load_parent_.resize(static_cast<std::size_t>(n_) + 1);
      arms_.resize(static_cast<std::size_t>(n_active) * kMaxSupportPoints + 1);
      n_arms_.resize(static_cast<std::size_t>(n_active) + 1);
      hold_arms_.resize(static_cast<std::size_t>(n_active) * kMaxHolds + 1);
      hold_n_.resize(static_cast<std::size_t>(n_active) * kMaxHolds + 1);
      n_holds_.resize(static_cast<std::size_t>(n_active) + 1);
      ck.load_parent = load_parent_.data();
      ck.arms_out = arms_.data();
      ck.n_arms_out = n_arms_.data();
      ck.hold_arms_out = hold_arms_.data();
      ck.hold_n_out = hold_n_.data();
      ck.n_holds_out = n_holds_.data();
    }
    be_.for_n(n_active, ck);
  }
  // eq 117: the loads (sweeps), then whether each is over its support.
  if (oriented_ && n_active > 0) {
    for (auto& buf : load_) buf.resize(static_cast<std::size_t>(n_) + 1);
    be_.fill_zero(load_[0].data(), static_cast<std::size_t>(n_) + 1);
    const int r = sweep_until_fixed(n_active + 2, [&](int in, int out, int* changed) {
      be_.for_n(n_active, LoadK<T>{active, body_, nl, load_parent_.data(), load_[in].data(), load_[out].data(), changed,
                                   sc_.faults});
    });
    be_.for_n(n_active, LoadOverK<T>{active, body_, sc_, nl, load_parent_.data(), support_idx_.data(), load_[r].data(),
                                  arms_.data(), n_arms_.data(), hold_arms_.data(), hold_n_.data(), n_holds_.data(),
                                  over_support_.data(), can_rest_.data()});
    for (auto& buf : load_tips_) buf.resize(static_cast<std::size_t>(n_) + 1);
    be_.fill_int(load_tips_[0].data(), 0, static_cast<std::size_t>(n_) + 1);
    const int t = sweep_until_fixed(n_active + 2, [&](int in, int out, int* changed) {
      be_.for_n(n_active, LoadTipsK<T>{active, body_, nl, load_parent_.data(), over_support_.data(),
                                    support_idx_.data(), load_tips_[in].data(), load_tips_[out].data(), changed, nullptr});
    });
    be_.for_n(n_active, LoadTipsK<T>{active, body_, nl, load_parent_.data(), over_support_.data(), support_idx_.data(), load_tips_[t].data(),
                                  load_tips_[1 - t].data(), nullptr, can_rest_.data()});
    sleeper_loads(n_active, load_[r].data());  // eq 124
  }
  // eq 112's chain: a body riding on a body that tips tips too (sweeps).
  const int* over = over_support_.data();
  if (oriented_ && n_active > 0) {
    be_.for_n(n_active, TipChainK<T>{active, body_, support_idx_.data(), over, over, over_chain_[0].data(), nullptr});
    const int r = sweep_until_fixed(n_active + 2, [&](int in, int out, int* changed) {
      be_.for_n(n_active, TipChainK<T>{active, body_, support_idx_.data(), over, over_chain_[in].data(),
                                    over_chain_[out].data(), changed});
    });
    over = over_chain_[r].data();
  }

  // 5: the solver's iterations alternate between buffers 1 and 2.
  be_.mark(kStageSolve);
  const int iterations = sc_.P.solver_iterations;
  int last = 1;
  if (n_active > 0) {
    const bool coloured = opt_.pair_solver == GpuOptions::PairSolver::kColoured;
    const int* colour = coloured ? colour_edges(n_active, active, nl, par) : nullptr;
    // gpu-fixed: the rows of the ground and SDF points, and of the coloured
    // edges' manifolds, formed once for the iterations (kRowsOnce).
    const ContactRows<T>* imm_rows = nullptr;
    const ContactRows<T>* edge_rows = nullptr;
    if constexpr (kRowsOnce<T>) {
      if (iterations > 0) {
        imm_rows_.resize(static_cast<std::size_t>(n_active) * static_cast<std::size_t>(sc_.imm_stride()) + 1);
        if (sc_.imm_stride() > 0)
          be_.for_n(n_active, ImmRowsK<T>{d, coloured ? immovable_.data() : nullptr, imm_rows_.data()});
        imm_rows = imm_rows_.data();
        if (coloured && oriented_) {
          const int n_edges = colour_offset_[static_cast<std::size_t>(colours_)];
          edge_rows_.resize(static_cast<std::size_t>(n_edges) * kBoxManifoldPoints + 1);
          be_.for_n(n_edges, EdgeRowsK<T>{d, edges_.data(), edge_rows_.data()});
          edge_rows = edge_rows_.data();
        }
      }
    }
    if (coloured) {
      for (int it = 0; it < iterations; ++it) {  // in place in buffer 1
        // The oriented-box model alternates (7.2 step 5): odd passes visit
        // the colours top-down, then the bodies' own manifolds in reverse.
        const bool reverse = oriented_ && (it & 1) != 0;
        SolveK<T> sk{d, work_order, colour, immovable_.data(), vel_[1].data(), ang_[1].data(),
                  vel_[1].data(), ang_[1].data(), ctr_.data()};
        sk.reverse = reverse;
        sk.pass = it;
        sk.imm_rows = imm_rows;
        auto colour_pass = [&](int c) {
          SolveEdgeK<T> ek{d, edges_.data() + colour_offset_[c], mate_.data(), vel_[1].data(), ang_[1].data(),
                           ctr_.data(), it};
          if (edge_rows != nullptr) ek.rows = edge_rows + static_cast<std::size_t>(colour_offset_[c]) * kBoxManifoldPoints;
          be_.for_n(colour_offset_[c + 1] - colour_offset_[c], ek);
        };
        if (!reverse) {
          be_.for_n(n_active, sk);
          for (int c = 0; c < colours_; ++c) colour_pass(c);
        } else {
          for (int c = colours_ - 1; c >= 0; --c) colour_pass(c);
          be_.for_n(n_active, sk);
        }
      }
    } else {
      for (int it = 0; it < iterations; ++it) {
        const int in = it % 2 == 0 ? 1 : 2, out = 3 - in;
        SolveK<T> sk{d, work_order, nullptr, nullptr, vel_[in].data(), ang_[in].data(), vel_[out].data(),
                  ang_[out].data(), ctr_.data()};
        sk.reverse = oriented_ && (it & 1) != 0;
        sk.pass = it;
        sk.imm_rows = imm_rows;
        be_.for_n(n_active, sk);
        last = out;
      }
    }
  }

  // 6: settling sweeps but the last (which runs with the correction).
  be_.mark(kStageSettle);
  SettleSweep<T> sweep{support_idx_.data(), support_n_.data(), vel_[last].data(), vel_[last].data(), oriented_};
  if (oriented_) sweep.over = over, sweep.leaning = leaning_.data();
  sweep.limit = settle_limit_.data();
  if (fx_.settling && n_active > 0) {
    const int batch = std::max(1, opt_.settle_batch);
    for (int s = 0;;) {  // until every body's settled velocity is final
      for (int k = 0; k < batch; ++k, ++s) {
        F4* sout = settle_[s % 2].data();
        if (k + 1 == batch) be_.fill_int(scal_.data() + 3, 0, 1);
        be_.for_n(n_active, SettleK<T>{active, body_, sc_, sweep, sout, k + 1 == batch ? scal_.data() + 3 : nullptr});
        sweep.sin = sout;
      }
      if (read_int(scal_.data() + 3) == 0) break;
    }
  }

  // 6 (last sweep), 7-8: final velocities, position correction and integration.
  be_.mark(kStageCorrect);
  if (n_active > 0) {
    CorrectIntegrateK<T> ci{active, body_, sc_, nl, sdf_c0_.data(), sdf_c1_.data(), imm_[par].data(),
                         pair_[par].data(), vel_[last].data(), ang_[last].data(), fx_.settling,
                         sweep, p_tmp_.data(), q_tmp_.data(), ctr_.data()};
    ci.p_world = oriented_ ? p_world_.data() : nullptr;
    be_.for_n(n_active, ci);
    if (oriented_) {  // eqs 110, 111: the pairs bottom-up (sweeps), then eqs 2, 7-10
      const F4* corrected = p_world_.data();
      const F4* turn = nullptr;
      if (contacts && n_awake > 0) {
        for (auto& buf : before_) buf.resize(entries);
        be_.fill_zero(before_[0].data(), entries);
        const int r = sweep_until_fixed(static_cast<int>(entries) + 2, [&](int in, int out, int* changed) {
          be_.for_n(n_active, PairCorrectK<T>{active, body_, sc_, nl, man, slot_of_[par].data(), p_world_.data(),
                                           before_[in].data(), before_[out].data(), p_pairs_.data(), changed});
        });
        (void)r;
        // eq 111: the pairs' points again in the same order (sweeps), from
        // the positions after eq 110 (p_pairs_) into p_world_ and turn_slot_.
        for (auto& buf : turn_) buf.resize(entries);
        be_.fill_zero(before_[0].data(), entries);
        be_.fill_zero(turn_[0].data(), entries);
        const int r2 = sweep_until_fixed(static_cast<int>(entries) + 2, [&](int in, int out, int* changed) {
          be_.for_n(n_active, PairTurnK<T>{active, body_, sc_, nl, man, slot_of_[par].data(), p_pairs_.data(),
                                        before_[in].data(), turn_[in].data(), before_[out].data(), turn_[out].data(),
                                        p_world_.data(), turn_slot_.data(), changed});
        });
        (void)r2;
        corrected = p_world_.data();
        turn = turn_slot_.data();
      }
      be_.for_n(n_active, IntegrateK<T>{active, body_, sc_, nl, contacts && n_awake > 0 ? man : nullptr, corrected, turn,
                                     p_tmp_.data(), q_tmp_.data(), ctr_.data()});
    }
  }
  counters_.integrate_position += static_cast<std::uint64_t>(n_active);

  // 9: commit, sleep update, compaction of the awake set.
  be_.mark(kStageSleep);
  int error = 0x7fffffff;
  int new_awake = 0;
  if (n_active > 0) {
    be_.for_n(1, SetIntK{scal_.data() + 1, error});
    CommitSleepK<T> cs{active, body_, sc_, p_tmp_.data(), q_tmp_.data(), support_idx_.data(),
                    support_n_.data(), frame_, keep_.data(), scal_.data() + 1, ctr_.data()};
    const bool eq109 = oriented_ && fx_.sleep;
    cs.ready = eq109 ? ready_.data() : nullptr;
    cs.can_rest = can_rest_.data();  // eqs 116, 117
    if (oriented_) cs.over = over, cs.leaning = leaning_.data();  // eq 112: one not over its support is not slowed (it sleeps on its own counter only)
    be_.for_n(n_active, cs);
    if (eq109) {  // eq 109: the ready bodies fall asleep bottom-up (sweeps)
      const PairManifold<T>* pairs = contacts && n_awake > 0 ? man : nullptr;
      be_.fill_int(sleep_sw_[0].data(), 0, static_cast<std::size_t>(n_active));
      const int r = sweep_until_fixed(n_active + 2, [&](int in, int out, int* changed) {
        be_.for_n(n_active, SleepSweepK<T>{active, body_, sc_, nl, pairs, slot_of_[par].data(), ready_.data(),
                                        sleep_sw_[in].data(), sleep_sw_[out].data(), changed});
      });
      SleepApplyK<T> apply{active, body_, sc_, nl, pairs, sleep_sw_[r].data(), leaning_.data(), rests(),
                        grow_.data(), frame_, keep_.data(), nullptr, nullptr, nullptr, {}};
      apply.load_parent = load_parent_.data();  // eq 124's records
      apply.arms = arms_.data();
      apply.n_arms = n_arms_.data();
      apply.records = sleep_records();
      be_.for_n(n_active, apply);
    }
    be_.exclusive_scan(keep_.data(), keep_scan_.data(), n_active);
    be_.for_n(n_active, ScatterK{active, keep_.data(), keep_scan_.data(), list_[1 - cur_].data()});
    int host[2] = {0, 0};
    be_.download(&host[0], keep_scan_.data() + n_active, 1);
    be_.download(&host[1], scal_.data() + 1, 1);
    Counter ctr[kCounterCount];
    be_.download(ctr, ctr_.data(), kCounterCount);
    be_.sync();
    new_awake = host[0];
    error = host[1];
    cur_ = 1 - cur_;
    new_awake += wake_loaded(new_awake);  // eq 124
    counters_.pairs_tested = ctr[kCPairsTested];
    counters_.ground_contacts = ctr[kCGroundContacts];
    counters_.sdf_contacts = ctr[kCSdfContacts];
    counters_.body_contacts = ctr[kCBodyContacts];
    counters_.solver_contacts = ctr[kCSolverContacts];
    counters_.normal_impulses = ctr[kCNormalImpulses];
    counters_.restitution_bounces = ctr[kCRestitutionBounces];
    counters_.friction_steps = ctr[kCFrictionSteps];
    counters_.corrections = ctr[kCCorrections];
    counters_.settling_bodies = ctr[kCSettlingBodies];
    counters_.sleep_updates = ctr[kCSleepUpdates];
  }
  be_.mark(kStageCount);
  be_.end_frame(times_);
  if (new_awake != n_active) frozen_dirty_ = true;
  n_awake_ = new_awake;
  if constexpr (Num<T>::kExact) {  // World<Q16>::check_faults: the frame, the body, the quantity
    int code = 0x7fffffff;
    unsigned flags = 0;
    be_.download(&code, fault_code_.data(), 1);
    be_.download(&flags, fault_flags_.data(), 1);
    be_.sync();
    if (code != 0x7fffffff)
      throw RunError(frame_, code & ((1 << kFaultBodyBits) - 1), fault_quantity_name(code >> kFaultBodyBits, oriented_),
                     q16_flag_name(flags));
  }
  if (error != 0x7fffffff) {
    static const char* const kWhat[] = {"position", "velocity", "angular velocity", "orientation"};
    throw RunError(frame_, error / 4, kWhat[error % 4], "not finite (NaN or infinity)");
  }
}

// Snapshots (gpu_state.hpp, docs/SNAPSHOTS.md "The GPU engine"): the state
// after the last step, and the last frame's contacts by slot (the warm start
// reads them through PreviousContacts: slot_of_, stamp_, count_, nbr_, imm_,
// ground_mask_ and pair_ or man_ of the frame's parity).
template <class B, class T>
void Pipeline<B, T>::save(GpuState<T>& s) {
  const auto n = static_cast<std::size_t>(n_);
  auto down = [&](auto& host, auto& buf, std::size_t count) {
    host.resize(count);
    be_.download(host.data(), buf.data(), count);
  };
  s.frame = frame_;
  s.counters = counters_;
  down(s.pos, pos_, n); down(s.rot, rot_, n); down(s.aabb, aabb_, n); down(s.vel, vel_[0], n); down(s.ang, ang_[0], n);
  down(s.flags, flags_, n); down(s.sleep_counter, sleep_counter_, n); down(s.sleep_frame, sleep_frame_, n);
  if (oriented_) {
    down(s.grow, grow_, n);
    down(s.rest_count, rest_count_, n);
    down(s.rest_body, rest_body_, kMaxRests * n);
    down(s.rest_local, rest_local_, kMaxRests * n);
    down(s.rest_point, rest_point_, kMaxRests * n);
    down(s.rest_last, rest_last_, kMaxRests * n);
    s.sleep_parent.clear(); s.sleep_count.clear(); s.sleep_arms.clear();
    if (fx_.sleep) {  // eq 124's records
      down(s.sleep_parent, sl_parent_, n);
      down(s.sleep_count, sl_count_, n);
      down(s.sleep_arms, sl_arms_, static_cast<std::size_t>(kMaxSupportPoints) * n);
    }
  } else {
    s.sleep_parent.clear(); s.sleep_count.clear(); s.sleep_arms.clear();
    s.grow.clear(); s.rest_count.clear(); s.rest_body.clear(); s.rest_local.clear(); s.rest_point.clear(); s.rest_last.clear();
  }
  down(s.awake, list_[cur_], static_cast<std::size_t>(n_awake_));
  s.stride = {stride_[0], stride_[1]};
  s.colours = colours_;
  s.frozen_dirty = frozen_dirty_;
  s.slot_body.clear(); s.ground_mask.clear(); s.imm.clear(); s.nbr_begin.assign(1, 0); s.nbr.clear();
  s.pair.clear(); s.man_count.clear(); s.man_feature.clear(); s.man_impulse.clear();
  const int p = frame_ & 1;
  std::vector<int> stamp, slot;
  if (frame_ > 0) { down(stamp, stamp_[p], n); down(slot, slot_of_[p], n); }
  be_.sync();
  int active = 0;
  for (std::size_t i = 0; i < stamp.size(); ++i) active += stamp[i] == frame_ ? 1 : 0;
  if (active == 0) return;
  const auto un = static_cast<std::size_t>(active);
  s.slot_body.assign(un, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (stamp[i] == frame_) s.slot_body.at(static_cast<std::size_t>(slot[i])) = static_cast<int>(i);
  const int stride = stride_[p];
  const auto per = static_cast<std::size_t>(sc_.imm_stride());
  std::vector<int> count, nbr;
  std::vector<ContactRecord<T>> imm, pair;
  std::vector<PairManifold<T>> man;
  down(count, count_[p], un);
  down(s.ground_mask, ground_mask_[p], un);
  down(imm, imm_[p], un * per);
  down(nbr, nbr_[p], un * static_cast<std::size_t>(stride));
  if (oriented_) down(man, man_[p], un * static_cast<std::size_t>(stride));
  else down(pair, pair_[p], un * static_cast<std::size_t>(stride));
  be_.sync();
  // A ground corner's record is the last frame's only when its mask bit is
  // set (ContactsK writes the corners in contact); the others are not read.
  s.imm.reserve(un * per);
  for (std::size_t e = 0; e < imm.size(); ++e) {
    const int corner = static_cast<int>(e % per);
    const bool stale = corner < sc_.ground_slots() && ((s.ground_mask[e / per] >> corner) & 1) == 0;
    s.imm.push_back(stale ? F4{} : imm[e].a);
  }
  for (std::size_t k = 0; k < un; ++k) {
    for (int e = 0; e < count[k]; ++e) {
      const std::size_t t = k * static_cast<std::size_t>(stride) + static_cast<std::size_t>(e);
      s.nbr.push_back(nbr[t]);
      if (oriented_) {
        s.man_count.push_back(man[t].count);
        for (int u = 0; u < kSnapshotManifoldPoints; ++u) {
          s.man_feature.push_back(u < man[t].count ? man[t].feature[u] : 0);
          s.man_impulse.push_back(u < man[t].count ? man[t].st[u].a : F4{});
        }
      } else {
        s.pair.push_back(pair[t].a);
      }
    }
    s.nbr_begin.push_back(static_cast<int>(s.nbr.size()));
  }
}

template <class B, class T>
void Pipeline<B, T>::load(const GpuState<T>& s) {
  const auto n = static_cast<std::size_t>(n_);
  auto up = [&](auto& buf, const auto& host) {
    buf.resize(std::max<std::size_t>(host.size(), 1));
    be_.upload(buf.data(), host.data(), host.size());
  };
  frame_ = s.frame;
  counters_ = s.counters;
  up(pos_, s.pos); up(rot_, s.rot); up(aabb_, s.aabb); up(vel_[0], s.vel); up(ang_[0], s.ang);
  up(flags_, s.flags); up(sleep_counter_, s.sleep_counter); up(sleep_frame_, s.sleep_frame);
  const StageCounters& c = s.counters;
  const Counter ctr[kCounterCount] = {c.integrate_velocity, c.damping, c.integrate_position, c.broadphase_bodies,
                                      c.pairs_tested, c.ground_contacts, c.sdf_contacts, c.body_contacts,
                                      c.solver_contacts, c.normal_impulses, c.restitution_bounces, c.friction_steps,
                                      c.corrections, c.settling_bodies, c.sleep_updates, c.wakes};
  be_.upload(ctr_.data(), ctr, kCounterCount);
  if (oriented_) {
    up(grow_, s.grow); up(rest_count_, s.rest_count); up(rest_body_, s.rest_body);
    up(rest_local_, s.rest_local); up(rest_point_, s.rest_point); up(rest_last_, s.rest_last);
    if (fx_.sleep && !s.sleep_parent.empty()) {  // eq 124's records
      up(sl_parent_, s.sleep_parent); up(sl_count_, s.sleep_count); up(sl_arms_, s.sleep_arms);
    }
  }
  n_awake_ = static_cast<int>(s.awake.size());
  be_.upload(list_[cur_].data(), s.awake.data(), s.awake.size());
  stride_[0] = s.stride[0];
  stride_[1] = s.stride[1];
  colours_ = s.colours;
  be_.fill_int(wake_flag_.data(), 0, n + 1);
  be_.fill_int(stamp_[0].data(), -1, n + 1);
  be_.fill_int(stamp_[1].data(), -1, n + 1);
  const int p = frame_ & 1;
  const auto active = s.slot_body.size();
  if (active > 0) {
    const int stride = stride_[p];
    const auto per = static_cast<std::size_t>(sc_.imm_stride());
    const auto entries = active * static_cast<std::size_t>(stride);
    std::vector<int> stamp(n, -1), slot(n, 0), count(active), nbr(entries, 0);
    std::vector<ContactRecord<T>> imm(active * per), pair(oriented_ ? 0 : entries);
    std::vector<PairManifold<T>> man(oriented_ ? entries : 0);
    for (std::size_t k = 0; k < active; ++k) {
      const auto b = static_cast<std::size_t>(s.slot_body[k]);
      stamp[b] = frame_;
      slot[b] = static_cast<int>(k);
      count[k] = s.nbr_begin[k + 1] - s.nbr_begin[k];
      for (int e = 0; e < count[k]; ++e) {
        const auto from = static_cast<std::size_t>(s.nbr_begin[k] + e);
        const std::size_t t = k * static_cast<std::size_t>(stride) + static_cast<std::size_t>(e);
        nbr[t] = s.nbr[from];
        if (oriented_) {
          man[t].count = s.man_count[from];
          for (int u = 0; u < kSnapshotManifoldPoints; ++u) {
            man[t].feature[u] = s.man_feature[from * kSnapshotManifoldPoints + static_cast<std::size_t>(u)];
            man[t].st[u].a = s.man_impulse[from * kSnapshotManifoldPoints + static_cast<std::size_t>(u)];
          }
        } else {
          pair[t].a = s.pair[from];
        }
      }
    }
    for (std::size_t e = 0; e < imm.size(); ++e) imm[e].a = s.imm[e];
    be_.upload(stamp_[p].data(), stamp.data(), n);
    be_.upload(slot_of_[p].data(), slot.data(), n);
    up(count_[p], count);
    count_[p].resize(n + 1);
    up(ground_mask_[p], s.ground_mask);
    up(imm_[p], imm);
    up(nbr_[p], nbr);
    if (oriented_) up(man_[p], man);
    else up(pair_[p], pair);
  }
  // The sleeping/static grid: rebuilt now when the saved engine held a
  // current one (it is a function of the frozen set, which has not changed
  // since), else at the next step; not counted (the saved counters hold the
  // build that made it).
  frozen_dirty_ = true;
  const int n_frozen = n_static_small_ + (n_ - n_static_ - n_awake_);
  if (!s.frozen_dirty && fx_.contacts && n_ >= 2 && n_frozen > 0) {
    frozen_grid_.bounds.resize(n);
    be_.for_n(n_, FrozenBoundsK<T>{body_, large_flag_.data(), frozen_grid_.bounds.data()});
    build_grid(frozen_grid_, nullptr, n_, n_frozen);
  }
  frozen_dirty_ = s.frozen_dirty;
  be_.sync();
}

}  // namespace lockstep::gpu
