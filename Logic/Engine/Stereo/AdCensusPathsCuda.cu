// The CUDA launcher of AD-Census's scanline optimisation: a warp per path, the disparities across its lanes.
// A path is serial along its pixels, so a thread per path (the CPU's form) leaves the GPU nearly idle: on the H100
// it took 136 ms at 960x540 x 101 disparities. Here every step of a path is one warp-wide update: each lane owns
// disparities lane, lane + 32, ..., the previous step's costs sit in shared memory for the d +- 1 neighbours, and
// the step's minimum is a warp reduction. All four directions run in one launch and add into pathCost with integer
// atomics, which are exact in any order: the sum equals the CPU's bit for bit.
#include "Core/CudaRuntime.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "StereoPipeline.h"

#include <cuda_runtime.h>

#include <climits>

namespace tissuemosaic::stereo {

namespace {

constexpr int kWarpLanes = 32;
constexpr int kWarpsPerBlock = 4;
constexpr int kMaxSlots = 32;  // disparities per lane: StereoParameters allows up to 1024 disparities

__device__ int32_t warpMinimum(int32_t value) {
#pragma unroll
  for (int offset = kWarpLanes / 2; offset > 0; offset /= 2) value = min(value, __shfl_xor_sync(0xffffffffu, value, offset));
  return value;
}

/// kSlots: disparities per lane, ceil(disparityCount / 32) rounded up to a power of two (registers are indexed by
/// unrolled loops only).
template <int kSlots>
__global__ void __launch_bounds__(kWarpsPerBlock * kWarpLanes) scanlinePathsKernel(ScanlineInputs in) {
  __shared__ int32_t rows[kWarpsPerBlock][2][kSlots * kWarpLanes];
  const int lane = threadIdx.x % kWarpLanes, warp = threadIdx.x / kWarpLanes;
  const VolumeGeometry& g = in.g;
  // Warps are numbered through the paths of direction 0, then 1, ...
  int path = blockIdx.x * kWarpsPerBlock + warp, k = 0;
  while (k < kScanlineDirectionCount && path >= ScanlineDirection::number(k).pathCount(g)) {
    path -= ScanlineDirection::number(k).pathCount(g);
    ++k;
  }
  if (k == kScanlineDirectionCount) return;  // the whole warp: no barrier below involves other warps
  const ScanlineDirection direction = ScanlineDirection::number(k);
  const int D = g.disparityCount, length = direction.length(g);
  int32_t* previous = rows[warp][0];
  int32_t* current = rows[warp][1];

  int x, y;
  direction.start(g, path, x, y);
  // The next step's costs are loaded one step ahead, so that their latency overlaps the current step's update.
  int32_t upcoming[kSlots];
  const auto loadCosts = [&](int atX, int atY) {
    const int32_t* cost = in.cost + (static_cast<int64_t>(atY) * g.width + atX) * D;
#pragma unroll
    for (int j = 0; j < kSlots; ++j) {
      const int i = lane + j * kWarpLanes;
      upcoming[j] = i < D ? __ldg(cost + i) : 0;
    }
  };
  loadCosts(x, y);
  int32_t previousMin = 0;
  for (int s = 0; s < length; ++s, x += direction.dx, y += direction.dy) {
    int32_t cost[kSlots];
#pragma unroll
    for (int j = 0; j < kSlots; ++j) cost[j] = upcoming[j];
    if (s + 1 < length) loadCosts(x + direction.dx, y + direction.dy);
    const int px = x - direction.dx, py = y - direction.dy;
    const bool leftEdge = s > 0 && greyEdge(in.leftGrey, x, y, px, py, in.edgeGrey);
    int32_t* sum = in.pathCost + (static_cast<int64_t>(y) * g.width + x) * D;
    int32_t localMin = INT_MAX;
#pragma unroll
    for (int j = 0; j < kSlots; ++j) {
      const int i = lane + j * kWarpLanes;
      if (i >= D) break;
      int32_t value = cost[j];
      if (s > 0) {
        const int edges = pathEdges(in, leftEdge, x, y, px, py, i);
        value = pathCostStep(cost[j], i > 0 ? previous[i - 1] : kPathUnreachable, previous[i],
                             i + 1 < D ? previous[i + 1] : kPathUnreachable, previousMin, in.penalties.small[edges],
                             in.penalties.large[edges]);
      }
      current[i] = value;
      atomicAdd(sum + i, value);
      localMin = min(localMin, value);
    }
    previousMin = warpMinimum(localMin);
    __syncwarp();  // this step's row is complete before the next step reads it and overwrites the one before
    int32_t* swap = previous;
    previous = current;
    current = swap;
  }
}

template <int kSlots>
void launchScanlinePaths(const ScanlineInputs& inputs, int paths) {
  const int blocks = (paths + kWarpsPerBlock - 1) / kWarpsPerBlock;
  scanlinePathsKernel<kSlots><<<blocks, kWarpsPerBlock * kWarpLanes>>>(inputs);
}

}  // namespace

void computeScanlinePathsCuda(const ScanlineInputs& inputs) {
  const VolumeGeometry& g = inputs.g;
  if (g.disparityCount > kMaxSlots * kWarpLanes) {
    throw Error("the scanline optimisation takes at most " + std::to_string(kMaxSlots * kWarpLanes) +
                " disparities on the GPU, not " + std::to_string(g.disparityCount));
  }
  int paths = 0;
  for (int k = 0; k < kScanlineDirectionCount; ++k) paths += ScanlineDirection::number(k).pathCount(g);
  const int slots = (g.disparityCount + kWarpLanes - 1) / kWarpLanes;
  cuda::setZero(inputs.pathCost, static_cast<std::size_t>(g.elementCount()) * sizeof(int32_t));
  profiling::ScopedTimer timer("scanlinePathsKernel", cuda::synchronize);
  if (slots <= 1) launchScanlinePaths<1>(inputs, paths);
  else if (slots <= 2) launchScanlinePaths<2>(inputs, paths);
  else if (slots <= 4) launchScanlinePaths<4>(inputs, paths);
  else if (slots <= 8) launchScanlinePaths<8>(inputs, paths);
  else if (slots <= 16) launchScanlinePaths<16>(inputs, paths);
  else launchScanlinePaths<kMaxSlots>(inputs, paths);
  cuda::checkLaunch("scanline optimisation kernel");
}

}  // namespace tissuemosaic::stereo
