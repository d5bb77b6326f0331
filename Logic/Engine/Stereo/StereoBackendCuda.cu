// The CUDA instantiation of the section II pipeline, and the CUDA launcher of the ZNCC cost volume.
#include "Core/CudaRuntime.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "DisparitySampling.h"
#include "StereoPipeline.inl"

#include <cuda_runtime.h>

namespace tissuemosaic::stereo {

namespace {

constexpr int kThreads = 128;  // one thread per column of the tile and its halo
constexpr int kRowsPerBlock = 4;

/// One block computes kRowsPerBlock image rows for a tile of (kThreads - 2r) pixels and every disparity. The left
/// rows of the tile (with halo) and the right rows over the whole disparity span are cached in shared memory. Per
/// disparity each thread forms its column's chessboard sums of L*R for the first row, then for the next rows by
/// the exact recurrences Ce(y+1) = Co(y) -/+ one product, Co(y+1) = Ce(y) +/- one product (integer-valued floats:
/// no rounding, so the sums equal the CPU's); then each pixel combines 2r+1 columns.
/// kRadius > 0: the window radius as a constant (the paper's 11x11 window, the widest 19x19), so that the window loops
/// unroll into fixed shared-memory offsets (a third fewer instructions); 0: in.radius at run time.
template <int kRadius>
__global__ void __launch_bounds__(kThreads) znccVolumeKernel(ZnccVolumeInputs in) {
  extern __shared__ float shared[];
  const int r = kRadius > 0 ? kRadius : in.radius;
  const int cachedRows = 2 * r + kRowsPerBlock;
  const int width = in.left.width, height = in.left.height;
  const int tileWidth = kThreads - 2 * r;
  const int y0 = blockIdx.y * kRowsPerBlock;
  const int x0 = blockIdx.x * tileWidth;
  const int maxDisparity = in.minDisparity + in.disparityCount - 1;
  const int columns = kThreads;                              // c in [x0 - r, x0 + tileWidth + r)
  const int rightColumns = columns + in.disparityCount - 1;  // c - d for every d
  const int rightBegin = x0 - r - maxDisparity;
  float* leftRows = shared;
  float* rightRows = leftRows + cachedRows * columns;
  // Column sums, double-buffered by disparity parity so that one barrier per disparity suffices: a thread that
  // writes buffer (i & 1) has passed the barrier of disparity i - 1, after every read of disparity i - 2.
  float* columnBuffers = rightRows + cachedRows * rightColumns;  // [2][2][kRowsPerBlock][columns]
  const int bufferFloats = 2 * kRowsPerBlock * columns;
  // Right pixels x - d that this tile can reach: [x0 - maxDisparity, x0 + tileWidth - 1 - minDisparity].
  const int rightPixels = tileWidth + in.disparityCount - 1;
  const int rightPixelBegin = x0 - maxDisparity;
  float* rightSum = columnBuffers + 2 * bufferFloats;          // [kRowsPerBlock][rightPixels]
  float* rightNorm = rightSum + kRowsPerBlock * rightPixels;
  uint32_t* rightWinner = reinterpret_cast<uint32_t*>(rightNorm + kRowsPerBlock * rightPixels);

  for (int k = threadIdx.x; k < cachedRows * columns; k += blockDim.x) {
    const int row = k / columns, c = k % columns;
    leftRows[k] = in.left.at(clampIndex(x0 - r + c, width), clampIndex(y0 - r + row, height));
  }
  for (int k = threadIdx.x; k < cachedRows * rightColumns; k += blockDim.x) {
    const int row = k / rightColumns, c = k % rightColumns;
    rightRows[k] = in.right.at(clampIndex(rightBegin + c, width), clampIndex(y0 - r + row, height));
  }
  for (int k = threadIdx.x; k < kRowsPerBlock * rightPixels; k += blockDim.x) {
    const int row = k / rightPixels, xr = rightPixelBegin + k % rightPixels, y = y0 + row;
    const bool inside = xr >= 0 && xr < width && y < height;
    rightSum[k] = inside ? in.sumRight.at(xr, y) : 0.0f;
    rightNorm[k] = inside ? in.inverseNormRight.at(xr, y) : 0.0f;
    rightWinner[k] = 0;
  }
  __syncthreads();

  const int t = threadIdx.x;
  const int x = x0 + t;
  const bool ownsColumn = t < tileWidth && x < width;
  const int n = chessboardPixelCount(r);
  float sumL[kRowsPerBlock], normL[kRowsPerBlock];
  int16_t best[kRowsPerBlock], bestDisparity[kRowsPerBlock];
#pragma unroll
  for (int k = 0; k < kRowsPerBlock; ++k) {
    const bool owns = ownsColumn && y0 + k < height;
    sumL[k] = owns ? in.sumLeft.at(x, y0 + k) : 0.0f;
    normL[k] = owns ? in.inverseNormLeft.at(x, y0 + k) : 0.0f;
    best[k] = kNoZncc;
    bestDisparity[k] = kNoDisparity;
  }

  for (int i = 0; i < in.disparityCount; ++i) {
    const int d = in.minDisparity + i;
    float* columnEven = columnBuffers + (i & 1) * bufferFloats;
    float* columnOdd = columnEven + kRowsPerBlock * columns;
    {
      const int rightOffset = t + maxDisparity - d;  // column (x0 - r + t) - d in the right cache
      const auto product = [&](int cachedRow) {
        return leftRows[cachedRow * columns + t] * rightRows[cachedRow * rightColumns + rightOffset];
      };
      float e, o;
      chessboardColumnSums([&](int dy) { return product(dy + r); }, r, e, o);
      columnEven[t] = e;
      columnOdd[t] = o;
#pragma unroll
      for (int k = 1; k < kRowsPerBlock; ++k) {
        const float leaving = product(k - 1);   // row y0 + k - 1 - r
        const float entering = product(k + 2 * r);  // row y0 + k + r
        const float nextEven = (r & 1) ? o - leaving : o + entering;
        const float nextOdd = (r & 1) ? e + entering : e - leaving;
        e = nextEven;
        o = nextOdd;
        columnEven[k * columns + t] = e;
        columnOdd[k * columns + t] = o;
      }
    }
    __syncthreads();
    if (ownsColumn) {
      const bool matchable = x - d >= 0 && x - d < width;
#pragma unroll
      for (int k = 0; k < kRowsPerBlock; ++k) {
        const int y = y0 + k;
        if (y >= height) break;
        int16_t q = kNoZncc;
        if (matchable) {
          const float sumLR = chessboardWindowSum(
              [&](int dx, bool even) { return (even ? columnEven : columnOdd)[k * columns + t + r + dx]; }, r);
          const int rightIndex = k * rightPixels + (x - d - rightPixelBegin);
          q = quantisedZncc(sumLR, sumL[k], rightSum[rightIndex], normL[k], rightNorm[rightIndex], n);
          // Within one disparity every thread owns a different right pixel, and disparities are separated by a
          // barrier: a plain compare-and-store merges the candidates.
          const uint32_t key = packRightWinner(q, i);
          if (q != kNoZncc && key > rightWinner[rightIndex]) rightWinner[rightIndex] = key;
        }
        in.volume[in.volumeIndex(i, x, y)] = q;
        if (q > best[k]) {
          best[k] = q;
          bestDisparity[k] = static_cast<int16_t>(d);
        }
      }
    }
  }
  __syncthreads();
  if (ownsColumn) {
#pragma unroll
    for (int k = 0; k < kRowsPerBlock; ++k) {
      if (y0 + k < height) in.bestDisparity.at(x, y0 + k) = bestDisparity[k];
    }
  }
  // This tile's right-view candidates join those of the other tiles that reach the same right pixels.
  for (int k = threadIdx.x; k < kRowsPerBlock * rightPixels; k += blockDim.x) {
    const int row = k / rightPixels, xr = rightPixelBegin + k % rightPixels, y = y0 + row;
    if (rightWinner[k] != 0 && xr >= 0 && xr < width && y < height) {
      atomicMax(&in.rightWinnerKeys[static_cast<int64_t>(y) * width + xr], rightWinner[k]);
    }
  }
}

/// Right-view winners from their packed keys; clears the keys for the next frame.
struct UnpackRightWinners {
  uint32_t* keys;
  int minDisparity;
  ImageView<int16_t> rightBestDisparity;
  __device__ void operator()(int64_t index) const {
    rightBestDisparity[index] = unpackRightWinner(keys[index], minDisparity);
    keys[index] = 0;
  }
};

}  // namespace

void computeZnccVolumeCuda(const ZnccVolumeInputs& inputs) {
  const int r = inputs.radius;
  const int cachedRows = 2 * r + kRowsPerBlock;
  const int tileWidth = kThreads - 2 * r;
  const std::size_t rightPixels = tileWidth + inputs.disparityCount - 1;
  const std::size_t sharedBytes =
      sizeof(float) * (static_cast<std::size_t>(cachedRows) * (2 * kThreads + inputs.disparityCount - 1) +
                       4 * kRowsPerBlock * kThreads + 3 * kRowsPerBlock * rightPixels);
  // Compiled radii: StereoParameters' default 11x11 window, and the widest, 19x19, which HD frames want
  // (docs/STEREO.md, "Limits"); other radii take the run-time form.
  constexpr int kPaperRadius = 5, kWidestRadius = 9;
  const int variant = r == kPaperRadius ? 1 : (r == kWidestRadius ? 2 : 0);
  void (*const kernels[3])(ZnccVolumeInputs) = {znccVolumeKernel<0>, znccVolumeKernel<kPaperRadius>,
                                                znccVolumeKernel<kWidestRadius>};
  void (*kernel)(ZnccVolumeInputs) = kernels[variant];
  static std::size_t raisedLimit[3] = {48 * 1024, 48 * 1024, 48 * 1024};
  std::size_t& raised = raisedLimit[variant];
  if (sharedBytes > raised) {
    const cudaError_t status =
        cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, static_cast<int>(sharedBytes));
    if (status != cudaSuccess) {
      throw Error("the disparity range is too wide for the GPU's shared memory (" + std::to_string(sharedBytes) +
                  " bytes): " + cudaGetErrorString(status));
    }
    raised = sharedBytes;
  }
  const dim3 grid((inputs.left.width + tileWidth - 1) / tileWidth, (inputs.left.height + kRowsPerBlock - 1) / kRowsPerBlock);
  {
    profiling::ScopedTimer timer("znccVolumeKernel", cuda::synchronize);
    kernel<<<grid, kThreads, sharedBytes>>>(inputs);
    cuda::checkLaunch("ZNCC cost volume kernel");
  }
  parallelFor<CudaBackend>(inputs.left.pixelCount(),
                           UnpackRightWinners{inputs.rightWinnerKeys, inputs.minDisparity, inputs.rightBestDisparity});
}

