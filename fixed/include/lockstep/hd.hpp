// LS_HD marks a function usable on host and device (CUDA). Outside nvcc it is empty.
#pragma once
#if defined(__CUDACC__)
#define LS_HD __host__ __device__
#else
#define LS_HD
#endif
