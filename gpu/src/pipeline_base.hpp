// What GpuWorld needs of a pipeline, whichever backend runs it.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gpu_state.hpp"
#include "initial_state.hpp"
#include "lockstep/gpu/gpu_engine.hpp"
#include "lockstep/gpu/soa.hpp"

namespace lockstep::gpu {

// The state as World<T> would hold it, downloaded on demand.
template <class T>
struct HostState {
  std::vector<T4<T>> pos, rot, vel, ang;
  std::vector<std::uint8_t> flags;
  std::vector<int> sleep_frame;
  // Run-time inputs (gpu_inputs.hpp) only, when download's `full` is set:
  std::vector<int> sleep_counter;
  std::vector<int> rest_count, rest_body;  // eq 108's records: per body their count, kMaxRests supporters each
};

template <class T>
class PipelineBase {
 public:
  virtual ~PipelineBase() = default;
  virtual void step() = 0;
  // The state; with `full`, the sleep counters and eq 108's supporters too.
  virtual void download(HostState<T>& out, bool full = false) = 0;
  // A pipeline rebuilt for run-time inputs goes on from this frame.
  void set_frame(int frame) { frame_ = frame; }
  // Snapshots (gpu_state.hpp): everything following frames read, downloaded
  // or uploaded by the same code on either backend. load expects a state
  // checked against this pipeline's scene (gpu_snapshot.cpp).
  virtual void save(GpuState<T>& out) = 0;
  virtual void load(const GpuState<T>& in) = 0;
  // Ground and SDF contact records per slot (8 with the ground, 9 per SDF volume).
  virtual int imm_stride() const = 0;

  int frame() const { return frame_; }
  int body_count() const { return n_; }
  int awake_count() const { return n_awake_; }
  bool on_device() const { return on_device_; }
  const std::string& description() const { return description_; }
  const StageCounters& counters() const { return counters_; }
  StageTimes stage_times() const { return times_; }
  void reset_stage_times() { times_ = StageTimes{}; }

 protected:
  int n_ = 0;
  int frame_ = 0;
  int n_awake_ = 0;
  bool on_device_ = false;
  std::string description_;
  StageCounters counters_;
  StageTimes times_;
};

// Instantiated for float and Q16 (host.cpp, device.cu).
template <class T>
std::unique_ptr<PipelineBase<T>> make_host_pipeline(const InitialState<T>& s, const GpuOptions& options,
                                                    const std::string& description);
// Defined only when built with CUDA.
template <class T>
std::unique_ptr<PipelineBase<T>> make_device_pipeline(const InitialState<T>& s, const GpuOptions& options);
// Number of CUDA devices (0 when built without CUDA or when none is usable).
int cuda_device_count();

}  // namespace lockstep::gpu
