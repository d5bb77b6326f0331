#pragma once
/// @file HostDevice.h
/// @brief One macro that marks a function for both backends: __host__ __device__ under nvcc, nothing otherwise.
/// Every per-pixel or per-point step is written once with it (see docs/DESIGN.md, "One algorithm, two backends").
/// TM_UNROLL asks nvcc to unroll the next loop; host compilers unroll by themselves (and warn about the pragma).
#if defined(__CUDACC__)
#define TM_HOST_DEVICE __host__ __device__
#define TM_FORCE_INLINE __forceinline__
#define TM_UNROLL _Pragma("unroll")
#else
#define TM_HOST_DEVICE
#define TM_FORCE_INLINE inline __attribute__((always_inline))
#define TM_UNROLL
#endif
