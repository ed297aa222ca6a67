// A type-erased engine run: the harness, `lockstep run` and the benchmarks
// drive every engine (fixed, float, double, mp, gpu) through this interface.
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lockstep/input.hpp"
#include "lockstep/scene.hpp"
#include "lockstep/world.hpp"

namespace lockstep {

// One body's state, converted to double (exact for Q16 and float).
struct BodySnapshot {
  double p[3];      // position (m)
  double q[4];      // orientation w, x, y, z
  double v[3];      // velocity (m/s)
  double w[3];      // angular velocity (rad/s)
  bool asleep;
  int sleep_frame;  // -1: not asleep yet
};

// A World<T> body as a snapshot (converted to double): what WorldRun<T>::body
// returns, and what tests compare other engines' bodies with.
template <class T>
BodySnapshot snapshot_of(const Body<T>& b) {
  auto d = [](const T& x) { return Num<T>::to_double(x); };
  return {{d(b.p.x), d(b.p.y), d(b.p.z)},
          {d(b.q.w), d(b.q.x), d(b.q.y), d(b.q.z)},
          {d(b.v.x), d(b.v.y), d(b.v.z)},
          {d(b.w.x), d(b.w.y), d(b.w.z)},
          b.asleep,
          b.asleep ? b.sleep_frame : -1};
}

// One contact the narrow phase found in the last step (docs/SPEC.md 7.2 step
// 3), converted to double: body a against body b (b = -1: the ground, -2 - k:
// SDF volume k); n points from b towards a; penetration > 0 is overlap (m).
struct ContactSnapshot {
  int a = 0, b = -1;
  double point[3] = {0, 0, 0};
  double normal[3] = {0, 0, 0};
  double penetration = 0;
};

// Every body's state after one stage of a frame (`lockstep replay`'s
// bisection): the stage's name ("5 solve", docs/SPEC.md 7.2) and the bodies.
struct StageState {
  std::string stage;
  std::vector<BodySnapshot> bodies;
};

class EngineRun {
 public:
  virtual ~EngineRun() = default;
  virtual std::string name() const = 0;          // "fixed", "float", "double", "mp", "gpu"
  virtual std::string description() const = 0;  // e.g. "gpu (host build: no CUDA device)"
  virtual void step() = 0;                       // throws RunError
  virtual int frame() const = 0;
  virtual int body_count() const = 0;
  virtual BodySnapshot body(int i) const = 0;
  virtual std::uint64_t state_hash() const = 0;  // eq 92
  virtual double energy() const = 0;             // (J)
  virtual StageCounters counters() const = 0;
  // Raw Q16.16 state of body i (p, q, v, w: 13 int32) for the fixed engine; empty otherwise.
  virtual std::vector<std::int32_t> raw_state(int /*i*/) const { return {}; }
  // Steps on `threads` threads from now on (docs/SPEC.md 7.7 "Threads"):
  // the CPU engines (World<T>::set_threads), the same bits for every count.
  // Others take 1 only; they throw std::invalid_argument naming the value.
  virtual void set_threads(int threads) {
    if (threads != 1)
      throw std::invalid_argument("--threads " + std::to_string(threads) + ": the " + name() +
                                  " engine schedules its own work; threads apply to fixed, float, double and mp (give 1)");
  }
  // Whether contacts() reports the engine's contacts (the CPU engines do).
  virtual bool has_contacts() const { return false; }
  // The contacts found in the last step, in the engine's order.
  virtual std::vector<ContactSnapshot> contacts() const { return {}; }
  // Steps one frame and returns every body's state after each of its stages
  // (docs/SPEC.md 7.2), in order; the frame's bits are step()'s. An engine
  // that cannot stop between stages (gpu) steps and returns nothing.
  virtual std::vector<StageState> step_stages() {
    step();
    return {};
  }
  // Applies a run-time input now (lockstep/input.hpp, docs/SPEC.md "Run-time
  // inputs"): input.frame must be frame() + 1. Every engine of
  // engine_names() implements it; throws std::invalid_argument for a bad
  // input (a stale id, a body the loader would refuse, ...). Inline, as
  // save_state below.
  virtual void apply(const Input& /*input*/) {
    throw std::invalid_argument("the " + name() + " engine takes no run-time inputs");
  }
  // The engine's snapshot (docs/SNAPSHOTS.md); every engine of
  // engine_names() has them (the gpu engine's: "The GPU engine"), others
  // throw std::invalid_argument.
  // Inline: the GPU engine's library derives from EngineRun without linking this one.
  virtual std::vector<std::uint8_t> save_state() const {
    throw std::invalid_argument("the " + name() +
                                " engine has no snapshots (the engines fixed, float, double, mp and gpu have)");
  }
};

// Engine names in a fixed order; "gpu" is present when the GPU engine is built
// (its host build when no CUDA device is found).
std::vector<std::string> engine_names();
// Variants that make_engine also accepts, named on request only (not in
// engine_names()): "gpu-jacobi" (when "gpu" is present), the GPU engine with
// its Jacobi pair solver (docs/GPU.md "Contact resolution"), and "gpu-fixed",
// the GPU engine on Q16.16 (World<Q16>'s bits, docs/GPU.md "gpu-fixed").
std::vector<std::string> engine_variants();
// engine_names() then engine_variants(): every name make_engine accepts.
std::vector<std::string> accepted_engine_names();
// Why engine `name` cannot run `scene` ("" when it can). Every engine runs
// every scene today, both pair models included (docs/GPU.md "Pair models");
// the hook stays for an engine that implements part of the spec: make_engine
// refuses with its reason and engine_names_for leaves it out.
std::string engine_limitation(std::string_view name, const Scene& scene);
// engine_names() less those with a limitation for `scene`.
std::vector<std::string> engine_names_for(const Scene& scene);
// Throws std::invalid_argument naming the allowed engines, or the engine's
// limitation for this scene; throws SceneError (validate_scene_for,
// lockstep/scene_limits.hpp) when the engine's number type cannot represent a
// body of the scene, naming the field, the value, the limit and a fix.
std::unique_ptr<EngineRun> make_engine(std::string_view name, const Scene& scene);
// Engines made after set_quiet_engines(true) print no notes on stderr (the
// gpu engine's "host build" note when it runs on the CPU).
void set_quiet_engines(bool quiet);
// How the gpu engine was built: "CUDA" (and whether a device is present),
// "host build only (no CUDA)", or "not built".
std::string gpu_build_description();

// An engine resumed from a snapshot: World<T>::load_state on the number type
// the snapshot's header names (GpuWorld::load_state for the gpu engine's),
// and the loaded world's scene. Throws SnapshotError for a bad snapshot.
struct ResumedEngine {
  std::unique_ptr<EngineRun> engine;
  Scene scene;
};
ResumedEngine engine_from_snapshot(const std::vector<std::uint8_t>& bytes);

// The CPU engines: a World<T> behind EngineRun.
template <class T>
class WorldRun final : public EngineRun {
 public:
  explicit WorldRun(const Scene& scene) : world_(scene) {}
  explicit WorldRun(World<T>&& world) : world_(std::move(world)) {}
  std::string name() const override { return Num<T>::kName; }
  std::string description() const override;
  void step() override { world_.step(); }
  void set_threads(int threads) override { world_.set_threads(threads); }
  std::vector<StageState> step_stages() override;
  void apply(const Input& input) override { world_.apply(input); }
  int frame() const override { return world_.frame(); }
  int body_count() const override { return static_cast<int>(world_.bodies().size()); }
  BodySnapshot body(int i) const override;
  std::uint64_t state_hash() const override { return world_.state_hash(); }
  double energy() const override { return world_.energy(); }
  StageCounters counters() const override { return world_.counters(); }
  std::vector<std::int32_t> raw_state(int i) const override;
  bool has_contacts() const override { return true; }
  std::vector<ContactSnapshot> contacts() const override;
  std::vector<std::uint8_t> save_state() const override { return world_.save_state(); }
  World<T>& world() { return world_; }
  const World<T>& world() const { return world_; }

 private:
  World<T> world_;
};

}  // namespace lockstep
