// Rollback netcode on lockstep's fixed engine: two peers simulate pile1000,
// each sends its player's inputs to the other, which receives them kDelay
// frames late. A peer never waits: it predicts that the other player did
// nothing, and when an input arrives for a frame it has already simulated it
// rolls back (restores the snapshot of the frame before the input) and
// simulates again up to the present. Because the fixed engine gives the same
// bits everywhere, both peers end in the same state, and in the state of a
// run that knew every input in time: the program checks both and exits 1
// otherwise. It prints what one rollback of kDelay = 8 frames costs.
//
// Build: part of the lockstep build (target `rollback`); run ./build/examples/rollback.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <vector>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/fixed/q16_vec.hpp"  // World<Q16>: the fixed engine
#include "lockstep/world.hpp"

using lockstep::BodyId;
using lockstep::Input;
using lockstep::InputKind;
using World = lockstep::World<lockstep::Q16>;

constexpr int kDelay = 8;                 // frames an input takes to reach the other peer
constexpr int kFrames = 200;              // frames to simulate
constexpr int kSnapshots = kDelay + 2;    // saved states kept: frames now-kDelay-1 .. now

// What player `peer` does before frame `frame` (a game reads its controller
// here). `world` is the peer's own, predicted world: ids name bodies, points
// are world points.
std::vector<Input> player_inputs(int peer, int frame, const World& world) {
  std::vector<Input> out;
  Input in;
  in.frame = frame;
  if (peer == 0 && (frame == 20 || frame == 90)) {  // kick a box of the top layer, off-centre
    in.kind = InputKind::impulse;
    in.id = BodyId{frame == 20 ? 905u : 944u, 0};
    const auto& b = world.body(world.index_of(in.id));
    in.a = {4.0, 6.0, 0.0};                                          // J (N s)
    in.b = {b.p.x.to_double() + 0.3, b.p.y.to_double(), b.p.z.to_double()};  // where (m)
    out.push_back(in);
  }
  if (peer == 0 && frame == 60) {  // drop a crate on the pile
    in.kind = InputKind::create;
    in.body.half_extents = {0.75, 0.5, 0.75};
    in.body.mass = 4.0;
    in.body.position = {0.0, 18.0, 0.0};
    out.push_back(in);
  }
  if (peer == 1 && frame == 35) {  // remove a box from the middle of the pile
    in.kind = InputKind::destroy;
    in.id = BodyId{455u, 0};
    out.push_back(in);
  }
  if (peer == 1 && (frame == 75 || frame == 120 || frame == 150)) {  // push a box for one frame
    in.kind = InputKind::force;
    in.id = BodyId{frame == 75 ? 990u : 909u, 0};
    in.a = {0.0, 0.0, 600.0};  // F (N)
    out.push_back(in);
  }
  return out;
}

struct Message {  // one frame of one player's inputs, sent every frame (empty too)
  int frame;
  std::vector<Input> inputs;
};

class Peer {
 public:
  explicit Peer(int id) : id_(id), world_(*lockstep::builtin_scene("pile1000")), saved_(kSnapshots) {}

  // Simulates the next frame: our player's inputs, sent to the other peer.
  Message advance() {
    const int frame = world_.frame() + 1;
    inputs_[id_][frame] = player_inputs(id_, frame, world_);
    simulate(frame);
    return {frame, inputs_[id_][frame]};
  }

  // The other peer's inputs of an earlier frame. We predicted "no input";
  // if it did something, roll back to the frame before it and simulate again.
  void receive(const Message& m) {
    inputs_[1 - id_][m.frame] = m.inputs;
    if (m.inputs.empty()) return;  // the prediction was right
    const auto start = std::chrono::steady_clock::now();
    const int now = world_.frame();
    world_.restore_state(saved_[(m.frame - 1) % kSnapshots]);  // the state before frame m.frame
    for (int f = m.frame; f <= now; ++f) simulate(f);
    rollback_ms_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }

  const World& world() const { return world_; }
  const std::vector<double>& rollback_ms() const { return rollback_ms_; }

 private:
  // Saves the state before `frame`, applies both players' known inputs of
  // it (always in the same order: player 0's, then player 1's) and steps.
  void simulate(int frame) {
    world_.save_state(saved_[(frame - 1) % kSnapshots]);
    for (int p = 0; p < 2; ++p)
      for (const Input& in : inputs_[p][frame]) world_.apply(in);
    world_.step();
  }

  int id_;
  World world_;
  std::vector<std::vector<std::uint8_t>> saved_;  // ring of snapshots, by frame
  std::map<int, std::vector<Input>> inputs_[2];   // per player: frame -> inputs
  std::vector<double> rollback_ms_;
};

int main() {
  Peer peers[2] = {Peer(0), Peer(1)};
  std::deque<std::pair<int, Message>> wire[2];  // to peer p: (arrival frame, message)
  std::map<int, std::vector<Input>> sent[2];     // every input each player made, by frame
  for (int frame = 1; frame <= kFrames + kDelay; ++frame) {
    for (int p = 0; p < 2; ++p) {
      // Deliver what arrives now, then simulate (the last kDelay frames only
      // deliver: every input is known at the end).
      while (!wire[p].empty() && wire[p].front().first <= frame) {
        peers[p].receive(wire[p].front().second);
        wire[p].pop_front();
      }
      if (frame > kFrames) continue;
      const Message m = peers[p].advance();
      sent[p][m.frame] = m.inputs;
      wire[1 - p].push_back({frame + kDelay, m});
    }
  }

  // A run that knew every input in time: what both peers must have reached.
  World truth(*lockstep::builtin_scene("pile1000"));
  for (int frame = 1; frame <= kFrames; ++frame) {
    for (int p = 0; p < 2; ++p)
      for (const Input& in : sent[p][frame]) truth.apply(in);
    truth.step();
  }

  std::vector<double> ms = peers[0].rollback_ms();
  ms.insert(ms.end(), peers[1].rollback_ms().begin(), peers[1].rollback_ms().end());
  std::sort(ms.begin(), ms.end());
  if (ms.empty()) ms.push_back(0.0);  // no rollback: nothing was late (cannot happen with these inputs)
  const std::uint64_t h0 = peers[0].world().state_hash(), h1 = peers[1].world().state_hash();
  std::printf("pile1000 on the fixed engine, %d frames, inputs %d frames late: %zu rollbacks\n", kFrames, kDelay, ms.size());
  std::printf("one rollback of %d frames (restore_state + %d steps): median %.2f ms, min %.2f ms, max %.2f ms\n", kDelay,
              kDelay, ms[ms.size() / 2], ms.front(), ms.back());
  std::printf("peer 0 %016llx, peer 1 %016llx, all inputs in time %016llx: %s\n", static_cast<unsigned long long>(h0),
              static_cast<unsigned long long>(h1), static_cast<unsigned long long>(truth.state_hash()),
              h0 == h1 && h0 == truth.state_hash() ? "equal" : "DIFFERENT");
  return h0 == h1 && h0 == truth.state_hash() && peers[0].world().save_state() == truth.save_state() ? 0 : 1;
}
