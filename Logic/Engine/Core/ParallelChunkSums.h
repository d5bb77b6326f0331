#pragma once
/// @file ParallelChunkSums.h
/// @brief parallelChunkSums<Backend, N>(chunks, chunkBegin, values, sums, skip): for every chunk c,
/// sums[c * N + k] = the sum over items i in [chunkBegin[c], chunkBegin[c + 1]) of values(i)[k], where
/// values(i, out) writes item i's N values into out (zeroed before). The items' values are never stored: for
/// per-item terms that are only needed as sums (the pose LM's 28 normal-equation terms per residual).
/// Both backends add in one order, so that they give the same bits (the engine's CPU and CUDA paths agree exactly):
/// within a chunk, "thread" t of kChunkSumThreads sums items t, t + kChunkSumThreads, ... in turn; each warp of 32
/// threads adds its lanes as a tree (lane l + lane l + h for h = 16, 8, 4, 2, 1, as CUDA's shuffles do); the warps'
/// sums are then added in warp order. CUDA runs a block per chunk; the CPU runs the chunks in parallel and repeats
/// the block's order on one thread.
/// Writing every item's values to memory and summing them in a second pass cost 3x the computation on the H100 (the
/// pose LM's ReduceTerms: a thread per chunk and term, too few threads to hide the loads).
/// skip (may be null): when *skip != 0 as the work runs, nothing is computed or written (queued work that an earlier
/// step found unnecessary, read on the device).
#include "ParallelFor.h"

#include <cstdint>

namespace tissuemosaic {

constexpr int kChunkSumThreads = 256;  ///< threads (CUDA) or thread sums (CPU) per chunk
constexpr int kChunkSumWarpSize = 32;
constexpr int kChunkSumWarps = kChunkSumThreads / kChunkSumWarpSize;

template <class Backend, int N>
struct ParallelChunkSums;

template <int N>
struct ParallelChunkSums<CpuBackend, N> {
  template <class Values>
  static void run(int chunks, const int* chunkBegin, const Values& values, double* sums, const int* skip) {
    if (chunks <= 0 || (skip && *skip)) return;
    parallelFor<CpuBackend>(
        chunks,
        [&](int64_t c) {
          double threadSums[kChunkSumThreads][N] = {};
          for (int t = 0; t < kChunkSumThreads; ++t) {
            for (int64_t i = chunkBegin[c] + t; i < chunkBegin[c + 1]; i += kChunkSumThreads) {
              double item[N] = {};
              values(i, item);
              for (int k = 0; k < N; ++k) threadSums[t][k] += item[k];
            }
          }
          double total[N] = {};
          for (int w = 0; w < kChunkSumWarps; ++w) {
            double(*lanes)[N] = threadSums + w * kChunkSumWarpSize;
            for (int half = kChunkSumWarpSize / 2; half > 0; half /= 2) {
              for (int l = 0; l < half; ++l) {
                for (int k = 0; k < N; ++k) lanes[l][k] += lanes[l + half][k];
              }
            }
            for (int k = 0; k < N; ++k) total[k] += lanes[0][k];
          }
          for (int k = 0; k < N; ++k) sums[c * N + k] = total[k];
        },
        1);
  }
};

#if defined(__CUDACC__)
template <int N, class Values>
__global__ void __launch_bounds__(kChunkSumThreads) chunkSumsKernel(const int* chunkBegin, Values values, double* sums,
                                                                     const int* skip) {
  if (skip && *skip) return;
  __shared__ double warpSums[kChunkSumWarps][N];
  const int c = blockIdx.x;
  double sum[N];
  TM_UNROLL
  for (int k = 0; k < N; ++k) sum[k] = 0.0;
  for (int64_t i = chunkBegin[c] + threadIdx.x; i < chunkBegin[c + 1]; i += kChunkSumThreads) {
    double item[N];
    TM_UNROLL
    for (int k = 0; k < N; ++k) item[k] = 0.0;
    values(i, item);
    TM_UNROLL
    for (int k = 0; k < N; ++k) sum[k] += item[k];
  }
  const int lane = threadIdx.x % kChunkSumWarpSize, warp = threadIdx.x / kChunkSumWarpSize;
  TM_UNROLL
  for (int k = 0; k < N; ++k) {
    double x = sum[k];
    for (int half = kChunkSumWarpSize / 2; half > 0; half /= 2) x += __shfl_down_sync(0xffffffffu, x, half);
    if (lane == 0) warpSums[warp][k] = x;
  }
  __syncthreads();
  for (int k = threadIdx.x; k < N; k += kChunkSumThreads) {
    double total = 0.0;
    for (int w = 0; w < kChunkSumWarps; ++w) total += warpSums[w][k];
    sums[static_cast<int64_t>(c) * N + k] = total;
  }
}

template <int N>
struct ParallelChunkSums<CudaBackend, N> {
  template <class Values>
  static void run(int chunks, const int* chunkBegin, const Values& values, double* sums, const int* skip) {
    if (chunks <= 0) return;
    profiling::ScopedTimer timer(typeid(Values).name(), cuda::synchronize);
    chunkSumsKernel<N><<<static_cast<unsigned>(chunks), kChunkSumThreads>>>(chunkBegin, values, sums, skip);
    cuda::checkLaunch("chunk sums kernel");
  }
};
#endif

template <class Backend, int N, class Values>
void parallelChunkSums(int chunks, const int* chunkBegin, const Values& values, double* sums,
                       const int* skip = nullptr) {
  ParallelChunkSums<Backend, N>::run(chunks, chunkBegin, values, sums, skip);
}

}  // namespace tissuemosaic
