#pragma once
/// @file OrbKernels.h
/// @brief The per-pixel, per-cell and per-feature steps of the ORB extractor and the Hamming matcher, written
/// once for both backends (TM_HOST_DEVICE). All integer, except the pattern rotation (IEEE float and double basic
/// operations, no contraction): the CPU and CUDA results are identical.
#include "Core/HostDevice.h"
#include "Core/PortableAtomics.h"
#include "Core/Image.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace tissuemosaic::orb {

constexpr int kDescriptorBytes = 32;
constexpr int kPatternPairs = 256;
constexpr int kPatchRadius = 15;    ///< orientation circle and pattern disc
constexpr int kMaxPerCell = 8;      ///< bound of OrbParameters::maxPerCell
constexpr int kResponseBins = 1024; ///< 64 octaves x 16 sub-bins
constexpr int kMaxMatchK = 8;

/// One feature of a level: position, Harris response, then the intensity-centroid moments.
struct LevelKeypoint {
  int x, y;
  int64_t response;  ///< 0: empty slot
  int m10, m01;
};

/// Level control values: [0] threshold bin, [1] features to take from the threshold bin, [2] features selected.
enum Control { kThresholdBin = 0, kTakeFromThreshold = 1, kSelected = 2, kControlCount = 4 };

// ---- small portable helpers ---------------------------------------------------------------------------------------

/// floor(log2(v)) for v > 0.
TM_HOST_DEVICE TM_FORCE_INLINE int floorLog2(uint64_t v) {
#if defined(__CUDA_ARCH__)
  return 63 - __clzll(static_cast<long long>(v));
#else
  return 63 - __builtin_clzll(v);
#endif
}

/// Response bin: 16 bins per octave (the 4 bits below the leading one), monotonic in the response.
TM_HOST_DEVICE TM_FORCE_INLINE int responseBin(int64_t response) {
  const uint64_t v = static_cast<uint64_t>(response);
  const int e = floorLog2(v);
  const int mantissa = static_cast<int>((e >= 4 ? v >> (e - 4) : v << (4 - e)) & 15u);
  return e * 16 + mantissa;
}

/// Strict order of candidates: higher response first, then lower raster index.
TM_HOST_DEVICE TM_FORCE_INLINE bool better(int64_t responseA, int indexA, int64_t responseB, int indexB) {
  return responseA > responseB || (responseA == responseB && indexA < indexB);
}

// ---- pyramid and smoothing ------------------------------------------------------------------------------------------

/// Bilinear down-sampling with 16.16 fixed-point source coordinates and 8-bit weights: dst(x, y) samples the
/// source at ((x + 0.5) * scale - 0.5, ...), scale = scaleQ16 / 65536.
struct ResizeBilinear {
  ImageView<const uint8_t> source;
  ImageView<uint8_t> target;
  int64_t scaleQ16;

  TM_HOST_DEVICE void operator()(int64_t i) const {
    const int x = static_cast<int>(i % target.width), y = static_cast<int>(i / target.width);
    int64_t sx = ((2 * x + 1) * scaleQ16 - 65536) / 2, sy = ((2 * y + 1) * scaleQ16 - 65536) / 2;
    sx = sx < 0 ? 0 : sx;
    sy = sy < 0 ? 0 : sy;
    const int x0 = static_cast<int>(sx >> 16), y0 = static_cast<int>(sy >> 16);
    const int fx = static_cast<int>((sx >> 8) & 255), fy = static_cast<int>((sy >> 8) & 255);
    const int x1 = x0 + 1 < source.width ? x0 + 1 : source.width - 1;
    const int y1 = y0 + 1 < source.height ? y0 + 1 : source.height - 1;
    const int xa = x0 < source.width ? x0 : source.width - 1, ya = y0 < source.height ? y0 : source.height - 1;
    const int top = source.at(xa, ya) * (256 - fx) + source.at(x1, ya) * fx;
    const int bottom = source.at(xa, y1) * (256 - fx) + source.at(x1, y1) * fx;
    target[i] = static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
  }
};

/// 7-tap integer Gaussian (sigma about 2, as ORB smooths before its tests), separable, replicated border.
TM_HOST_DEVICE TM_FORCE_INLINE int smoothingWeight(int offset) {
  const int weights[7] = {3, 6, 9, 10, 9, 6, 3};
  return weights[offset + 3];
}
constexpr int kSmoothingSum = 46;

