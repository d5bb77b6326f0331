#pragma once
// The GPU launcher of the stereo box filters (included by StereoPipeline.inl in CUDA translation units only).
// One block filters a 32x32 tile: it caches the tile and its halo in shared memory, sums each row window, then each
// column window, and hands every pixel's (sum, count) to the same consumers as the CPU path. The sums are exact
// integers (StereoKernels.h), so they equal the CPU's running sums. Radii whose tile does not fit in shared memory
// fall back to the direct per-pixel passes.
#include "Core/CudaRuntime.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "StereoKernels.h"

#include <cuda_runtime.h>

#include <chrono>
#include <typeinfo>

namespace tissuemosaic::stereo {

constexpr int kBoxTile = 32;
constexpr int kBoxThreads = 256;

/// Shared memory of one tile; Sum is the value type's exact tile accumulator (int32 where it cannot overflow).
template <class Sum>
inline std::size_t boxFilterSharedBytes(int radius) {
  const std::size_t span = kBoxTile + 2 * radius;
  return span * span * (sizeof(Sum) + sizeof(uint8_t)) + span * kBoxTile * (sizeof(Sum) + sizeof(int16_t)) + 16;
}

template <class Value, class Consumer>
__global__ void __launch_bounds__(kBoxThreads) boxFilterKernel(Value value, Consumer consumer, int width, int height,
                                                               int radius) {
  using Sum = typename Value::TileSum;
  extern __shared__ int64_t boxShared[];
  const int span = kBoxTile + 2 * radius;
  Sum* values = reinterpret_cast<Sum*>(boxShared);                  // [span][span]
  Sum* rowSums = values + span * span;                              // [span][kBoxTile]
  int16_t* rowCounts = reinterpret_cast<int16_t*>(rowSums + span * kBoxTile);  // [span][kBoxTile]
  uint8_t* valid = reinterpret_cast<uint8_t*>(rowCounts + span * kBoxTile);    // [span][span]
  const int x0 = blockIdx.x * kBoxTile, y0 = blockIdx.y * kBoxTile;

  for (int k = threadIdx.x; k < span * span; k += blockDim.x) {
    const int x = x0 - radius + k % span, y = y0 - radius + k / span;
    int64_t v = 0;
    const bool ok = x >= 0 && y >= 0 && x < width && y < height && value(x, y, v);
    values[k] = ok ? static_cast<Sum>(v) : Sum(0);
    valid[k] = ok;
  }
  __syncthreads();
  for (int k = threadIdx.x; k < span * kBoxTile; k += blockDim.x) {
    const int row = k / kBoxTile, c = k % kBoxTile;
    Sum sum = 0;
    int count = 0;
    for (int dx = 0; dx <= 2 * radius; ++dx) {
      sum += values[row * span + c + dx];
      count += valid[row * span + c + dx];
    }
    rowSums[k] = sum;
    rowCounts[k] = static_cast<int16_t>(count);
  }
  __syncthreads();
  for (int k = threadIdx.x; k < kBoxTile * kBoxTile; k += blockDim.x) {
    const int row = k / kBoxTile, c = k % kBoxTile;
    const int x = x0 + c, y = y0 + row;
    if (x >= width || y >= height) continue;
    Sum sum = 0;
    int count = 0;
    for (int dy = 0; dy <= 2 * radius; ++dy) {
      sum += rowSums[(row + dy) * kBoxTile + c];
      count += rowCounts[(row + dy) * kBoxTile + c];
    }
    consumer(static_cast<int64_t>(y) * width + x, static_cast<int64_t>(sum), count);
  }
}

/// Returns false (and does nothing) when the radius's tile does not fit in the GPU's shared memory.
template <class Value, class Consumer>
bool boxFilterTiledCuda(const Value& value, int radius, const Consumer& consumer, int width, int height) {
  // Windows above 41x41 could overflow an int32 tile sum: they take the direct int64 passes.
  if (sizeof(typename Value::TileSum) < sizeof(int64_t) && radius > 20) return false;
  const std::size_t bytes = boxFilterSharedBytes<typename Value::TileSum>(radius);
  static int limit = -1;
  if (limit < 0) {
    int device = 0, optIn = 0;
    cudaGetDevice(&device);
    cudaDeviceGetAttribute(&optIn, cudaDevAttrMaxSharedMemoryPerBlockOptin, device);
    limit = optIn;
  }
  if (bytes > static_cast<std::size_t>(limit)) return false;
  static std::size_t raised = 48 * 1024;
  if (bytes > raised) {
    cudaFuncSetAttribute(boxFilterKernel<Value, Consumer>, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(bytes));
    raised = bytes;
  }
  const bool profile = profiling::enabled();
  auto start = std::chrono::steady_clock::now();
  if (profile) {
    cuda::synchronize();
    start = std::chrono::steady_clock::now();
  }
  const dim3 grid((width + kBoxTile - 1) / kBoxTile, (height + kBoxTile - 1) / kBoxTile);
  boxFilterKernel<<<grid, kBoxThreads, bytes>>>(value, consumer, width, height, radius);
  cuda::checkLaunch("box filter kernel");
  if (profile) {
    cuda::synchronize();
    profiling::record(std::string("boxFilterKernel<") + typeid(Consumer).name() + ">",
                      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  return true;
}

}  // namespace tissuemosaic::stereo
