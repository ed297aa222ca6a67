// LS_HD marks a function usable on host and device (CUDA). Outside nvcc it is empty.
// LS_HD_INLINE is LS_HD for the small per-contact helpers of the hot loops
// (physics/contact.hpp, integrate.hpp), forced inline: called out of line they
// cost a fifth of the fixed engine's frame (2026-11-25, pile1000).
#pragma once
#if defined(__CUDACC__)
#define LS_HD __host__ __device__
#define LS_HD_INLINE __host__ __device__ __forceinline__
#elif defined(__GNUC__) || defined(__clang__)
#define LS_HD
#define LS_HD_INLINE inline __attribute__((always_inline))
#else
#define LS_HD
#define LS_HD_INLINE inline
#endif
