#pragma once
/// @file PortableAtomics.h
/// @brief The atomic operations that per-item functors (TM_HOST_DEVICE) share between the backends: CUDA's
/// atomics on the device, GCC's relaxed __atomic builtins on the CPU's thread pool. Integer operations only, so the
/// results do not depend on the order the threads run in.
#include "HostDevice.h"

#include <cstdint>

namespace tissuemosaic {

TM_HOST_DEVICE TM_FORCE_INLINE void atomicAddInt(int* target, int value) {
#if defined(__CUDA_ARCH__)
  atomicAdd(target, value);
#else
  __atomic_fetch_add(target, value, __ATOMIC_RELAXED);
#endif
}

TM_HOST_DEVICE TM_FORCE_INLINE void atomicMinU64(uint64_t* target, uint64_t value) {
#if defined(__CUDA_ARCH__)
  atomicMin(reinterpret_cast<unsigned long long*>(target), static_cast<unsigned long long>(value));
#else
  uint64_t current = __atomic_load_n(target, __ATOMIC_RELAXED);
  while (value < current &&
         !__atomic_compare_exchange_n(target, &current, value, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
#endif
}

/// Sets a flag that several threads may set at once (all to the same value).
TM_HOST_DEVICE TM_FORCE_INLINE void setFlag(uint8_t* flag) {
#if defined(__CUDA_ARCH__)
  *flag = 1;
#else
  __atomic_store_n(flag, static_cast<uint8_t>(1), __ATOMIC_RELAXED);
#endif
}

}  // namespace tissuemosaic