struct SmoothRows {
  ImageView<const uint8_t> source;
  ImageView<uint16_t> rows;
  TM_HOST_DEVICE void operator()(int64_t i) const {
    const int x = static_cast<int>(i % source.width), y = static_cast<int>(i / source.width);
    int sum = 0;
    for (int d = -3; d <= 3; ++d) sum += smoothingWeight(d) * source.clamped(x + d, y);
    rows[i] = static_cast<uint16_t>(sum);
  }
};

struct SmoothColumns {
  ImageView<const uint16_t> rows;
  ImageView<uint8_t> target;
  TM_HOST_DEVICE void operator()(int64_t i) const {
    const int x = static_cast<int>(i % rows.width), y = static_cast<int>(i / rows.width);
    int sum = 0;
    for (int d = -3; d <= 3; ++d) sum += smoothingWeight(d) * rows.clamped(x, y + d);
    constexpr int total = kSmoothingSum * kSmoothingSum;
    target[i] = static_cast<uint8_t>((sum + total / 2) / total);
  }
};

// ---- FAST-9, non-maximum suppression, Harris ----------------------------------------------------------------------

/// Offsets of the radius-3 Bresenham circle, clockwise from the top.
TM_HOST_DEVICE TM_FORCE_INLINE void fastCircle(int k, int& dx, int& dy) {
  const int xs[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
  const int ys[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};
  dx = xs[k];
  dy = ys[k];
}

/// True when the 16-bit circular mask has 9 contiguous set bits.
TM_HOST_DEVICE TM_FORCE_INLINE bool hasNineRun(uint32_t mask) {
  uint32_t run = mask | (mask << 16);  // unrolled circle: a run may wrap around
  uint32_t all = run;
  for (int j = 1; j < 9; ++j) all &= run >> j;
  return (all & 0xFFFFu) != 0;
}

/// Masks of the circle pixels brighter than p + t and darker than p - t.
TM_HOST_DEVICE TM_FORCE_INLINE bool fastCorner(const int (&d)[16], int t) {
  uint32_t bright = 0, dark = 0;
  for (int k = 0; k < 16; ++k) {
    bright |= static_cast<uint32_t>(d[k] > t) << k;
    dark |= static_cast<uint32_t>(d[k] < -t) << k;
  }
  return hasNineRun(bright) || hasNineRun(dark);
}

/// FAST-9 score: the largest t for which 9 contiguous circle pixels are all brighter than p + t (or all darker
/// than p - t), i.e. the max over arcs of the arc's smallest difference; found by bisection on the corner test.
/// 0 when it is not above threshold.
TM_HOST_DEVICE TM_FORCE_INLINE int fastScore(ImageView<const uint8_t> image, int x, int y, int threshold) {
  const int p = image.at(x, y);
  int d[16];
  for (int k = 0; k < 16; ++k) {
    int dx, dy;
    fastCircle(k, dx, dy);
    d[k] = image.at(x + dx, y + dy) - p;
  }
  // Any 9-arc contains two adjacent compass points (0, 4, 8, 12): reject most pixels with four tests.
  int bright = 0, dark = 0;
  for (int k = 0; k < 16; k += 4) {
    bright += d[k] > threshold;
    dark += d[k] < -threshold;
  }
  if (bright < 2 && dark < 2) return 0;
  if (!fastCorner(d, threshold)) return 0;
  // Corner at low (= threshold), not at high (= 255): the score is the largest t' with a corner at t' - 1.
  int low = threshold, high = 255;
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    if (fastCorner(d, middle)) low = middle;
    else high = middle;
  }
  return high;
}

struct FastScores {
  ImageView<const uint8_t> image;
  ImageView<uint8_t> scores;
  int threshold, border;
  TM_HOST_DEVICE void operator()(int64_t i) const {
    const int x = static_cast<int>(i % image.width), y = static_cast<int>(i / image.width);
    const bool inside = x >= border && y >= border && x < image.width - border && y < image.height - border;
    scores[i] = static_cast<uint8_t>(inside ? fastScore(image, x, y, threshold) : 0);
  }
};