void detectHighlightSeedsCuda(const DetectHighlightSeeds& seeds) {
  parallelFor<CudaBackend>(seeds.left.pixelCount(), seeds);
}

void runStereoPipelineCuda(StereoWorkspace& workspace, const StereoParameters& parameters, StereoTimingsMs& timings,
                           StereoExplanation* explanation) {
  runStereoPipeline<CudaBackend>(workspace, parameters, timings,
                                 {computeZnccVolumeCuda, computeScanlinePathsCuda, detectHighlightSeedsCuda}, explanation);
}

}  // namespace tissuemosaic::stereo

namespace tissuemosaic {

namespace {

struct SampleDisparities {
  ImageView<const float> disparityPx;
  const float* pointsXyPx;
  float* disparitiesPx;
  TM_HOST_DEVICE void operator()(int64_t i) const {
    disparitiesPx[i] = sampleDisparityPx(disparityPx, pointsXyPx[2 * i], pointsXyPx[2 * i + 1]);
  }
};

}  // namespace

void sampleDisparitiesCuda(ImageView<const float> disparityPx, const float* pointsXyPx, float* disparitiesPx, int count) {
  parallelFor<CudaBackend>(count, SampleDisparities{disparityPx, pointsXyPx, disparitiesPx});
}

}  // namespace tissuemosaic
