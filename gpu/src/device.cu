// The CUDA backend of the GPU engine: device buffers, one kernel per functor
// of stages.hpp, CUB's stable radix sort, prefix sum and maximum, CUDA events
// for the stage times. Built with --fmad=false so that the device rounds
// every operation as the host build does (docs/GPU.md "Host and device").
#include <cuda_profiler_api.h>
#include <cuda_runtime.h>

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_reduce.cuh>
#include <cub/device/device_scan.cuh>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "lockstep/gpu/formula_cases.hpp"
#include "pipeline.hpp"

namespace lockstep::gpu {
namespace {

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("gpu: ") + what + ": " + cudaGetErrorString(e));
}

constexpr int kBlock = 256;

template <class F>
__global__ void for_n_kernel(int n, F f) {
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (k < n) f(k);
}

// The heavy per-body kernels (gather, solver) are latency-bound; their
// register cap is set by a number of blocks per multiprocessor:
// LOCKSTEP_GPU_MIN_BLOCKS for the solver's kernels (and gpu-fixed's pair
// correction, PairTurnK<Q16>), LOCKSTEP_GPU_GATHER_BLOCKS for the gather.
// Measured (docs/GPU.md "Performance"): 2 for the solver (its registers
// without spills) beats 3 and 4, whose spills cost more than the extra warps
// gain; gpu-fixed's kernels at 1 (255 registers) lost as much; PairTurnK<Q16>
// at 2 took 6.4 ms a 10^6 frame against 7.5 uncapped (162 registers).
#ifndef LOCKSTEP_GPU_MIN_BLOCKS
#define LOCKSTEP_GPU_MIN_BLOCKS 2
#endif
#ifndef LOCKSTEP_GPU_GATHER_BLOCKS
#define LOCKSTEP_GPU_GATHER_BLOCKS 2
#endif
template <int MinBlocks, class F>
__global__ void __launch_bounds__(kBlock, MinBlocks) for_n_kernel_bounded(int n, F f) {
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (k < n) f(k);
}

template <class F>
constexpr int kMinBlocks = std::is_same_v<F, GatherK<float>> || std::is_same_v<F, GatherK<Q16>> ? LOCKSTEP_GPU_GATHER_BLOCKS
                           : std::is_same_v<F, ContactsK<float>> || std::is_same_v<F, SolveK<float>> ||
                                     std::is_same_v<F, SolveEdgeK<float>> || std::is_same_v<F, ContactsK<Q16>> ||
                                     std::is_same_v<F, SolveK<Q16>> || std::is_same_v<F, SolveEdgeK<Q16>> ||
                                     std::is_same_v<F, PairTurnK<Q16>>
                               ? LOCKSTEP_GPU_MIN_BLOCKS
                               : 0;

class DeviceBackend {
 public:
  explicit DeviceBackend(bool timing) : timing_(timing) {
    check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
  }
  ~DeviceBackend() {
    for (cudaEvent_t e : events_) cudaEventDestroy(e);
    cudaFree(temp_);
    cudaStreamDestroy(stream_);
  }
  DeviceBackend(const DeviceBackend&) = delete;
  DeviceBackend& operator=(const DeviceBackend&) = delete;

  template <class T>
  class Buf {
   public:
    Buf() = default;
    Buf(const Buf&) = delete;
    Buf& operator=(const Buf&) = delete;
    ~Buf() { cudaFree(p_); }
    T* data() { return p_; }
    const T* data() const { return p_; }
    std::size_t size() const { return n_; }
    void resize(std::size_t n) {  // grows only; contents kept
      if (n <= n_) return;
      const std::size_t cap = n + n / 4;
      T* q = nullptr;
      check(cudaMalloc(&q, cap * sizeof(T)), "cudaMalloc");
      if (n_ > 0) check(cudaMemcpy(q, p_, n_ * sizeof(T), cudaMemcpyDeviceToDevice), "cudaMemcpy");
      cudaFree(p_);
      p_ = q;
      n_ = cap;
    }

   private:
    T* p_ = nullptr;
    std::size_t n_ = 0;
  };

