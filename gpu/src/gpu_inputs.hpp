// The GPU engine's run-time inputs (docs/GPU.md "Run-time inputs", docs/SPEC.md
// "Run-time inputs"): the same inputs as World<T>, applied to a host copy of
// the state between frames and taken up by rebuilding the pipeline before the
// next step, with the bodies in World<T>'s index order (a creation appends,
// a removal closes the gap) and World<T>'s ids (BodyIds). The rebuilt
// pipeline starts without a warm-start cache (eq 96) and without eq 108's
// records: deterministic (the same inputs in the same frames give the same
// bits), but not World<T>'s bits.
#pragma once
#include <memory>
#include <utility>
#include <vector>

#include "initial_state.hpp"
#include "lockstep/body_ids.hpp"
#include "lockstep/input.hpp"
#include "lockstep/scene.hpp"
#include "pipeline_base.hpp"

namespace lockstep::gpu {

template <class T>
class GpuInputs {
 public:
  using F4 = T4<T>;
  explicit GpuInputs(const Scene& scene) : scene_(scene) { ids_.reset(scene.bodies.size()); }

  // Applies the input to the host copy (downloaded from `pipeline` first
  // when there is none); `frame` is the pipeline's. Returns the created id
  // (create) or input.id. Throws std::invalid_argument as World<T>::apply.
  BodyId apply(const Input& input, PipelineBase<T>& pipeline);
  // Whether inputs wait for a rebuild, and the edited state they left.
  bool pending() const { return dirty_; }
  const HostState<T>& state() const { return edit_; }
  const std::vector<F4>& inert() const { return inert_; }
  int body_count() const { return static_cast<int>(scene_.bodies.size()); }
  // The initial state of the rebuilt pipeline (the pending forces applied,
  // eq 121); clears pending().
  InitialState<T> take_state();
  const BodyIds& ids() const { return ids_; }
  // Snapshots (gpu_world.cpp): the bodies' shapes now (created ones
  // appended), and the id table of a loaded snapshot.
  const Scene& scene() const { return scene_; }
  void set_ids(BodyIds ids) { ids_ = std::move(ids); }
  // Wakes (5.1) that inputs caused since the last take_state (the stage
  // counter's share of the inputs).
  std::uint64_t wakes() const { return wakes_; }

 private:
  struct Force { int body; Vec3<T> f, tau; };
  void begin(PipelineBase<T>& pipeline);
  void wake(std::size_t i);
  void wake_resting_on(std::size_t i);
  void wake_all();
  void erase(std::size_t i);

  Scene scene_;     // every body's shape (created ones appended), as World<T>::scene()
  BodyIds ids_;
  HostState<T> edit_;  // full: with sleep counters and eq 108's supporters
  std::vector<F4> half_, inert_;  // per body, as InitialState
  std::vector<Force> forces_;     // ascending body
  bool dirty_ = false;   // an input changed the copy: the next step rebuilds the pipeline
  int copy_frame_ = -1;  // the frame whose state edit_ holds (-1: none)
  std::uint64_t wakes_ = 0;
};

}  // namespace lockstep::gpu
