// The host build's backend: buffers are std::vectors, a kernel launch is a
// loop over its elements in order, the sort is a stable sort (the same
// permutation as CUB's stable radix sort), the scan and maximum are
// sequential.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

#include "lockstep/gpu/gpu_engine.hpp"
#include "grid.hpp"

namespace lockstep::gpu {

class HostBackend {
 public:
  explicit HostBackend(bool timing) : timing_(timing) {}

  template <class T>
  class Buf {
   public:
    T* data() { return v_.data(); }
    const T* data() const { return v_.data(); }
    std::size_t size() const { return v_.size(); }
    void resize(std::size_t n) {  // grows only; contents kept
      if (n > v_.size()) v_.resize(n);
    }

   private:
    std::vector<T> v_;
  };

  template <class F>
  void for_n(int n, const F& f) {
    for (int k = 0; k < n; ++k) f(k);
  }

  // Stable sort of (key, value) pairs by the low `bits` bits of the key; the
  // result is in (k0, v0).
  int sort_pairs(unsigned* k0, int* v0, unsigned* k1, int* v1, int n, int bits) {
    const unsigned mask = bits >= 32 ? 0xffffffffu : ((1u << bits) - 1u);
    order_.resize(static_cast<std::size_t>(n));
    std::iota(order_.begin(), order_.end(), 0);
    std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) { return (k0[a] & mask) < (k0[b] & mask); });
    for (int s = 0; s < n; ++s) { k1[s] = k0[order_[static_cast<std::size_t>(s)]]; v1[s] = v0[order_[static_cast<std::size_t>(s)]]; }
    std::copy(k1, k1 + n, k0);
    std::copy(v1, v1 + n, v0);
    return 0;
  }
  void sort_ints(int* a, int* /*tmp*/, int n) { std::sort(a, a + n); }
  // out[k] = sum of in[0..k) for k = 0..n (out[n] is the total).
  void exclusive_scan(const int* in, int* out, int n) {
    int s = 0;
    for (int k = 0; k < n; ++k) { out[k] = s; s += in[k]; }
    out[n] = s;
  }
  template <class T>
  void reduce_bounds(const Bounds<T>* in, int n, Bounds<T>* out) {
    Bounds<T> r;
    for (int k = 0; k < n; ++k) r = BoundsOp<T>{}(r, in[k]);
    *out = r;
  }
  void fill_int(int* p, int v, std::size_t n) { std::fill(p, p + n, v); }
  template <class T>
  void fill_zero(T* p, std::size_t n) { std::fill(p, p + n, T{}); }
  template <class T>
  void fill_minus_one(T* p, std::size_t n) {  // every bit set: each int member -1
    if (n) std::memset(static_cast<void*>(p), 0xff, n * sizeof(T));
  }
  template <class T>
  void upload(T* dst, const T* src, std::size_t n) { if (n) std::memcpy(static_cast<void*>(dst), src, n * sizeof(T)); }
  template <class T>
  void download(T* dst, const T* src, std::size_t n) { if (n) std::memcpy(static_cast<void*>(dst), src, n * sizeof(T)); }
  void sync() {}

  // Stage timing: mark(s) starts stage s (kStageCount ends the frame).
  void begin_frame() { marks_.clear(); }
  void mark(int stage) {
    if (timing_) marks_.push_back({stage, std::chrono::steady_clock::now()});
  }
  void end_frame(StageTimes& t) {
    if (!timing_) return;
    for (std::size_t m = 0; m + 1 < marks_.size(); ++m)
      t.ms[static_cast<std::size_t>(marks_[m].stage)] +=
          std::chrono::duration<double, std::milli>(marks_[m + 1].at - marks_[m].at).count();
    ++t.frames;
  }

 private:
  struct Mark {
    int stage;
    std::chrono::steady_clock::time_point at;
  };
  bool timing_;
  std::vector<int> order_;
  std::vector<Mark> marks_;
};

}  // namespace lockstep::gpu