  template <class F>
  void for_n(int n, const F& f) {
    if (n <= 0) return;
    if constexpr (kMinBlocks<F> > 0)
      for_n_kernel_bounded<kMinBlocks<F>><<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, f);
    else for_n_kernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, f);
    check(cudaGetLastError(), "kernel launch");
  }

  int sort_pairs(unsigned* k0, int* v0, unsigned* k1, int* v1, int n, int bits) {
    if (n <= 1) return 0;
    cub::DoubleBuffer<unsigned> keys(k0, k1);
    cub::DoubleBuffer<int> vals(v0, v1);
    std::size_t bytes = 0;
    check(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys, vals, n, 0, bits, stream_), "SortPairs size");
    check(cub::DeviceRadixSort::SortPairs(temp(bytes), bytes, keys, vals, n, 0, bits, stream_), "SortPairs");
    return keys.Current() == k0 ? 0 : 1;
  }
  void sort_ints(int* a, int* tmp, int n) {
    if (n <= 1) return;
    cub::DoubleBuffer<int> keys(a, tmp);
    std::size_t bytes = 0;
    check(cub::DeviceRadixSort::SortKeys(nullptr, bytes, keys, n, 0, 32, stream_), "SortKeys size");
    check(cub::DeviceRadixSort::SortKeys(temp(bytes), bytes, keys, n, 0, 32, stream_), "SortKeys");
    if (keys.Current() != a) check(cudaMemcpyAsync(a, tmp, n * sizeof(int), cudaMemcpyDeviceToDevice, stream_), "copy");
  }
  // out[k] = sum of in[0..k) for k = 0..n; in must have n + 1 elements (in[n] is zeroed).
  void exclusive_scan(int* in, int* out, int n) {
    check(cudaMemsetAsync(in + n, 0, sizeof(int), stream_), "memset");
    std::size_t bytes = 0;
    check(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, n + 1, stream_), "ExclusiveSum size");
    check(cub::DeviceScan::ExclusiveSum(temp(bytes), bytes, in, out, n + 1, stream_), "ExclusiveSum");
  }
  // min/max reductions are exact: the result does not depend on CUB's order.
  template <class T>
  void reduce_bounds(const Bounds<T>* in, int n, Bounds<T>* out) {
    std::size_t bytes = 0;
    check(cub::DeviceReduce::Reduce(nullptr, bytes, in, out, n, BoundsOp<T>{}, Bounds<T>{}, stream_), "Reduce size");
    check(cub::DeviceReduce::Reduce(temp(bytes), bytes, in, out, n, BoundsOp<T>{}, Bounds<T>{}, stream_), "Reduce");
  }
  void fill_int(int* p, int v, std::size_t n) {  // v is 0 or -1 (a byte pattern)
    check(cudaMemsetAsync(p, v == 0 ? 0 : 0xff, n * sizeof(int), stream_), "memset");
  }
  template <class T>
  void fill_zero(T* p, std::size_t n) { check(cudaMemsetAsync(p, 0, n * sizeof(T), stream_), "memset"); }
  template <class T>
  void fill_minus_one(T* p, std::size_t n) {  // every bit set: each int member -1
    check(cudaMemsetAsync(p, 0xff, n * sizeof(T), stream_), "memset");
  }
  template <class T>
  void upload(T* dst, const T* src, std::size_t n) {
    if (n) check(cudaMemcpyAsync(dst, src, n * sizeof(T), cudaMemcpyHostToDevice, stream_), "upload");
    sync();
  }
  template <class T>
  void download(T* dst, const T* src, std::size_t n) {
    if (n) check(cudaMemcpyAsync(dst, src, n * sizeof(T), cudaMemcpyDeviceToHost, stream_), "download");
  }
  void sync() { check(cudaStreamSynchronize(stream_), "cudaStreamSynchronize"); }

  void begin_frame() { used_ = 0; stages_.clear(); }
  void mark(int stage) {
    if (!timing_) return;
    if (used_ == events_.size()) {
      cudaEvent_t e;
      check(cudaEventCreate(&e), "cudaEventCreate");
      events_.push_back(e);
    }
    check(cudaEventRecord(events_[used_], stream_), "cudaEventRecord");
    stages_.push_back(stage);
    ++used_;
  }
  void end_frame(StageTimes& t) {
    if (!timing_) return;
    sync();
    for (std::size_t m = 0; m + 1 < used_; ++m) {
      float ms = 0.0f;
      check(cudaEventElapsedTime(&ms, events_[m], events_[m + 1]), "cudaEventElapsedTime");
      t.ms[static_cast<std::size_t>(stages_[m])] += ms;
    }
    ++t.frames;
  }

 private:
  void* temp(std::size_t bytes) {
    if (bytes > temp_bytes_) {
      cudaFree(temp_);
      temp_bytes_ = bytes + bytes / 2;
      check(cudaMalloc(&temp_, temp_bytes_), "cudaMalloc temp");
    }
    return temp_;
  }
  bool timing_;
  cudaStream_t stream_ = nullptr;
  void* temp_ = nullptr;
  std::size_t temp_bytes_ = 0;
  std::vector<cudaEvent_t> events_;
  std::vector<int> stages_;
  std::size_t used_ = 0;
};

