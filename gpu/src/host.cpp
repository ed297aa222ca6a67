// The host build of the GPU engine: the pipeline over HostBackend, for both
// number types (float: "gpu", Q16.16: "gpu-fixed").
#include "host_backend.hpp"
#include "pipeline.hpp"

namespace lockstep::gpu {

template <class T>
std::unique_ptr<PipelineBase<T>> make_host_pipeline(const InitialState<T>& s, const GpuOptions& options,
                                                    const std::string& description) {
  return std::make_unique<Pipeline<HostBackend, T>>(s, options, description, false);
}

template std::unique_ptr<PipelineBase<float>> make_host_pipeline<float>(const InitialState<float>&, const GpuOptions&,
                                                                        const std::string&);
template std::unique_ptr<PipelineBase<Q16>> make_host_pipeline<Q16>(const InitialState<Q16>&, const GpuOptions&,
                                                                    const std::string&);

}  // namespace lockstep::gpu
