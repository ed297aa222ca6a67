// Host/device primitives of the GPU engine's kernels (stages.hpp,
// colouring.hpp): integer counters and atomics whose order cannot change a
// result, read-only loads, the neighbour lists, bit equality, and the small
// kernels of the pipeline's bookkeeping.
#pragma once
#include <cstdint>
#include <type_traits>

#include "lockstep/gpu/soa.hpp"

namespace lockstep::gpu {

// ---------------------------------------------------------------------------
// Host/device primitives.

using Counter = unsigned long long;

// Counters in the order of StageCounters' fields.
enum CounterId : int {
  kCIntegrateVelocity = 0, kCDamping, kCIntegratePosition, kCBroadphaseBodies, kCPairsTested, kCGroundContacts,
  kCSdfContacts, kCBodyContacts, kCSolverContacts, kCNormalImpulses, kCRestitutionBounces, kCFrictionSteps,
  kCCorrections, kCSettlingBodies, kCSleepUpdates, kCWakes, kCounterCount
};

// Adds v to a counter: a warp-aggregated integer atomic on the device (integer
// sums do not depend on order), a plain add in the host build.
LS_HD inline void add_counter(Counter* c, unsigned v) {
#if defined(__CUDA_ARCH__)
  const unsigned mask = __activemask();
  const unsigned sum = __reduce_add_sync(mask, v);
  if (static_cast<int>(threadIdx.x & 31u) == __ffs(static_cast<int>(mask)) - 1 && sum != 0u)
    atomicAdd(c, static_cast<Counter>(sum));
#else
  *c += v;
#endif
}

// *c += v for an int counter, warp-aggregated on the device like add_counter
// (integer sums do not depend on order).
LS_HD inline void add_to(int* c, int v) {
#if defined(__CUDA_ARCH__)
  const unsigned mask = __activemask();
  const int sum = __reduce_add_sync(mask, v);
  if (static_cast<int>(threadIdx.x & 31u) == __ffs(static_cast<int>(mask)) - 1 && sum != 0) atomicAdd(c, sum);
#else
  *c += v;
#endif
}

// *counter += 1, returning the value before (a position to write to); on the
// device the threads of a warp that claim from the same counter share one
// atomic. Which thread gets which position depends on the order of the
// threads: only for outputs whose order does not matter.
LS_HD inline int claim_one(int* counter) {
#if defined(__CUDA_ARCH__)
  const unsigned active = __activemask();
  const unsigned same = __match_any_sync(active, reinterpret_cast<unsigned long long>(counter));
  const int lane = static_cast<int>(threadIdx.x & 31u);
  const int leader = __ffs(static_cast<int>(same)) - 1;
  int base = 0;
  if (lane == leader) base = atomicAdd(counter, __popc(same));
  base = __shfl_sync(same, base, leader);
  return base + __popc(same & ((1u << lane) - 1u));
#else
  return (*counter)++;
#endif
}

// Sets *flag to 1; true for the one caller that found it 0.
LS_HD inline bool claim_flag(int* flag) {
#if defined(__CUDA_ARCH__)
  return atomicExch(flag, 1) == 0;
#else
  if (*flag != 0) return false;
  *flag = 1;
  return true;
#endif
}

LS_HD inline int fetch_add(int* counter, int v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(counter, v);
#else
  const int old = *counter;
  *counter += v;
  return old;
#endif
}

LS_HD inline void store_max(int* target, int v) {
#if defined(__CUDA_ARCH__)
  atomicMax(target, v);
#else
  if (v > *target) *target = v;
#endif
}

LS_HD inline void store_min(int* target, int v) {
#if defined(__CUDA_ARCH__)
  atomicMin(target, v);
#else
  if (v < *target) *target = v;
#endif
}

// A load from an array that no thread of the running kernel writes: on the
// device through the read-only data path (ld.global.nc), which lets the
// compiler issue it ahead of the kernel's stores (more loads in flight);
// a plain load in the host build. Only the data path differs, never the value.
template <class T>
LS_HD inline T4<T> ro(const T4<T>* p) {
#if defined(__CUDA_ARCH__)
  static_assert(sizeof(T4<T>) == sizeof(int4), "a group is one 128-bit load");
  const int4 v = __ldg(reinterpret_cast<const int4*>(p));
  T4<T> r;
  __builtin_memcpy(&r, &v, sizeof r);
  return r;
#else
  return *p;
#endif
}
template <class T>
LS_HD inline T ro(const T* p) {
#if defined(__CUDA_ARCH__)
  if constexpr (std::is_arithmetic_v<T>) {
    return __ldg(p);
  } else {  // a Q16.16: its int32 through the same path
    static_assert(sizeof(T) == sizeof(int), "a 4-byte value");
    const int v = __ldg(reinterpret_cast<const int*>(p));
    T r;
    __builtin_memcpy(&r, &v, sizeof r);
    return r;
  }
#else
  return *p;
#endif
}

// ---------------------------------------------------------------------------
// Neighbour lists: each active body's list is the block [k stride, k stride +
// count[k]) of the frame's list array (slot k), ascending by body index (GatherK sorts
// it).
struct NeighbourLists {
  int* nbr = nullptr;
  int* count = nullptr;
  int stride = 0;
  LS_HD int begin(int k) const { return k * stride; }
  LS_HD int end(int k) const { return k * stride + count[k]; }
  // The entry of `body` in slot k's list (ascending: a binary search), or -1.
  // For kernels that write none of the lists.
  LS_HD int find(int k, int body) const {
    const int last = begin(k) + ro(count + k);
    int lo = begin(k), hi = last;
    while (lo < hi) {
      const int mid = lo + (hi - lo) / 2;
      if (ro(nbr + mid) < body) lo = mid + 1;
      else hi = mid;
    }
    return lo < last && ro(nbr + lo) == body ? lo : -1;
  }
};

// ---------------------------------------------------------------------------
// Bit equality of two values (NaN included): the fixed-point sweeps stop
// when a sweep reproduces its input exactly. Both number types are 4 bytes.
template <class T>
LS_HD inline bool same_bits(const T& x, const T& y) {
  static_assert(sizeof(T) == 4, "float or Q16");
  unsigned ux, uy;
  __builtin_memcpy(&ux, &x, sizeof ux);
  __builtin_memcpy(&uy, &y, sizeof uy);
  return ux == uy;
}
template <class T>
LS_HD inline bool same_bits(const T4<T>& a, const T4<T>& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z) && same_bits(a.w, b.w);
}

// ---------------------------------------------------------------------------
// Small kernels of the pipeline's bookkeeping.

struct SetIntK {
  int* target;
  int value;
  LS_HD void operator()(int) const { *target = value; }
};

// dst[k] = src[k].
struct CopyIntsK {
  const int* src;
  int* dst;
  LS_HD void operator()(int k) const { dst[k] = src[k]; }
};

// Stream compaction: out[scan[k]] = in[k] where keep[k].
struct ScatterK {
  const int* in;
  const int* keep;
  const int* scan;
  int* out;
  LS_HD void operator()(int k) const {
    if (keep[k] != 0) out[scan[k]] = in[k];
  }
};

}  // namespace lockstep::gpu
