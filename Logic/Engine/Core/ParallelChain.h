#pragma once
/// @file ParallelChain.h
/// @brief parallelChain<Backend>(chainLoop(n1, f1), chainLoop(n2, f2), ...) runs the loops one after another, each
/// over its whole range before the next starts: on CUDA as ONE kernel of one block with a barrier between loops, on
/// the CPU serially on the calling thread. For short dependent loops (tens to a few hundred light items each, e.g.
/// the pose LM's per-frame bookkeeping) whose cost is their launches, not their work: each launch costs
/// microseconds on the host and on the device, and one block on one multiprocessor is plenty for such loops.
#include "ParallelFor.h"

#include <cstdint>
#include <tuple>
#include <typeinfo>

namespace tissuemosaic {

template <class Functor>
struct ChainLoop {
  int64_t count;
  Functor functor;
};

template <class Functor>
ChainLoop<Functor> chainLoop(int64_t count, const Functor& functor) {
  return ChainLoop<Functor>{count, functor};
}

template <class Backend>
struct ParallelChain;

template <>
struct ParallelChain<CpuBackend> {
  template <class... Functors>
  static void run(const ChainLoop<Functors>&... loops) {
    profiling::ScopedTimer timer(typeid(std::tuple<Functors...>).name());
    const auto runLoop = [](const auto& loop) {
      for (int64_t i = 0; i < loop.count; ++i) loop.functor(i);
    };
    (runLoop(loops), ...);
  }
};

#if defined(__CUDACC__)
template <class Functor>
__device__ void runChainLoopInBlock(const ChainLoop<Functor>& loop) {
  for (int64_t i = threadIdx.x; i < loop.count; i += blockDim.x) loop.functor(i);
  __syncthreads();  // every item's writes are visible to the next loop (global memory, one block)
}

template <class... Functors>
__global__ void parallelChainKernel(ChainLoop<Functors>... loops) {
  (runChainLoopInBlock(loops), ...);
}

template <>
struct ParallelChain<CudaBackend> {
  static constexpr int kThreads = 256;

  template <class... Functors>
  static void run(const ChainLoop<Functors>&... loops) {
    profiling::ScopedTimer timer(typeid(std::tuple<Functors...>).name(), cuda::synchronize);
    parallelChainKernel<<<1, kThreads>>>(loops...);
    cuda::checkLaunch("parallelChain kernel");
  }
};
#endif

template <class Backend, class... Functors>
void parallelChain(const ChainLoop<Functors>&... loops) {
  ParallelChain<Backend>::run(loops...);
}

}  // namespace tissuemosaic