__global__ void formula_kernel(int kind, Params<float> P, int n, const float* in, float* out) {
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (k < n) evaluate_formula_case(kind, P, in + k * kFormulaInputs, out + k * kFormulaOutputs);
}

}  // namespace

int cuda_device_count() {
  int n = 0;
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();  // clear the error state
    return 0;
  }
  return n;
}

void profiler_capture(bool on) {
  if (cuda_device_count() == 0) return;
  check(on ? cudaProfilerStart() : cudaProfilerStop(), "cudaProfiler");
}

DeviceInfo device_info() {
  DeviceInfo info;
  if (cuda_device_count() == 0) return info;
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, 0), "cudaGetDeviceProperties");
  info.name = prop.name;
  info.multiprocessors = prop.multiProcessorCount;
  info.memory_gib = static_cast<double>(prop.totalGlobalMem) / (1024.0 * 1024.0 * 1024.0);
  return info;
}

double measure_copy_bandwidth(std::size_t bytes, int repetitions) {
  if (cuda_device_count() == 0 || repetitions < 1) return 0.0;
  void* a = nullptr;
  void* b = nullptr;
  check(cudaMalloc(&a, bytes), "cudaMalloc");
  check(cudaMalloc(&b, bytes), "cudaMalloc");
  check(cudaMemset(a, 1, bytes), "cudaMemset");
  check(cudaMemset(b, 2, bytes), "cudaMemset");
  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "cudaEventCreate");
  check(cudaEventCreate(&stop), "cudaEventCreate");
  std::vector<float> ms;
  for (int r = 0; r < repetitions + 2; ++r) {  // two warm-up copies
    check(cudaEventRecord(start), "cudaEventRecord");
    check(cudaMemcpy(r % 2 ? a : b, r % 2 ? b : a, bytes, cudaMemcpyDeviceToDevice), "cudaMemcpy");
    check(cudaEventRecord(stop), "cudaEventRecord");
    check(cudaEventSynchronize(stop), "cudaEventSynchronize");
    float t = 0.0f;
    check(cudaEventElapsedTime(&t, start, stop), "cudaEventElapsedTime");
    if (r >= 2) ms.push_back(t);
  }
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  cudaFree(a);
  cudaFree(b);
  std::sort(ms.begin(), ms.end());
  const double median = ms[ms.size() / 2];
  return 2.0 * static_cast<double>(bytes) / (median * 1e-3) / 1e9;
}

template <class T>
std::unique_ptr<PipelineBase<T>> make_device_pipeline(const InitialState<T>& s, const GpuOptions& options) {
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, 0), "cudaGetDeviceProperties");
  const char* name = Num<T>::kExact ? "gpu-fixed: CUDA on " : "gpu: CUDA on ";
  return std::make_unique<Pipeline<DeviceBackend, T>>(s, options, std::string(name) + prop.name, true);
}
template std::unique_ptr<PipelineBase<float>> make_device_pipeline<float>(const InitialState<float>&, const GpuOptions&);
template std::unique_ptr<PipelineBase<Q16>> make_device_pipeline<Q16>(const InitialState<Q16>&, const GpuOptions&);

std::vector<float> evaluate_formula_cases_on_device(int kind, const std::vector<float>& inputs) {
  const int n = static_cast<int>(inputs.size() / kFormulaInputs);
  std::vector<float> out(static_cast<std::size_t>(n) * kFormulaOutputs);
  float* d_in = nullptr;
  float* d_out = nullptr;
  check(cudaMalloc(&d_in, inputs.size() * sizeof(float) + 4), "cudaMalloc");
  check(cudaMalloc(&d_out, out.size() * sizeof(float) + 4), "cudaMalloc");
  check(cudaMemcpy(d_in, inputs.data(), inputs.size() * sizeof(float), cudaMemcpyHostToDevice), "upload");
  if (n > 0) formula_kernel<<<(n + 127) / 128, 128>>>(kind, Params<float>::from(Constants{}), n, d_in, d_out);
  check(cudaGetLastError(), "formula kernel");
  check(cudaMemcpy(out.data(), d_out, out.size() * sizeof(float), cudaMemcpyDeviceToHost), "download");
  cudaFree(d_in);
  cudaFree(d_out);
  return out;
}

}  // namespace lockstep::gpu