/// Harris response 25 det(M) - trace(M)^2 (k = 0.04) of 3x3 Sobel gradients summed over the 7x7 block: exact
/// in int64 (|Ix| <= 1020, sums <= 5.1e7).
TM_HOST_DEVICE TM_FORCE_INLINE int64_t harrisResponse(ImageView<const uint8_t> image, int x, int y) {
  int64_t sxx = 0, syy = 0, sxy = 0;
  for (int v = y - 3; v <= y + 3; ++v) {
    for (int u = x - 3; u <= x + 3; ++u) {
      const int a = image.at(u - 1, v - 1), b = image.at(u, v - 1), c = image.at(u + 1, v - 1);
      const int d = image.at(u - 1, v), f = image.at(u + 1, v);
      const int g = image.at(u - 1, v + 1), h = image.at(u, v + 1), k = image.at(u + 1, v + 1);
      const int ix = (c + 2 * f + k) - (a + 2 * d + g);
      const int iy = (g + 2 * h + k) - (a + 2 * b + c);
      sxx += ix * ix;
      syy += iy * iy;
      sxy += ix * iy;
    }
  }
  const int64_t trace = sxx + syy;
  return 25 * (sxx * syy - sxy * sxy) - trace * trace;
}

/// Harris response at 3x3 maxima of the FAST score (ties: the first in raster order wins), else 0. Negative
/// responses (edges) are dropped.
struct MaximaResponses {
  ImageView<const uint8_t> image;
  ImageView<const uint8_t> scores;
  ImageView<int64_t> responses;
  TM_HOST_DEVICE void operator()(int64_t i) const {
    const int x = static_cast<int>(i % image.width), y = static_cast<int>(i / image.width);
    const int s = scores[i];
    int64_t response = 0;
    if (s > 0) {
      bool maximum = true;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0) continue;
          const int n = scores.at(x + dx, y + dy);  // s > 0 only inside the border, so neighbours exist
          const bool before = dy < 0 || (dy == 0 && dx < 0);
          maximum = maximum && (before ? s > n : s >= n);
        }
      }
      if (maximum) {
        const int64_t r = harrisResponse(image, x, y);
        response = r > 0 ? r : 0;
      }
    }
    responses[i] = response;
  }
};

// ---- grid selection -------------------------------------------------------------------------------------------------

struct CellGrid {
  int cellSize, cellsX, cellsY, perCell;
  TM_HOST_DEVICE int cellCount() const { return cellsX * cellsY; }
};

/// A candidate of a cell: Harris response (0: none) and raster index.
struct CellCandidate {
  int64_t response;
  int index;
};

/// Inserts (r, index) into a list of the best `count` candidates, best first (response desc, raster index asc).
TM_HOST_DEVICE TM_FORCE_INLINE void insertBest(int64_t r, int index, int64_t* bestResponse, int* bestIndex, int count) {
  const int last = count - 1;
  if (r <= 0 || !better(r, index, bestResponse[last], bestIndex[last])) return;
  int j = last;
  while (j > 0 && better(r, index, bestResponse[j - 1], bestIndex[j - 1])) {
    bestResponse[j] = bestResponse[j - 1];
    bestIndex[j] = bestIndex[j - 1];
    --j;
  }
  bestResponse[j] = r;
  bestIndex[j] = index;
}

/// Per row of a cell (item = cell * cellSize + row): the row's best perCell maxima, to rows[item * perCell, ...).
/// Splitting the cells into rows gives the GPU cellSize times more, shorter work items; the top perCell of a cell
/// is the top perCell of its rows' lists, so CellBest's result is the same as scanning the cell.
struct CellRowBest {
  ImageView<const int64_t> responses;
  CellGrid grid;
  CellCandidate* rows;
  TM_HOST_DEVICE void operator()(int64_t item) const {
    const int cell = static_cast<int>(item / grid.cellSize), row = static_cast<int>(item % grid.cellSize);
    const int cx = cell % grid.cellsX, cy = cell / grid.cellsX;
    int64_t bestResponse[kMaxPerCell];
    int bestIndex[kMaxPerCell];
    for (int j = 0; j < grid.perCell; ++j) {
      bestResponse[j] = 0;
      bestIndex[j] = 0;
    }
    const int y = cy * grid.cellSize + row, x0 = cx * grid.cellSize;
    const int x1 = x0 + grid.cellSize < responses.width ? x0 + grid.cellSize : responses.width;
    if (y < responses.height) {
      for (int x = x0; x < x1; ++x) insertBest(responses.at(x, y), y * responses.width + x, bestResponse, bestIndex, grid.perCell);
    }
    for (int j = 0; j < grid.perCell; ++j) rows[item * grid.perCell + j] = {bestResponse[j], bestIndex[j]};
  }
};

