// The GPU engine's record of Q16.16 faults (gpu-fixed, docs/GPU.md
// "gpu-fixed"): where the kernels note what World<Q16>::check_faults checks.
#pragma once
#include <cstdint>

#include "kernel_support.hpp"
#include "lockstep/fixed/q16_num.hpp"

namespace lockstep::gpu {

// Each Q16 operation ORs
// its flags into the calling thread's status word (q16.hpp: thread_local on
// the host, the thread's word of a block-shared array on a device). A kernel
// clears the word when its element starts and notes it where World<Q16>
// checks (World<T>::check_faults): the frame's lowest (quantity << 26 | body)
// and the OR of the flags, both integer atomics (min and OR: order-free), so
// the pipeline stops the run after the frame with World<Q16>'s frame, the
// first body by index in the first stage that faulted, and its quantity.
// For float nothing is recorded (non-finite values: CommitSleepK).
struct FaultSink {
  int* code = nullptr;         // lowest quantity << kFaultBodyBits | body; INT_MAX: none
  unsigned* flags = nullptr;   // the Q16Flag bits raised
};
inline constexpr int kFaultBodyBits = 26;  // bodies < 2^26
// The quantities in the order of the frame's stages (docs/SPEC.md 7.2), as
// World<T>::check_faults names them (fault_quantity_name).
enum FaultQuantity : int {
  kFqVelocity = 0,  // stage 1
  kFqSupportWake,   // 2a, eq 108
  kFqPairContact,   // 3: box-box contact (oriented-box model) or body contact (AABB model)
  kFqGround,
  kFqSdf,
  kFqLoad,          // eqs 112, 115-117
  kFqSleeperLoad,   // eq 124
  kFqPreparation,   // 5
  kFqWarmStart,
  kFqImpulse,       // with the ground or an SDF volume
  kFqImpulseBody,   // with another body
  kFqSettling,      // 6
  kFqCorrection,    // 7
  kFqPosition,      // 8
  kFqSleep,         // 9
  kFqCount
};
inline const char* fault_quantity_name(int q, bool oriented) {
  switch (q) {
    case kFqVelocity: return "velocity (gravity, damping)";
    case kFqSupportWake: return "support wake";
    case kFqPairContact: return oriented ? "box-box contact" : "body contact";
    case kFqGround: return "ground contact";
    case kFqSdf: return "SDF contact";
    case kFqLoad: return "load (eq 117)";
    case kFqSleeperLoad: return "sleeper load (eq 124)";
    case kFqPreparation: return "contact preparation";
    case kFqWarmStart: return "warm start impulse";
    case kFqImpulse: return "contact impulse";
    case kFqImpulseBody: return "contact impulse (with another body)";
    case kFqSettling: return "settling";
    case kFqCorrection: return "position correction";
    case kFqPosition: return "position/orientation";
    case kFqSleep: return "sleep";
    default: return "?";
  }
}
LS_HD inline void or_flags(unsigned* target, unsigned v) {
#if defined(__CUDA_ARCH__)
  atomicOr(target, v);
#else
  *target |= v;
#endif
}
// The element's faults so far are none (the status word may hold an earlier
// kernel's, or, on a device, anything).
template <class T>
LS_HD inline void clear_faults() {
  if constexpr (Num<T>::kExact) (void)q16_take_status();
}
// Notes the faults raised since the last clear or note against body and quantity.
template <class T>
LS_HD inline void note_faults(const FaultSink& sink, int body, int quantity) {
  if constexpr (Num<T>::kExact) {
    const std::uint32_t f = q16_take_status();
    if (f != 0 && sink.code != nullptr) {
      store_min(sink.code, (quantity << kFaultBodyBits) | body);
      or_flags(sink.flags, f);
    }
  }
}

}  // namespace lockstep::gpu
