// gpu-fixed for the certification driver (driver.cpp, -DLOCKSTEP_CERTIFY_GPU_FIXED):
// the GPU engine's pipeline on Q16.16, host build (gpu/src/host.cpp), behind
// the part of World<Q16>'s interface the driver uses: step, frame, the state
// hash (eq 92 over the raw Q16.16 values, as World<Q16>::state_hash) and
// per body its state. Needs gpu/src/{host,initial_state}.cpp and no other
// part of the GPU engine (no snapshots, inputs or JSON).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "initial_state.hpp"
#include "pipeline_base.hpp"

namespace lockstep::certify {

class GpuFixedEngine {
 public:
  struct BodyState {
    Vec3<Q16> p, v, w;
    Quat<Q16> q;
    bool asleep = false;
    int sleep_frame = -1;
    int sleep_counter = 0;
  };

  explicit GpuFixedEngine(const Scene& scene) {
    gpu::GpuOptions o;
    o.backend = gpu::Backend::kHost;
    o.quiet = true;
    pipeline_ = gpu::make_host_pipeline<Q16>(gpu::make_initial_state<Q16>(scene), o, "gpu-fixed (certification)");
    refresh();
  }
  void step() {
    pipeline_->step();
    refresh();
  }
  int frame() const { return pipeline_->frame(); }
  const std::vector<BodyState>& bodies() const { return bodies_; }
  std::uint64_t state_hash() const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    auto byte = [&h](std::uint8_t b) { h ^= b; h *= 0x100000001b3ull; };
    auto value = [&](Q16 x) {
      const auto u = static_cast<std::uint32_t>(x.raw());
      for (int s = 0; s < 32; s += 8) byte(static_cast<std::uint8_t>(u >> s));
    };
    for (const BodyState& b : bodies_) {
      for (Q16 x : {b.p.x, b.p.y, b.p.z, b.q.w, b.q.x, b.q.y, b.q.z, b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z}) value(x);
      byte(b.asleep ? 1 : 0);
    }
    return h;
  }

 private:
  void refresh() {
    gpu::HostState<Q16> s;
    pipeline_->download(s, true);
    bodies_.resize(s.pos.size());
    for (std::size_t i = 0; i < s.pos.size(); ++i) {
      BodyState& b = bodies_[i];
      b.p = gpu::xyz(s.pos[i]);
      b.q = gpu::quat(s.rot[i]);
      b.v = gpu::xyz(s.vel[i]);
      b.w = gpu::xyz(s.ang[i]);
      b.asleep = (s.flags[i] & gpu::kFlagAsleep) != 0;
      b.sleep_frame = s.sleep_frame[i];
      b.sleep_counter = s.sleep_counter[i];
    }
  }
  std::unique_ptr<gpu::PipelineBase<Q16>> pipeline_;
  std::vector<BodyState> bodies_;
};

}  // namespace lockstep::certify