/// Per cell: its best perCell maxima by (response desc, raster index), merged from its rows' lists (CellRowBest)
/// and written to slots [cell * perCell, ...); empty slots have response 0.
struct CellBest {
  const CellCandidate* rows;
  int width;  ///< of the level image, to turn raster indices into positions
  CellGrid grid;
  LevelKeypoint* slots;
  TM_HOST_DEVICE void operator()(int64_t cell) const {
    int64_t bestResponse[kMaxPerCell];
    int bestIndex[kMaxPerCell];
    for (int j = 0; j < grid.perCell; ++j) {
      bestResponse[j] = 0;
      bestIndex[j] = 0;
    }
    const int64_t first = cell * grid.cellSize * grid.perCell, count = static_cast<int64_t>(grid.cellSize) * grid.perCell;
    for (int64_t k = first; k < first + count; ++k) {
      insertBest(rows[k].response, rows[k].index, bestResponse, bestIndex, grid.perCell);
    }
    for (int j = 0; j < grid.perCell; ++j) {
      LevelKeypoint& slot = slots[cell * grid.perCell + j];
      slot.x = bestIndex[j] % width;
      slot.y = bestIndex[j] / width;
      slot.response = bestResponse[j];
      slot.m10 = 0;
      slot.m01 = 0;
    }
  }
};

/// Histogram of the response bins of the filled slots.
struct ResponseHistogram {
  const LevelKeypoint* slots;
  int* histogram;
  TM_HOST_DEVICE void operator()(int64_t i) const {
    if (slots[i].response > 0) atomicAddInt(&histogram[responseBin(slots[i].response)], 1);
  }
};

/// Loads that the single-item scans below read ahead of their sums: one after another, each load of a serial GPU
/// loop waited a whole memory round trip (CellOffsets' 920 cells took about 100 us at base clock, its stores to
/// arrays that the compiler cannot tell apart from the loaded ones keeping the loads in order).
constexpr int kScanBatch = 16;
static_assert(kResponseBins % kScanBatch == 0, "ResponseThreshold reads whole batches of bins");

/// One work item: the bin where the best `budget` slots end, and how many of that bin to take (threshold -1:
/// take every filled slot).
struct ResponseThreshold {
  const int* histogram;
  int* control;
  int budget;
  TM_HOST_DEVICE void operator()(int64_t) const {
    int above = 0, bin = -1;
    for (int top = kResponseBins - 1; top >= 0 && bin < 0; top -= kScanBatch) {
      int counts[kScanBatch];
      TM_UNROLL
      for (int k = 0; k < kScanBatch; ++k) counts[k] = histogram[top - k];
      TM_UNROLL
      for (int k = 0; k < kScanBatch; ++k) {
        if (bin >= 0) continue;
        if (above + counts[k] >= budget) bin = top - k;
        else above += counts[k];
      }
    }
    control[kThresholdBin] = bin;
    control[kTakeFromThreshold] = bin >= 0 ? budget - above : 0;
  }
};

/// Per cell: slots above the threshold bin, and slots in it.
struct CellCounts {
  const LevelKeypoint* slots;
  const int* control;
  int perCell;
  int* above;
  int* atThreshold;
  TM_HOST_DEVICE void operator()(int64_t cell) const {
    const int threshold = control[kThresholdBin];
    int a = 0, t = 0;
    for (int j = 0; j < perCell; ++j) {
      const int64_t r = slots[cell * perCell + j].response;
      if (r <= 0) continue;
      const int bin = responseBin(r);
      a += bin > threshold;
      t += bin == threshold;
    }
    above[cell] = a;
    atThreshold[cell] = t;
  }
};

