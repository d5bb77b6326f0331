#pragma once
// The GPU launcher of the stereo box filters (included by StereoPipeline.inl in CUDA translation units only).
// One block filters a 32x32 tile: it caches the tile and its halo in shared memory, sums the row windows, then the
// column windows (running sums over short runs), and hands every pixel's (sum, count) to the same consumers as the CPU path. The sums are exact
// integers (StereoKernels.h), so they equal the CPU's running sums. Radii whose tile does not fit in shared memory
// fall back to the direct per-pixel passes.
#include "Core/CudaRuntime.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "StereoKernels.h"

#include <cuda_runtime.h>

#include <string>
#include <typeinfo>

namespace tissuemosaic::stereo {

constexpr int kBoxTile = 32;
constexpr int kBoxThreads = 256;
/// Running sums: a thread sums one window, then slides it over this many outputs (two shared reads per step instead
/// of 2r+1). Rows: kBoxTile / kBoxRowRun runs per cached row; columns: kBoxTile columns x kBoxTile / kBoxColumnRun.
constexpr int kBoxRowRun = 8;
constexpr int kBoxColumnRun = 4;
static_assert(kBoxTile * (kBoxTile / kBoxColumnRun) == kBoxThreads, "one column run per thread");

/// Odd row pitch of the shared tiles: threads that walk neighbouring rows then hit distinct banks.
__host__ __device__ inline int boxPitch(int radius) { return (kBoxTile + 2 * radius) | 1; }

/// Shared memory of one tile; Sum is the value type's exact tile accumulator (int32 where it cannot overflow).
template <class Sum>
inline std::size_t boxFilterSharedBytes(int radius) {
  const std::size_t span = kBoxTile + 2 * radius, pitch = boxPitch(radius);
  return span * pitch * (sizeof(Sum) + sizeof(uint8_t)) + kBoxTile * pitch * (sizeof(Sum) + sizeof(int16_t)) + 16;
}

template <class Value, class Consumer>
__global__ void __launch_bounds__(kBoxThreads) boxFilterKernel(Value value, Consumer consumer, int width, int height,
                                                               int radius) {
  using Sum = typename Value::TileSum;
  extern __shared__ int64_t boxShared[];
  const int span = kBoxTile + 2 * radius, pitch = boxPitch(radius), side = 2 * radius + 1;
  Sum* values = reinterpret_cast<Sum*>(boxShared);                         // [span rows][pitch]
  Sum* rowSums = values + span * pitch;                                    // [kBoxTile columns][pitch]: transposed
  int16_t* rowCounts = reinterpret_cast<int16_t*>(rowSums + kBoxTile * pitch);  // [kBoxTile columns][pitch]
  uint8_t* valid = reinterpret_cast<uint8_t*>(rowCounts + kBoxTile * pitch);    // [span rows][pitch]
  const int x0 = blockIdx.x * kBoxTile, y0 = blockIdx.y * kBoxTile;

  for (int k = threadIdx.x; k < span * span; k += blockDim.x) {
    const int column = k % span, row = k / span;
    const int x = x0 - radius + column, y = y0 - radius + row;
    int64_t v = 0;
    const bool ok = x >= 0 && y >= 0 && x < width && y < height && value(x, y, v);
    values[row * pitch + column] = ok ? static_cast<Sum>(v) : Sum(0);
    valid[row * pitch + column] = ok;
  }
  __syncthreads();
  // Row windows: neighbouring threads take neighbouring rows of one run.
  for (int k = threadIdx.x; k < span * (kBoxTile / kBoxRowRun); k += blockDim.x) {
    const int row = k % span, c0 = (k / span) * kBoxRowRun;
    const Sum* in = values + row * pitch;
    const uint8_t* ok = valid + row * pitch;
    Sum sum = 0;
    int count = 0;
    for (int dx = 0; dx < side; ++dx) {
      sum += in[c0 + dx];
      count += ok[c0 + dx];
    }
    for (int c = c0;; ++c) {
      rowSums[c * pitch + row] = sum;
      rowCounts[c * pitch + row] = static_cast<int16_t>(count);
      if (c + 1 == c0 + kBoxRowRun) break;
      sum += in[c + side] - in[c];
      count += ok[c + side] - ok[c];
    }
  }
  __syncthreads();
  // Column windows: a warp takes the 32 columns of one run.
  {
    const int c = threadIdx.x % kBoxTile, row0 = (threadIdx.x / kBoxTile) * kBoxColumnRun;
    const Sum* in = rowSums + c * pitch;
    const int16_t* counts = rowCounts + c * pitch;
    Sum sum = 0;
    int count = 0;
    for (int dy = 0; dy < side; ++dy) {
      sum += in[row0 + dy];
      count += counts[row0 + dy];
    }
    const int x = x0 + c;
    for (int row = row0;; ++row) {
      const int y = y0 + row;
      if (x < width && y < height) consumer(static_cast<int64_t>(y) * width + x, static_cast<int64_t>(sum), count);
      if (row + 1 == row0 + kBoxColumnRun) break;
      sum += in[row + side] - in[row];
      count += counts[row + side] - counts[row];
    }
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
  static const std::string name = std::string("boxFilterKernel<") + typeid(Consumer).name() + ">";
  profiling::ScopedTimer timer(name.c_str(), cuda::synchronize);
  const dim3 grid((width + kBoxTile - 1) / kBoxTile, (height + kBoxTile - 1) / kBoxTile);
  boxFilterKernel<<<grid, kBoxThreads, bytes>>>(value, consumer, width, height, radius);
  cuda::checkLaunch("box filter kernel");
  return true;
}

}  // namespace tissuemosaic::stereo
