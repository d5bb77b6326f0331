// The CUDA instantiation of the ORB extractor, the Hamming matcher (a warp per row) and the sub-pixel refinement.
#include "OrbPipeline.inl"

#include <cub/block/block_scan.cuh>

namespace tissuemosaic::orb {

void runOrbPipelineCuda(OrbLevelWorkspace* levels, int levelCount, const OrbSettings& settings, const int8_t* pattern) {
  runOrbPipeline<CudaBackend>(levels, levelCount, settings, pattern);
}

namespace {

constexpr int kScanThreads = 1024;
using BlockScan = cub::BlockScan<int, kScanThreads>;
static_assert(kResponseBins == kScanThreads, "one thread per response bin");

/// ResponseThreshold with a thread per bin, bins taken from the top: the threshold bin is the one where the count
/// from the top first reaches the budget; the features above it are the count before it.
__global__ void __launch_bounds__(kScanThreads) responseThresholdKernel(ResponseThreshold step) {
  __shared__ typename BlockScan::TempStorage scan;
  const int bin = kResponseBins - 1 - static_cast<int>(threadIdx.x);
  const int count = step.histogram[bin];
  int before = 0, total = 0;
  BlockScan(scan).ExclusiveSum(count, before, total);
  // The first bin from the top where the count reaches the budget (the top bin itself for a budget of 0).
  if (before + count >= step.budget && (before < step.budget || threadIdx.x == 0)) {
    step.control[kThresholdBin] = bin;
    step.control[kTakeFromThreshold] = step.budget - before;
  }
  if (threadIdx.x == 0 && total < step.budget) {  // too few features: all of them, no threshold bin
    step.control[kThresholdBin] = -1;
    step.control[kTakeFromThreshold] = 0;
  }
}

/// CellOffsets in runs of kScanThreads cells: a cell takes min(its slots in the threshold bin, what the cells before
/// it left of the threshold bin's share), and its offset is the sum of what the cells before it take in all.
__global__ void __launch_bounds__(kScanThreads) cellOffsetsKernel(CellOffsets step) {
  __shared__ typename BlockScan::TempStorage scan;
  const int share = step.control[kTakeFromThreshold];
  int atBefore = 0, offsetBefore = 0;  // over the runs before this one
  for (int first = 0; first < step.cells; first += kScanThreads) {
    const int cell = first + static_cast<int>(threadIdx.x);
    const bool inside = cell < step.cells;
    const int at = inside ? step.atThreshold[cell] : 0;
    int atPrefix = 0, atRun = 0;
    BlockScan(scan).ExclusiveSum(at, atPrefix, atRun);
    __syncthreads();  // the scan storage is used again below
    const int left = share - (atBefore + atPrefix);
    const int take = left <= 0 ? 0 : (at < left ? at : left);
    const int selected = inside ? step.above[cell] + take : 0;
    int offsetPrefix = 0, offsetRun = 0;
    BlockScan(scan).ExclusiveSum(selected, offsetPrefix, offsetRun);
    __syncthreads();
    if (inside) {
      step.atThreshold[cell] = take;
      step.offsets[cell] = offsetBefore + offsetPrefix;
    }
    atBefore += atRun;
    offsetBefore += offsetRun;
  }
  if (threadIdx.x == 0) step.control[kSelected] = offsetBefore;
}

}  // namespace

void responseThresholdCuda(const ResponseThreshold& step) {
  profiling::ScopedTimer timer("responseThresholdKernel", cuda::synchronize);
  responseThresholdKernel<<<1, kScanThreads>>>(step);
  cuda::checkLaunch("response threshold kernel");
}

void cellOffsetsCuda(const CellOffsets& step) {
  profiling::ScopedTimer timer("cellOffsetsKernel", cuda::synchronize);
  cellOffsetsKernel<<<1, kScanThreads>>>(step);
  cuda::checkLaunch("cell offsets kernel");
}

namespace {

constexpr int kWarp = 32;
constexpr int kWarpsPerBlock = 4;

/// Launches `kernel(argument, count)` with a warp per item; with TM_PROFILE_KERNELS synchronised and timed as `name`.
template <class Argument>
void launchWarpPerItem(const char* name, void (*kernel)(Argument, int), const Argument& argument, int count) {
  if (count <= 0) return;
  profiling::ScopedTimer timer(name, cuda::synchronize);
  kernel<<<(count + kWarpsPerBlock - 1) / kWarpsPerBlock, kWarp * kWarpsPerBlock>>>(argument, count);
  cuda::checkLaunch(name);
}

/// (distance, index) as one ordered key: the smaller key is the nearer row, ties to the lower index.
__device__ __forceinline__ uint64_t matchKey(int distance, int index) {
  return (static_cast<uint64_t>(distance) << 32) | static_cast<uint32_t>(index);
}

/// HammingKnn with a warp per row of A: each lane keeps the k nearest of every 32nd row of B, then k rounds of a
/// warp minimum take the overall k nearest. Keys are unique (the index is in them), so the result equals the
/// per-row loop's: the same k rows in the same order.
__global__ void hammingKnnWarpKernel(HammingKnn knn, int rowsA) {
  const int lane = threadIdx.x % kWarp;
  const int64_t row = static_cast<int64_t>(blockIdx.x) * kWarpsPerBlock + threadIdx.x / kWarp;
  if (row >= rowsA) return;  // whole warps leave together
  const int s = knn.segments.segmentOf(row);
  const int bFirst = knn.segments.bBegin[s], rowsB = knn.segments.bBegin[s + 1] - bFirst;
  const uint64_t a0 = knn.a[4 * row], a1 = knn.a[4 * row + 1], a2 = knn.a[4 * row + 2], a3 = knn.a[4 * row + 3];
  constexpr uint64_t none = ~0ull;
  uint64_t best[kMaxMatchK];
  for (int j = 0; j < kMaxMatchK; ++j) best[j] = none;
  const int k = knn.k;
  for (int r = lane; r < rowsB; r += kWarp) {
    const uint64_t key = matchKey(hammingDistance(a0, a1, a2, a3, knn.b + 4 * static_cast<int64_t>(bFirst + r)), r);
    if (key >= best[k - 1]) continue;
    int j = k - 1;
    while (j > 0 && key < best[j - 1]) {
      best[j] = best[j - 1];
      --j;
    }
    best[j] = key;
  }
  int head = 0;  // this lane's next unused entry
  for (int j = 0; j < k; ++j) {
    const uint64_t mine = head < k ? best[head] : none;
    uint64_t smallest = mine;
    for (int offset = kWarp / 2; offset > 0; offset /= 2) {
      const uint64_t other = __shfl_xor_sync(0xffffffffu, smallest, offset);
      smallest = other < smallest ? other : smallest;
    }
    if (mine == smallest && mine != none) ++head;
    if (lane == 0) {
      knn.indices[row * k + j] = smallest == none ? -1 : static_cast<int>(smallest & 0xffffffffu);
      knn.distances[row * k + j] = smallest == none ? (1 << 30) : static_cast<int>(smallest >> 32);
    }
  }
}

}  // namespace

void hammingKnnCuda(const HammingKnn& knn, int rowsA) {
  launchWarpPerItem("hammingKnnWarpKernel", hammingKnnWarpKernel, knn, rowsA);
}

namespace {

constexpr int kMaxWindowPixelsPerLane = (subpixel::kMaxTemplateSide * subpixel::kMaxTemplateSide + kWarp - 1) / kWarp;

/// Sum over the warp by butterfly: every lane ends with the same bits (a + b == b + a at each stage).
__device__ __forceinline__ double warpSum(double value) {
  for (int offset = kWarp / 2; offset > 0; offset /= 2) value += __shfl_xor_sync(0xffffffffu, value, offset);
  return value;
}

/// LucasKanadeRefine with a warp per match: the lanes share the window's pixels and sum by butterfly, then every
/// lane takes the same step (LucasKanadeRefine::update). Same samples as the CPU; only the order of the sums differs.
__global__ void lucasKanadeWarpKernel(subpixel::LucasKanadeRefine refine, int count) {
  const int lane = threadIdx.x % kWarp;
  const int64_t index = static_cast<int64_t>(blockIdx.x) * kWarpsPerBlock + threadIdx.x / kWarp;
  if (index >= count) return;  // whole warps leave together
  const subpixel::Query q = refine.queries[index];
  subpixel::Answer answer{q.toX, q.toY, 0};
  const int half = refine.halfWindowPx, n = 2 * half + 1, pixels = n * n;
  const float margin = static_cast<float>(half + 2) + refine.maxShiftPx;
  if (refine.inside(q.fromX, q.fromY, margin) && refine.inside(q.toX, q.toY, margin)) {
    const uint8_t* reference = refine.images[q.referenceImage];
    const uint8_t* image = refine.images[q.image];
    const float originX = q.fromX - half, originY = q.fromY - half;
    float templ[kMaxWindowPixelsPerLane], gx[kMaxWindowPixelsPerLane], gy[kMaxWindowPixelsPerLane];
    double hxx = 0, hxy = 0, hyy = 0;
    for (int j = 0, k = lane; k < pixels; ++j, k += kWarp) {
      subpixel::templateAt(reference, refine.width, originX, originY, k % n, k / n, templ[j], gx[j], gy[j]);
      hxx += gx[j] * gx[j];
      hxy += gx[j] * gy[j];
      hyy += gy[j] * gy[j];
    }
    hxx = warpSum(hxx);
    hxy = warpSum(hxy);
    hyy = warpSum(hyy);
    if (subpixel::textured(hxx, hxy, hyy, n)) {
      float px = q.toX, py = q.toY;
      for (int iteration = 0; iteration < subpixel::kIterations; ++iteration) {
        const float windowX = px - half, windowY = py - half;
        double bx = 0, by = 0;
        for (int j = 0, k = lane; k < pixels; ++j, k += kWarp) {
          const float e = subpixel::sampleBilinear(image, refine.width, windowX + k % n, windowY + k / n) - templ[j];
          bx += gx[j] * e;
          by += gy[j] * e;
        }
        double stepX = 0, stepY = 0;
        subpixel::solveStep(hxx, hxy, hyy, warpSum(bx), warpSum(by), stepX, stepY);
        if (refine.update(q, stepX, stepY, margin, px, py, answer)) break;
      }
    }
  }
  if (lane == 0) refine.answers[index] = answer;
}

}  // namespace

void refineSubPixelCuda(const subpixel::LucasKanadeRefine& refine, int count) {
  launchWarpPerItem("lucasKanadeWarpKernel", lucasKanadeWarpKernel, refine, count);
}

}  // namespace tissuemosaic::orb