/// One work item: each cell's output offset and its share of the threshold bin (in cell order).
struct CellOffsets {
  const int* above;
  int* atThreshold;  ///< in: slots in the threshold bin; out: how many of them this cell takes
  int* offsets;
  int* control;
  int cells;
  TM_HOST_DEVICE void operator()(int64_t) const {
    int offset = 0, remaining = control[kTakeFromThreshold];
    for (int first = 0; first < cells; first += kScanBatch) {
      int cellAbove[kScanBatch], cellAt[kScanBatch];
      TM_UNROLL
      for (int k = 0; k < kScanBatch; ++k) {
        cellAbove[k] = first + k < cells ? above[first + k] : 0;
        cellAt[k] = first + k < cells ? atThreshold[first + k] : 0;
      }
      TM_UNROLL
      for (int k = 0; k < kScanBatch; ++k) {
        if (first + k >= cells) continue;
        const int take = cellAt[k] < remaining ? cellAt[k] : remaining;
        remaining -= take;
        atThreshold[first + k] = take;
        offsets[first + k] = offset;
        offset += cellAbove[k] + take;
      }
    }
    control[kSelected] = offset;
  }
};

/// Per cell: copies its selected slots (in rank order) to the level's feature list.
struct CellWrite {
  const LevelKeypoint* slots;
  const int* control;
  const int* takeAtThreshold;
  const int* offsets;
  int perCell;
  LevelKeypoint* selected;
  TM_HOST_DEVICE void operator()(int64_t cell) const {
    const int threshold = control[kThresholdBin];
    int out = offsets[cell], takeLeft = takeAtThreshold[cell];
    for (int j = 0; j < perCell; ++j) {
      const LevelKeypoint& slot = slots[cell * perCell + j];
      if (slot.response <= 0) continue;
      const int bin = responseBin(slot.response);
      const bool take = bin > threshold || (bin == threshold && takeLeft > 0);
      if (bin == threshold && take) --takeLeft;
      if (take) selected[out++] = slot;
    }
  }
};

// ---- orientation and rotated BRIEF ----------------------------------------------------------------------------------

/// Half-width of the radius-15 disc at row offset dy: the largest u with u^2 + dy^2 <= 225.
TM_HOST_DEVICE TM_FORCE_INLINE int discHalfWidth(int dy) {
  int u = kPatchRadius;
  while (u * u + dy * dy > kPatchRadius * kPatchRadius) --u;
  return u;
}

/// Per selected feature: intensity-centroid moments over the radius-15 disc of the level image, then the 256
/// tests of the pattern rotated by the centroid direction on the smoothed level image.
struct Describe {
  ImageView<const uint8_t> image;
  ImageView<const uint8_t> smoothed;
  const int8_t* pattern;  ///< kPatternPairs x (x1, y1, x2, y2)
  const int* control;
  LevelKeypoint* features;
  uint8_t* descriptors;   ///< kDescriptorBytes per feature
  TM_HOST_DEVICE void operator()(int64_t i) const {
    if (i >= control[kSelected]) return;
    LevelKeypoint& f = features[i];
    int m10 = 0, m01 = 0;
    for (int dy = -kPatchRadius; dy <= kPatchRadius; ++dy) {
      const int u = discHalfWidth(dy);
      int rowSum = 0, rowMoment = 0;
      for (int dx = -u; dx <= u; ++dx) {
        const int v = image.at(f.x + dx, f.y + dy);
        rowSum += v;
        rowMoment += dx * v;
      }
      m10 += rowMoment;
      m01 += dy * rowSum;
    }
    f.m10 = m10;
    f.m01 = m01;
    // Unit direction of the centroid: the squares are exact in double, sqrt and divisions are IEEE.
    const double norm = sqrt(static_cast<double>(m10) * m10 + static_cast<double>(m01) * m01);
    const float c = norm > 0 ? static_cast<float>(m10 / norm) : 1.0f;
    const float s = norm > 0 ? static_cast<float>(m01 / norm) : 0.0f;
    uint8_t* out = descriptors + i * kDescriptorBytes;
    for (int b = 0; b < kDescriptorBytes; ++b) {
      int byte = 0;
      for (int j = 0; j < 8; ++j) {
        const int8_t* q = pattern + 4 * (8 * b + j);
        const float x1 = q[0], y1 = q[1], x2 = q[2], y2 = q[3];
        const int u1 = static_cast<int>(rintf(c * x1 - s * y1)), v1 = static_cast<int>(rintf(s * x1 + c * y1));
        const int u2 = static_cast<int>(rintf(c * x2 - s * y2)), v2 = static_cast<int>(rintf(s * x2 + c * y2));
        byte |= (smoothed.at(f.x + u1, f.y + v1) < smoothed.at(f.x + u2, f.y + v2)) << j;
      }
      out[b] = static_cast<uint8_t>(byte);
    }
  }
};

