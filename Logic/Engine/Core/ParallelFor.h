#pragma once
/// @file ParallelFor.h
/// @brief The engine's one parallel loop: parallelFor<Backend>(n, functor) calls functor(i) for i in [0, n).
/// CpuBackend runs it on oneTBB's thread pool; CudaBackend (only in .cu translation units) as a grid-stride
/// kernel. Algorithms are written once as functors with a TM_HOST_DEVICE operator() and instantiated for both.
/// Not cv::parallel_for_: OpenCV runs a loop serially while any other thread is inside one (a process-wide flag),
/// which serialised the pipeline's stages that run side by side (e.g. the refiner's two matching steps).
#include "HostDevice.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>

#include "KernelProfiler.h"

#include <typeinfo>

#if defined(__CUDACC__)
#include "CudaRuntime.h"
#endif

namespace tissuemosaic {

struct CpuBackend {};
struct CudaBackend {};

template <class Backend>
struct ParallelFor;

template <>
struct ParallelFor<CpuBackend> {
  /// grain: indices per task; small for heavy items (rows), large for light ones (pixels).
  template <class Functor>
  static void run(int64_t count, const Functor& functor, int64_t grain) {
    if (count <= 0) return;
    grain = std::max<int64_t>(1, grain);
    const int64_t tasks = (count + grain - 1) / grain;
    profiling::ScopedTimer timer(typeid(Functor).name());
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, tasks), [&](const tbb::blocked_range<int64_t>& range) {
      for (int64_t task = range.begin(); task < range.end(); ++task) {
        const int64_t end = std::min(count, (task + 1) * grain);
        for (int64_t i = task * grain; i < end; ++i) functor(i);
      }
    });
  }
};

#if defined(__CUDACC__)
template <class Functor>
__global__ void parallelForKernel(int64_t count, Functor functor) {
  const int64_t stride = static_cast<int64_t>(blockDim.x) * gridDim.x;
  for (int64_t i = static_cast<int64_t>(blockIdx.x) * blockDim.x + threadIdx.x; i < count; i += stride) functor(i);
}

template <>
struct ParallelFor<CudaBackend> {
  template <class Functor>
  static void run(int64_t count, const Functor& functor, int64_t /*grain*/) {
    if (count <= 0) return;
    // 256 threads a block, fewer for small counts (features, cells, matches: heavy, latency-bound items) so that
    // every multiprocessor gets at least two blocks.
    int threads = 256;
    const int64_t wantedBlocks = 2 * static_cast<int64_t>(cuda::multiprocessorCount());
    while (threads > 32 && (count + threads - 1) / threads < wantedBlocks) threads /= 2;
    const int64_t blocks = std::min<int64_t>((count + threads - 1) / threads, 65535);
    profiling::ScopedTimer timer(typeid(Functor).name(), cuda::synchronize);
    parallelForKernel<<<static_cast<unsigned>(blocks), threads>>>(count, functor);
    cuda::checkLaunch("parallelFor kernel");
  }
};
#endif

/// Threads the CPU backend's loops run on (oneTBB's pool, or fewer under a tbb::global_control cap): what the engine
/// sizes its CPU work by and reports. Not cv::getNumThreads(): OpenCV's own setting (e.g. OPENCV_FOR_THREADS_NUM)
/// does not limit these loops.
inline int cpuThreadCount() {
  const auto cap = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()), cap));
}

template <class Backend, class Functor>
void parallelFor(int64_t count, const Functor& functor, int64_t grain = 4096) {
  ParallelFor<Backend>::run(count, functor, grain);
}

}  // namespace tissuemosaic
