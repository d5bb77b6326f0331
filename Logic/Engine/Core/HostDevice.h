#pragma once
/// @file HostDevice.h
/// @brief One macro that marks a function for both backends: __host__ __device__ under nvcc, nothing otherwise.
/// Every per-pixel or per-point step is written once with it (see docs/DESIGN.md, "One algorithm, two backends").
/// TM_UNROLL asks nvcc to unroll the next loop; host compilers unroll by themselves (and warn about the pragma).
/// TM_UNROLL_BY(n) unrolls a loop of unknown length n times: a sum of independent loads then has n in flight at once
/// rather than one (the additions stay in order, so the result is the same). popcount64 counts set bits on both
/// (ORB descriptor distances, census costs).
#if defined(__CUDACC__)
#define TM_HOST_DEVICE __host__ __device__
#define TM_FORCE_INLINE __forceinline__
#define TM_UNROLL _Pragma("unroll")
#define TM_PRAGMA(text) _Pragma(#text)
#define TM_UNROLL_BY(n) TM_PRAGMA(unroll n)
#else
#define TM_HOST_DEVICE
#define TM_FORCE_INLINE inline __attribute__((always_inline))
#define TM_UNROLL
#define TM_UNROLL_BY(n)
#endif

#include <cstdint>

namespace tissuemosaic {

TM_HOST_DEVICE TM_FORCE_INLINE int popcount64(uint64_t v) {
#if defined(__CUDA_ARCH__)
  return __popcll(v);
#else
  return __builtin_popcountll(v);
#endif
}

}  // namespace tissuemosaic