// ---- brute-force Hamming matching ---------------------------------------------------------------------------------

/// Matching several (A, B) pairs in one call: the rows of all A's, then of all B's, are stacked; pair s owns A rows
/// [aBegin[s], aBegin[s + 1]) and B rows [bBegin[s], bBegin[s + 1]). Reported B indices are within the pair's B.
struct MatchSegments {
  const int* aBegin;  ///< segmentCount + 1 entries
  const int* bBegin;  ///< segmentCount + 1 entries
  int segmentCount;

  /// The pair that owns stacked A row `row`.
  TM_HOST_DEVICE int segmentOf(int64_t row) const {
    int low = 0, high = segmentCount - 1;
    while (low < high) {
      const int middle = (low + high + 1) / 2;
      if (aBegin[middle] <= row) low = middle;
      else high = middle - 1;
    }
    return low;
  }
};

/// Hamming distance of two 256-bit descriptors (4 words each).
TM_HOST_DEVICE TM_FORCE_INLINE int hammingDistance(uint64_t a0, uint64_t a1, uint64_t a2, uint64_t a3, const uint64_t* q) {
  return popcount64(a0 ^ q[0]) + popcount64(a1 ^ q[1]) + popcount64(a2 ^ q[2]) + popcount64(a3 ^ q[3]);
}

/// The same for two 32-byte descriptor rows at any alignment (the host's guided matching: inline, four popcounts,
/// where cv::hal::normHamming is a call through a table).
TM_HOST_DEVICE TM_FORCE_INLINE int hammingDistance(const uint8_t* a, const uint8_t* b) {
  uint64_t x[4], y[4];
  memcpy(x, a, sizeof(x));
  memcpy(y, b, sizeof(y));
  return hammingDistance(x[0], x[1], x[2], x[3], y);
}

/// Per stacked row of A: the k nearest rows of its pair's B (distance asc, index asc); index -1 where that B has
/// fewer than k rows. The CPU runs this per row; CUDA runs a warp per row (OrbBackendCuda.cu) with the same result.
struct HammingKnn {
  const uint64_t* a;  ///< 4 words per row
  const uint64_t* b;
  MatchSegments segments;
  int k;
  int* indices;
  int* distances;
  TM_HOST_DEVICE void operator()(int64_t row) const {
    const int s = segments.segmentOf(row);
    const int bFirst = segments.bBegin[s], rowsB = segments.bBegin[s + 1] - bFirst;
    const uint64_t a0 = a[4 * row], a1 = a[4 * row + 1], a2 = a[4 * row + 2], a3 = a[4 * row + 3];
    int bestIndex[kMaxMatchK], bestDistance[kMaxMatchK];
    for (int j = 0; j < k; ++j) {
      bestIndex[j] = -1;
      bestDistance[j] = 1 << 30;
    }
    for (int r = 0; r < rowsB; ++r) {
      const int d = hammingDistance(a0, a1, a2, a3, b + 4 * static_cast<int64_t>(bFirst + r));
      if (d >= bestDistance[k - 1]) continue;  // rows come in index order: equal distances keep the lower index
      int j = k - 1;
      while (j > 0 && d < bestDistance[j - 1]) {
        bestDistance[j] = bestDistance[j - 1];
        bestIndex[j] = bestIndex[j - 1];
        --j;
      }
      bestDistance[j] = d;
      bestIndex[j] = r;
    }
    for (int j = 0; j < k; ++j) {
      indices[row * k + j] = bestIndex[j];
      distances[row * k + j] = bestDistance[j];
    }
  }
};

}  // namespace tissuemosaic::orb
