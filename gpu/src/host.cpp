// The host build of the GPU engine: the pipeline over HostBackend.
#include "host_backend.hpp"
#include "pipeline.hpp"

namespace lockstep::gpu {

std::unique_ptr<PipelineBase> make_host_pipeline(const InitialState& s, const GpuOptions& options,
                                                 const std::string& description) {
  return std::make_unique<Pipeline<HostBackend>>(s, options, description, false);
}

}  // namespace lockstep::gpu
