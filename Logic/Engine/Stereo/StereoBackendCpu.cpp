// The CPU instantiation of the section II pipeline, and the CPU launcher of the ZNCC cost volume.
#include "StereoPipeline.inl"

#include "Core/Error.h"
#include "Core/ParallelFor.h"

#include <algorithm>
#include <cmath>
#include <cassert>
#include <climits>
#include <string>
#include <vector>

namespace tissuemosaic::stereo {

namespace {

/// Image rows [firstRow, firstRow + rowCount) with replicated borders: rows clamped to the image, each padded on both
/// sides by `margin` replicated pixels, so the inner loops over x need no clamping.
struct PaddedRows {
  int firstRow, margin, stride;
  std::vector<float> values;

  PaddedRows(ImageView<const float> image, int firstRow_, int rowCount, int margin_)
      : firstRow(firstRow_), margin(margin_), stride(image.width + 2 * margin_),
        values(static_cast<std::size_t>(rowCount) * stride) {
    for (int k = 0; k < rowCount; ++k) {
      float* row = values.data() + static_cast<std::size_t>(k) * stride;
      const int sourceY = clampIndex(firstRow + k, image.height);
      for (int c = -margin; c < image.width + margin; ++c) row[c + margin] = image.at(clampIndex(c, image.width), sourceY);
    }
  }
  /// Pointer to column 0 of image row y (clamped rows included).
  const float* row(int y) const { return values.data() + static_cast<std::size_t>(y - firstRow) * stride + margin; }
};

/// Chessboard window sums of one row from column sums (even/odd indexed by column c in [xBegin - r, xEnd + r)):
/// S(x) = sum over dx of (dx even ? even : odd)[x + dx]. Grouped for fewer additions: with f the array of offset
/// -r's parity and g the other, G(j) = f(j) + g(j + 1) pairs neighbouring offsets, H(j) = G(j) + G(j + 2) pairs
/// those, and S(x) = f(x + r) + H(x - r) + H(x - r + 4) + ... (+ G for odd r). All values are integers below 2^24,
/// so the grouping changes nothing. This builds G and H and returns f; ChessboardScoreRow adds the terms up per pixel.
const float* chessboardPairsAndQuads(const float* even, const float* odd, int r, int xBegin, int xEnd, float* pairs,
                                     float* quads) {
  const float* __restrict f = (r & 1) ? odd : even;
  const float* __restrict g = (r & 1) ? even : odd;
  float* __restrict G = pairs;
  float* __restrict H = quads;
  const int cBegin = xBegin - r, cEnd = xEnd + r;
  for (int c = cBegin; c < cEnd - 1; ++c) G[c] = f[c] + g[c + 1];
  for (int c = cBegin; c < cEnd - 3; ++c) H[c] = G[c] + G[c + 2];
  return f;
}

/// The chessboard window sum at x from f, G and H (see chessboardPairsAndQuads); R is a template parameter so that
/// the terms unroll and the loops calling this vectorise.
template <int R>
TM_FORCE_INLINE float chessboardWindowSum(const float* __restrict f, const float* __restrict G,
                                          const float* __restrict H, int x) {
  float sum = f[x + R];
  for (int m = 0; m + 1 < R; m += 2) sum += H[x + m * 2 - R];
  if constexpr ((R & 1) != 0) sum += G[x + 2 * (R - 1) - R];
  return sum;
}

/// Row<R>::run(arguments...) for the runtime radius r (windows 3x3 to 19x19).
template <template <int> class Row, class... Arguments>
void runForChessboardRadius(int r, Arguments... arguments) {
  switch (r) {
    case 1: return Row<1>::run(arguments...);
    case 2: return Row<2>::run(arguments...);
    case 3: return Row<3>::run(arguments...);
    case 4: return Row<4>::run(arguments...);
    case 5: return Row<5>::run(arguments...);
    case 6: return Row<6>::run(arguments...);
    case 7: return Row<7>::run(arguments...);
    case 8: return Row<8>::run(arguments...);
    case 9: return Row<9>::run(arguments...);
    default: throw Error("ZNCC window radius " + std::to_string(r) + " is outside 1..9");
  }
}

/// One row of one disparity's slice, fused into one pass over x: the chessboard window sum from f, G and H (see
/// chessboardPairsAndQuads), the quantised ZNCC into the volume, and the running winners, strictly better (the
/// lowest disparity wins ties), of the left pixel x and of the right pixel x - d (whose arrays come shifted by d).
/// The radius is a template parameter so that the terms of the sum unroll and the loop vectorises.
template <int R>
struct ChessboardScoreRow {
  static void run(const float* __restrict f, const float* __restrict G, const float* __restrict H,
                  const float* __restrict sumL, const float* __restrict normL, const float* __restrict sumR,
                  const float* __restrict normR, int16_t* __restrict scores, int16_t* __restrict bestScore,
                  int16_t* __restrict bestD, int16_t* __restrict rightScore, int16_t* __restrict rightD,
                  int16_t disparity, int xBegin, int xEnd) {
    const int n = chessboardPixelCount(R);
    for (int x = xBegin; x < xEnd; ++x) {
      const float sum = chessboardWindowSum<R>(f, G, H, x);
      const int16_t q = quantisedZncc(sum, sumL[x], sumR[x], normL[x], normR[x], n);
      scores[x] = q;
      const bool leftBetter = q > bestScore[x], rightBetter = q > rightScore[x];
      bestD[x] = leftBetter ? disparity : bestD[x];
      bestScore[x] = leftBetter ? q : bestScore[x];
      rightD[x] = rightBetter ? disparity : rightD[x];
      rightScore[x] = rightBetter ? q : rightScore[x];
    }
  }
};

/// Rows per CPU task of the cost volume: the column sums of each disparity are carried down the band.
constexpr int kBandRows = 16;

/// One band of image rows of the cost volume, every disparity. Per disparity the chessboard column sums of L * R
/// (even and odd rows) start with a full sum at the band's first row and move down by the exact recurrences
/// Ce(y+1) = Co(y) -/+ one product, Co(y+1) = Ce(y) +/- one product (integer-valued floats: no rounding, as in the
/// CUDA kernel); then window sums, the quantised ZNCC (the shared per-pixel function) and the running winners.
struct ZnccVolumeBand {
  const ZnccVolumeInputs& in;

  void operator()(int64_t bandIndex) const {
    const int width = in.left.width, height = in.left.height, r = in.radius;
    const int y0 = static_cast<int>(bandIndex) * kBandRows;
    const int rows = std::min(kBandRows, height - y0);
    const int maxShift = std::max(std::abs(in.minDisparity), std::abs(in.minDisparity + in.disparityCount - 1));
    const PaddedRows left(in.left, y0 - r, rows + 2 * r, r);
    const PaddedRows right(in.right, y0 - r, rows + 2 * r, r + maxShift);
    std::vector<float> evenStore(width + 2 * r), oddStore(width + 2 * r);
    std::vector<float> pairs(width + 2 * r), quads(width + 2 * r);
    float* __restrict even = evenStore.data() + r;  // even[c] for c in [-r, width + r)
    float* __restrict odd = oddStore.data() + r;
    const std::size_t bandPixels = static_cast<std::size_t>(rows) * width;
    std::vector<int16_t> best(bandPixels, kNoZncc), bestDisparity(bandPixels, kNoDisparity);
    std::vector<int16_t> rightBest(bandPixels, kNoZncc), rightBestDisparity(bandPixels, kNoDisparity);

    for (int i = 0; i < in.disparityCount; ++i) {
      const int d = in.minDisparity + i;
      const int xBegin = std::max(0, d), xEnd = std::min(width, width + d);  // x - d inside the right image
      if (xBegin >= xEnd) {
        for (int k = 0; k < rows; ++k) {
          int16_t* scores = in.volume + in.volumeIndex(i, 0, y0 + k);
          std::fill(scores, scores + width, kNoZncc);
        }
        continue;
      }
      const int cBegin = xBegin - r, cEnd = xEnd + r;
      // Full column sums at the band's first row.
      std::fill(even + cBegin, even + cEnd, 0.0f);
      std::fill(odd + cBegin, odd + cEnd, 0.0f);
      for (int dy = -r; dy <= r; ++dy) {
        const float* __restrict l = left.row(y0 + dy);
        const float* __restrict rr = right.row(y0 + dy) - d;
        float* __restrict target = (dy & 1) == 0 ? even : odd;
        for (int c = cBegin; c < cEnd; ++c) target[c] += l[c] * rr[c];
      }
      for (int k = 0; k < rows; ++k) {
        const int y = y0 + k;
        if (k > 0) {
          // Move the column sums from row y - 1 to row y: row y - 1 - r leaves, row y + r enters.
          const float* __restrict leaveL = left.row(y - 1 - r);
          const float* __restrict leaveR = right.row(y - 1 - r) - d;
          const float* __restrict enterL = left.row(y + r);
          const float* __restrict enterR = right.row(y + r) - d;
          const bool oddRadius = (r & 1) != 0;
          for (int c = cBegin; c < cEnd; ++c) {
            const float leaving = leaveL[c] * leaveR[c], entering = enterL[c] * enterR[c];
            const float e = even[c], o = odd[c];
            even[c] = oddRadius ? o - leaving : o + entering;
            odd[c] = oddRadius ? e + entering : e - leaving;
          }
        }
        const float* f = chessboardPairsAndQuads(even, odd, r, xBegin, xEnd, pairs.data() + r, quads.data() + r);
        int16_t* scores = in.volume + in.volumeIndex(i, 0, y);  // row y's slice for d
        std::fill(scores, scores + xBegin, kNoZncc);
        std::fill(scores + xEnd, scores + width, kNoZncc);
        const std::size_t bandRow = static_cast<std::size_t>(k) * width;
        runForChessboardRadius<ChessboardScoreRow>(r, f, pairs.data() + r, quads.data() + r, &in.sumLeft.at(0, y), &in.inverseNormLeft.at(0, y),
                           &in.sumRight.at(0, y) - d, &in.inverseNormRight.at(0, y) - d,
                           scores, best.data() + bandRow, bestDisparity.data() + bandRow,
                           rightBest.data() + bandRow - d, rightBestDisparity.data() + bandRow - d,
                           static_cast<int16_t>(d), xBegin, xEnd);
      }
    }
    for (int k = 0; k < rows; ++k) {
      std::copy_n(bestDisparity.data() + static_cast<std::size_t>(k) * width, width, &in.bestDisparity.at(0, y0 + k));
      std::copy_n(rightBestDisparity.data() + static_cast<std::size_t>(k) * width, width,
                  &in.rightBestDisparity.at(0, y0 + k));
    }
  }
};

/// One row of window statistics from the pairs and quads (chessboardPairsAndQuads) of the column sums of I and I^2:
/// the window sums and the shared windowInverseNorm.
template <int R>
struct WindowStatisticsRow {
  static void run(const float* __restrict f, const float* __restrict G, const float* __restrict H,
                  const float* __restrict fSq, const float* __restrict GSq, const float* __restrict HSq, int width,
                  float minStdDev, float* __restrict outSum, float* __restrict outNorm) {
    const int n = chessboardPixelCount(R);
    for (int x = 0; x < width; ++x) {
      const float s = chessboardWindowSum<R>(f, G, H, x), s2 = chessboardWindowSum<R>(fSq, GSq, HSq, x);
      outSum[x] = s;
      outNorm[x] = windowInverseNorm(s, s2, n, minStdDev);
    }
  }
};

/// Window statistics of one band of rows: chessboard sums of I and I^2 per pixel (column sums carried down the band
/// as in ZnccVolumeBand, window sums from their pairs and quads), then the shared windowInverseNorm.
struct WindowStatisticsBand {
  ImageView<const float> image;
  ImageView<float> sum, inverseNorm;
  int radius;
  float minStdDev;

  void operator()(int64_t bandIndex) const {
    const int width = image.width, height = image.height, r = radius;
    const int y0 = static_cast<int>(bandIndex) * kBandRows;
    const int rows = std::min(kBandRows, height - y0);
    const PaddedRows padded(image, y0 - r, rows + 2 * r, r);
    const int columns = width + 2 * r;
    std::vector<float> store(8 * static_cast<std::size_t>(columns));
    float* __restrict even = store.data() + r;  // index c in [-r, width + r)
    float* __restrict odd = even + columns;
    float* __restrict evenSq = odd + columns;
    float* __restrict oddSq = evenSq + columns;
    float* pairs = oddSq + columns;
    float* quads = pairs + columns;
    float* pairsSq = quads + columns;
    float* quadsSq = pairsSq + columns;
    for (int dy = -r; dy <= r; ++dy) {
      const float* __restrict row = padded.row(y0 + dy);
      float* __restrict target = (dy & 1) == 0 ? even : odd;
      float* __restrict targetSq = (dy & 1) == 0 ? evenSq : oddSq;
      for (int c = -r; c < width + r; ++c) {
        target[c] += row[c];
        targetSq[c] += row[c] * row[c];
      }
    }
    const bool oddRadius = (r & 1) != 0;
    for (int k = 0; k < rows; ++k) {
      const int y = y0 + k;
      if (k > 0) {
        const float* __restrict leave = padded.row(y - 1 - r);
        const float* __restrict enter = padded.row(y + r);
        for (int c = -r; c < width + r; ++c) {
          const float e = even[c], o = odd[c], e2 = evenSq[c], o2 = oddSq[c];
          even[c] = oddRadius ? o - leave[c] : o + enter[c];
          odd[c] = oddRadius ? e + enter[c] : e - leave[c];
          evenSq[c] = oddRadius ? o2 - leave[c] * leave[c] : o2 + enter[c] * enter[c];
          oddSq[c] = oddRadius ? e2 + enter[c] * enter[c] : e2 - leave[c] * leave[c];
        }
      }
      const float* f = chessboardPairsAndQuads(even, odd, r, 0, width, pairs, quads);
      const float* fSq = chessboardPairsAndQuads(evenSq, oddSq, r, 0, width, pairsSq, quadsSq);
      runForChessboardRadius<WindowStatisticsRow>(r, f, pairs, quads, fSq, pairsSq, quadsSq, width, minStdDev,
                                                  &sum.at(0, y), &inverseNorm.at(0, y));
    }
  }
};

/// Band `band` of `bands` of a sweep over the image's rows along a direction with row step dy: sweep step s is row
/// height - 1 - s when dy > 0 (the neighbour's row comes first), else row s. The band's own steps are [begin, end);
/// a sweep that crosses rows (dy != 0) starts `overlap` steps early, knowing nothing before that, so that answers
/// which look at most `overlap` steps back come out exactly as from one sweep over the whole image.
struct SweepBand {
  int begin, end, first, height, dy;
  SweepBand(int height_, int band, int bands, int overlap, int dy_)
      : begin(static_cast<int>(static_cast<int64_t>(height_) * band / bands)),
        end(static_cast<int>(static_cast<int64_t>(height_) * (band + 1) / bands)),
        first(dy_ == 0 ? begin : std::max(0, begin - overlap)), height(height_), dy(dy_) {}
  int row(int step) const { return dy > 0 ? height - 1 - step : step; }
};

/// Nearest estimate along ray direction k for every pixel, within radius steps and inside the image: the hit at p
/// is p + delta itself when that carries an estimate, else the hit at p + delta one step further. One sweep in the
/// order that visits p + delta before p gives every ray walk's answer at O(1) per pixel.
/// A task is one direction and one band of rows, so that more than 8 threads have work. A band of a direction that
/// steps across rows starts its sweep `radius` rows early (knowing nothing before that): a hit is never farther than
/// radius, so the band's own rows come out exactly as from one sweep over the image. The band's rows are swept
/// straight into the maps; the rows before them go to scratch rows and never into the maps.
struct NearestAlongRay {
  ImageView<const int16_t> input;
  int radius;
  int rowBands;
  int16_t* hitDistance;  ///< [8][pixels]; 0 = none
  int16_t* hitValue;

  void operator()(int64_t task) const {
    const int k = static_cast<int>(task % 8), band = static_cast<int>(task / 8);
    int dx, dy;
    radialDirection(k, dx, dy);
    const int width = input.width, height = input.height;
    const int64_t offset = static_cast<int64_t>(k) * input.pixelCount();
    int16_t* __restrict distance = hitDistance + offset;
    int16_t* __restrict value = hitValue + offset;
    const SweepBand sweep(height, band, rowBands, radius, dy);
    // The band's own rows are swept straight into the maps; the rows before them (the overlap) into two scratch
    // rows taken in turn, and a row of "nothing known" stands before the first step.
    std::vector<int16_t> scratch(6 * static_cast<std::size_t>(width), int16_t{0});
    const auto scratchRow = [&](int slot) { return scratch.data() + static_cast<std::size_t>(slot) * width; };
    const int16_t* previousDistance = scratchRow(4);  // the row swept before (the neighbours' row when dy != 0)
    const int16_t* previousValue = scratchRow(5);
    std::vector<int16_t> reversedStore(dy == 0 ? 3 * static_cast<std::size_t>(width) : 0);
    for (int step = sweep.first; step < sweep.end; ++step) {
      const int y = sweep.row(step);
      const int16_t* row = &input.at(0, y);
      const int64_t rowStart = static_cast<int64_t>(y) * width;
      const bool kept = step >= sweep.begin;
      int16_t* rowDistance = kept ? distance + rowStart : scratchRow(2 * (step & 1));
      int16_t* rowValue = kept ? value + rowStart : scratchRow(2 * (step & 1) + 1);
      if (dy == 0) {
        nearestAlongRow(row, rowDistance, rowValue, width, dx, radius, reversedStore.data());
      } else if (step == 0) {  // the neighbours' row is outside the image
        std::fill(rowDistance, rowDistance + width, int16_t{0});
      } else {
        nearestRowAcross(&input.at(0, y + dy), previousDistance, previousValue, rowDistance, rowValue, width, dx,
                         radius);
      }
      previousDistance = rowDistance;
      previousValue = rowValue;
    }
  }

  /// The hits of one row along the row (direction dx): a scan from the far end whose only carried values are the
  /// nearest estimate's position and value, each one select (no recurrence through the distance). A ray towards -x
  /// runs on the reversed row. reversed: 3 x width scratch.
  static void nearestAlongRow(const int16_t* row, int16_t* rowDistance, int16_t* rowValue, int width, int dx,
                              int radius, int16_t* reversed) {
    const int16_t* in = row;
    int16_t* distance = rowDistance;
    int16_t* value = rowValue;
    if (dx < 0) {
      std::reverse_copy(row, row + width, reversed);
      in = reversed;
      distance = reversed + width;
      value = distance + width;
    }
    nearestTowardsPlusX(in, distance, value, width, radius);
    if (dx < 0) {
      std::reverse_copy(distance, distance + width, rowDistance);
      std::reverse_copy(value, value + width, rowValue);
    }
  }
  static void nearestTowardsPlusX(const int16_t* __restrict in, int16_t* __restrict distance,
                                  int16_t* __restrict value, int width, int radius) {
    int next = width + radius + 1, nextValue = 0;  // the nearest estimate right of x (none: beyond any radius)
    for (int x = width - 1; x >= 0; --x) {
      const int steps = next - x;
      const int hit = -static_cast<int>(steps <= radius);  // bit masks: GCC makes selects here into branches
      distance[x] = static_cast<int16_t>(steps & hit);
      value[x] = static_cast<int16_t>(nextValue & hit);
      const int valid = -static_cast<int>(in[x] != kNoDisparity);
      next = (x & valid) | (next & ~valid);
      nextValue = (in[x] & valid) | (nextValue & ~valid);
    }
  }

  /// One row of a sweep across rows: each pixel's hit from its neighbour in the row swept before (neighbourRow, at
  /// column x + dx) and that neighbour's own hit. No pixel depends on another of its row, so this vectorises.
  static void nearestRowAcross(const int16_t* __restrict neighbourRow, const int16_t* __restrict previousDistance,
                               const int16_t* __restrict previousValue, int16_t* __restrict rowDistance,
                               int16_t* __restrict rowValue, int width, int dx, int radius) {
    const int xBegin = dx < 0 ? 1 : 0, xEnd = dx > 0 ? width - 1 : width;  // the neighbour inside the image
    if (dx < 0) rowDistance[0] = rowValue[0] = 0;  // no neighbour: no hit
    if (dx > 0) rowDistance[width - 1] = rowValue[width - 1] = 0;
    for (int x = xBegin; x < xEnd; ++x) {
      // Bit masks instead of selects: GCC sees no control flow, so it vectorises.
      const int neighbour = neighbourRow[x + dx], carried = previousDistance[x + dx], carriedValue = previousValue[x + dx];
      const int hit = -static_cast<int>(neighbour != kNoDisparity);
      const int carries = -static_cast<int>((carried > 0) & (carried < radius)) & ~hit;
      rowDistance[x] = static_cast<int16_t>((1 & hit) | ((carried + 1) & carries));
      rowValue[x] = static_cast<int16_t>((neighbour & hit) | (carriedValue & carries));
    }
  }
};

/// II.B's smoothness test between neighbouring estimates along a ray: they differ by more than maxStep.
inline bool breaksBetween(int a, int b, int maxStep) { return std::abs(a - b) > maxStep; }

/// The break distance of an estimate v whose next estimate along the ray is `ahead` steps on (cap: none within the
/// radius), with value valueAhead and break distance breakAhead: SmoothRaySweep's recurrence.
inline int breakDistance(int v, int ahead, int valueAhead, int breakAhead, int cap, int maxStep) {
  return ahead >= cap ? cap : (breaksBetween(valueAhead, v, maxStep) ? ahead : std::min(cap, ahead + breakAhead));
}

/// II.B's test of one ray, as RemoveOutliers walks it: an estimate, steps inside the image, no break within them,
/// and estimates on at least half of them.
inline uint8_t rayPasses(int valid, int inImage, int breakSteps, int estimates) {
  return static_cast<uint8_t>(valid & (inImage > 0) & (breakSteps > inImage) & (2 * estimates >= inImage));
}

/// II.B's outlier test along ray direction k for every pixel, from one sweep in the order that visits p + delta
/// before p (the same answers as RemoveOutliers' ray walks, at O(1) per pixel). Per pixel the sweep carries the
/// nearest estimate at or beyond it (steps, value) and that estimate's break distance: the steps to the first
/// estimate beyond it that differs by more than maxStep from the estimate before it. For an estimate p with next
/// estimate n at a steps, break(p) = a when they differ by more, else a + break(n). Steps are capped at radius + 1
/// (none within the radius), and a running count of estimates gives the estimates over any stretch of the ray.
/// The ray from p passes when break(p) exceeds its in-image steps and the estimates over them are at least half.
/// Tasks as in NearestAlongRay: one direction and one band of rows; bands start radius + 1 rows early.
struct SmoothRaySweep {
  ImageView<const int16_t> input;
  int radius;
  float maxStepPx;
  int rowBands;
  uint8_t* passes;  ///< [8][pixels]: 1 where the ray of direction k passes

  void operator()(int64_t task) const {
    const int k = static_cast<int>(task % 8), band = static_cast<int>(task / 8);
    int dx, dy;
    radialDirection(k, dx, dy);
    const int width = input.width, height = input.height, cap = radius + 1;
    // Steps are integers: "differs by more than maxStepPx" is "more than its floor".
    const int maxStep = static_cast<int>(std::floor(std::min(maxStepPx, 1e6f)));
    uint8_t* pass = passes + static_cast<int64_t>(k) * input.pixelCount();
    const SweepBand sweep(height, band, rowBands, cap, dy);
    if (dy == 0) {
      sweepRows(sweep, dx, cap, maxStep, pass);
      return;
    }
    // Row state of the step before (the neighbours' row) and of this step, with one column of "none" on each side.
    const int padded = width + 2;
    std::vector<int> state(6 * static_cast<std::size_t>(padded));
    int* previousNear = state.data() + 1;
    int* previousValue = previousNear + padded;
    int* previousBreak = previousValue + padded;
    int* near = previousBreak + padded;
    int* value = near + padded;
    int* breakSteps = value + padded;
    std::fill(state.begin(), state.end(), cap);
    // Running counts of the last cap + 1 steps (the far end of a ray is cap steps back), padded by cap columns of 0.
    const int countColumns = width + 2 * cap;
    std::vector<int> counts(static_cast<std::size_t>(cap + 2) * countColumns, 0);
    const int* noCounts = counts.data() + static_cast<std::size_t>(cap + 1) * countColumns + cap;  // stays 0
    const auto countRow = [&](int step) { return counts.data() + static_cast<std::size_t>(step % (cap + 1)) * countColumns + cap; };
    std::vector<uint8_t> overlapPasses(width);  // answers of the rows before the band: not kept
    for (int step = sweep.first; step < sweep.end; ++step) {
      const int y = sweep.row(step);
      const int16_t* row = &input.at(0, y);
      int* count = countRow(step);
      const int* previousCount = step > sweep.first ? countRow(step - 1) : noCounts;
      const int* farCount = step - cap >= sweep.first ? countRow(step - cap) + cap * dx : noCounts;
      sweepRowAcross(row, previousNear + dx, previousValue + dx, previousBreak + dx, previousCount + dx, farCount, near,
                     value, breakSteps, count, step >= sweep.begin ? pass + static_cast<int64_t>(y) * width : overlapPasses.data(),
                     width, dx, cap, maxStep, std::min(radius, step));
      std::swap(previousNear, near);
      std::swap(previousValue, value);
      std::swap(previousBreak, breakSteps);
    }
  }

  /// One row of a sweep across rows: the row state from the neighbours' (the "Ahead" arrays, already shifted by dx)
  /// and each pixel's answer. rowLimit: steps to the image's top or bottom. A function of its own so that the
  /// compiler knows the arrays apart (restrict parameters) and vectorises it.
  static void sweepRowAcross(const int16_t* __restrict row, const int* __restrict nearAhead,
                             const int* __restrict valueAhead, const int* __restrict breakAhead,
                             const int* __restrict countAhead, const int* __restrict farCount, int* __restrict near,
                             int* __restrict value, int* __restrict breakSteps, int* __restrict count,
                             uint8_t* __restrict pass, int width, int dx, int cap, int maxStep, int rowLimit) {
    for (int x = 0; x < width; ++x) {
      const int v = row[x];
      const int valid = v != kNoDisparity;
      const int ahead = std::min(cap, nearAhead[x] + 1);
      const int breakHere = breakDistance(v, ahead, valueAhead[x], breakAhead[x], cap, maxStep);
      near[x] = valid ? 0 : ahead;
      value[x] = valid ? v : valueAhead[x];
      breakSteps[x] = valid ? breakHere : breakAhead[x];
      count[x] = countAhead[x] + valid;
      const int columnLimit = dx > 0 ? width - 1 - x : (dx < 0 ? x : cap);
      const int inImage = std::min(rowLimit, columnLimit);
      const int estimates = countAhead[x] - farCount[x];
      pass[x] = rayPasses(valid, inImage, breakHere, estimates);
    }
  }

  /// The same for a direction along the rows, a row at a time (a ray towards -x runs on the reversed row). The
  /// break distance's recurrence unrolls to break(x) = min(cap, J(x) - x), where J(x) is the first estimate beyond
  /// x that differs by more than maxStep from the estimate before it; so two scans, each carrying only a select,
  /// and a vectorised pass for the answers replace the per-pixel recurrence (latency-bound along a row).
  void sweepRows(const SweepBand& sweep, int dx, int cap, int maxStep, uint8_t* pass) const {
    const int width = input.width;
    AlongRowScratch scratch(width, cap);
    for (int y = sweep.begin; y < sweep.end; ++y) {
      const int16_t* row = &input.at(0, y);
      uint8_t* out = pass + static_cast<int64_t>(y) * width;
      if (dx > 0) {
        passesTowardsPlusX(row, out, width, radius, cap, maxStep, scratch);
      } else {
        std::reverse_copy(row, row + width, scratch.reversedRow.data());
        passesTowardsPlusX(scratch.reversedRow.data(), scratch.reversedPass.data(), width, radius, cap, maxStep, scratch);
        std::reverse_copy(scratch.reversedPass.begin(), scratch.reversedPass.end(), out);
      }
    }
  }

  struct AlongRowScratch {
    std::vector<int16_t> reversedRow;
    std::vector<uint8_t> reversedPass, jump;
    std::vector<int> estimatesBefore;  ///< [j]: estimates in [0, j), j up to width + cap (constant past the row)
    std::vector<int> breakSteps;
    AlongRowScratch(int width, int cap)
        : reversedRow(width), reversedPass(width), jump(width), estimatesBefore(width + cap + 1), breakSteps(width) {}
  };

  static void passesTowardsPlusX(const int16_t* __restrict row, uint8_t* __restrict pass, int width, int radius,
                                 int cap, int maxStep, AlongRowScratch& scratch) {
    uint8_t* __restrict jump = scratch.jump.data();
    int* __restrict before = scratch.estimatesBefore.data();
    int* __restrict breakSteps = scratch.breakSteps.data();
    // Left to right: which estimates jump from the estimate before them, and the running count.
    int previous = 0, seen = 0, count = 0;  // bit masks below: GCC makes selects here into branches
    before[0] = 0;
    for (int x = 0; x < width; ++x) {
      const int v = row[x];
      const int valid = -static_cast<int>(v != kNoDisparity);
      jump[x] = static_cast<uint8_t>(valid & seen & -static_cast<int>(breaksBetween(v, previous, maxStep)) & 1);
      previous = (v & valid) | (previous & ~valid);
      seen |= valid;
      count += valid & 1;
      before[x + 1] = count;
    }
    std::fill(before + width + 1, before + width + cap + 1, count);
    // Right to left: the first jump beyond each pixel.
    int nextJump = width + cap;  // none: beyond any cap
    for (int x = width - 1; x >= 0; --x) {
      breakSteps[x] = std::min(cap, nextJump - x);
      const int jumps = -static_cast<int>(jump[x]);
      nextJump = (x & jumps) | (nextJump & ~jumps);
    }
    // The answers, independent per pixel: steps to the row's end, and the estimates over steps 1..radius.
    for (int x = 0; x < width; ++x) {
      const int valid = row[x] != kNoDisparity;
      const int inImage = std::min(radius, width - 1 - x);
      const int estimates = before[x + radius + 1] - before[x + 1];
      pass[x] = rayPasses(valid, inImage, breakSteps[x], estimates);
    }
  }
};

/// Keeps the estimates with at least one passing ray.
struct KeepWithPassingRay {
  ImageView<const int16_t> input;
  ImageView<int16_t> output;
  const uint8_t* passes;

  void operator()(int64_t row) const {
    const int64_t pixels = input.pixelCount(), first = row * input.width;
    keepRow(&input[first], &output[first], passes + first, pixels, input.width);
  }
  static void keepRow(const int16_t* __restrict in, int16_t* __restrict out, const uint8_t* __restrict p,
                      int64_t pixels, int width) {
    for (int x = 0; x < width; ++x) {
      const uint8_t any = p[x] | p[pixels + x] | p[2 * pixels + x] | p[3 * pixels + x] | p[4 * pixels + x] |
                          p[5 * pixels + x] | p[6 * pixels + x] | p[7 * pixels + x];
      out[x] = any ? in[x] : kNoDisparity;
    }
  }
};

/// Bands of rows per direction for the per-direction sweeps: `requested`, or from the thread count when 0. 8
/// directions give 8 tasks; with more threads than that each direction is cut into bands (each band sweeps radius
/// rows more, so only where threads would otherwise idle).
int directionRowBands(int requested, int height) {
  const int bands = requested > 0 ? requested : std::max(1, (cpuThreadCount() + 7) / 8);
  return std::min(bands, std::max(1, height));
}

}  // namespace

void removeOutliersCpu(ImageView<const int16_t> input, ImageView<int16_t> output, int radius, float maxStepPx,
                       uint8_t* rayPasses, int rowBands) {
  rowBands = directionRowBands(rowBands, input.height);
  parallelFor<CpuBackend>(8 * static_cast<int64_t>(rowBands), SmoothRaySweep{input, radius, maxStepPx, rowBands, rayPasses}, 1);
  parallelFor<CpuBackend>(input.height, KeepWithPassingRay{input, output, rayPasses}, 8);
}

void ReselectDiscreteRows::consumeRow(int64_t firstIndex, const int64_t* boxSums, const int* boxCounts,
                                      int columns) const {
  constexpr int kMaxColumns = kCpuBoxColumnBlock;
  constexpr int kGroup = 16;       // pixels that share one loop over candidates: few, so that their ranges overlap
  constexpr int kNotActive = INT32_MIN / 2;  // a centre no candidate is within search of (and no overflow)
  const ReselectDiscrete& r = rule;
  assert(columns <= kMaxColumns);
  int x0, y;
  pixelCoordinates(firstIndex, r.current.width, x0, y);
  float d[kMaxColumns];
  int centre[kMaxColumns];
  float* __restrict current = &r.current[firstIndex];
  const int16_t* __restrict discrete = &r.discrete[firstIndex];
  int segmentLo = r.disparityCount, segmentHi = -1;
  // Branch-free: the corrected d of every pixel, kept only where the pixel takes part. GCC 12 does not vectorise
  // this loop ("unsupported use in stmt"), though it has no branches left to mispredict.
  for (int c = 0; c < columns; ++c) {
    const bool takesPart = ReselectDiscrete::takesPart(discrete[c], boxCounts[c]);
    const float corrected = correctedDisparity(current[c], boxSums[c], takesPart ? boxCounts[c] : 1);
    const bool active = takesPart & isFinite(corrected);
    current[c] = takesPart ? corrected : current[c];
    d[c] = takesPart ? corrected : 0.0f;
    const float centred = active ? corrected : 0.0f;  // both select arms are evaluated: no NaN to int
    centre[c] = active ? r.centreIndex(centred) : kNotActive;
    segmentLo = std::min(segmentLo, active ? centre[c] - r.search : r.disparityCount);
    segmentHi = std::max(segmentHi, active ? centre[c] + r.search : -1);
  }
  // The next row of this column block comes next (BoxColumnSums runs down the rows), with much the same candidates:
  // ask for its volume lines now, so that their misses overlap this row's work (the volume is read in short
  // pieces a row of disparities apart, which the hardware prefetchers do not follow).
  if (y + 1 < r.current.height) {
    for (int i = std::max(segmentLo, 0); i <= std::min(segmentHi, r.disparityCount - 1); ++i) {
      const int16_t* next = r.volume + r.layout.index(x0, y + 1, i);
      for (int c = 0; c < columns; c += 32) __builtin_prefetch(next + c);
    }
  }
  for (int g0 = 0; g0 < columns; g0 += kGroup) {
    const int n = std::min(kGroup, columns - g0);
    const float* __restrict groupD = d + g0;
    const int* __restrict groupCentre = centre + g0;
    int lo = r.disparityCount, hi = -1;
    for (int c = 0; c < n; ++c) {
      if (groupCentre[c] == kNotActive) continue;
      lo = std::min(lo, groupCentre[c] - r.search);
      hi = std::max(hi, groupCentre[c] + r.search);
    }
    lo = std::max(lo, 0);
    hi = std::min(hi, r.disparityCount - 1);
    float bestCost[kGroup];
    int best[kGroup];
    std::fill(bestCost, bestCost + kGroup, INFINITY);
    std::fill(best, best + kGroup, -1);
    // Candidates in increasing order with a strict comparison: the lowest disparity wins ties, as in the rule.
    for (int i = lo; i <= hi; ++i) {
      const int16_t* __restrict q = r.volume + r.layout.index(x0 + g0, y, i);
      for (int c = 0; c < n; ++c) {
        const int offset = i - groupCentre[c];
        const float cost = reselectionCost(q[c], i + r.minDisparity, groupD[c], r.eta);
        const bool better = (offset >= -r.search) & (offset <= r.search) & (q[c] > 0) & (cost < bestCost[c]);
        bestCost[c] = better ? cost : bestCost[c];
        best[c] = better ? i : best[c];
      }
    }
    for (int c = 0; c < n; ++c) {
      const int64_t index = firstIndex + g0 + c;
      if (best[c] >= 0 && !r.keepsFilledValue(x0 + g0 + c, y, r.discrete[index])) {
        r.discrete[index] = static_cast<int16_t>(best[c] + r.minDisparity);
      }
    }
  }
}

void fillHolesRadialCpu(ImageView<const int16_t> input, ImageView<int16_t> output, int radius, int minLines,
                        float maxEndDifferencePx, int16_t* hitDistance, int16_t* hitValue, int rowBands) {
  rowBands = directionRowBands(rowBands, input.height);
  parallelFor<CpuBackend>(8 * static_cast<int64_t>(rowBands),
                          NearestAlongRay{input, radius, rowBands, hitDistance, hitValue}, 1);
  parallelFor<CpuBackend>(input.pixelCount(),
                          FillHolesRadialFromHits{input, output, hitDistance, hitValue, minLines, maxEndDifferencePx});
}

void computeWindowStatisticsCpu(ImageView<const float> image, ImageView<float> sum, ImageView<float> inverseNorm,
                                int radius, float minStdDev) {
  parallelFor<CpuBackend>((image.height + kBandRows - 1) / kBandRows,
                          WindowStatisticsBand{image, sum, inverseNorm, radius, minStdDev}, 1);
}

void computeZnccVolumeCpu(const ZnccVolumeInputs& inputs) {
  parallelFor<CpuBackend>((inputs.left.height + kBandRows - 1) / kBandRows, ZnccVolumeBand{inputs}, 1);
}

void detectHighlightSeedsCpu(const DetectHighlightSeeds& seeds) {
  parallelFor<CpuBackend>(seeds.left.pixelCount(), seeds);
}

void runStereoPipelineCpu(StereoWorkspace& workspace, const StereoParameters& parameters, StereoTimingsMs& timings,
                          StereoExplanation* explanation) {
  runStereoPipeline<CpuBackend>(workspace, parameters, timings,
                                {computeZnccVolumeCpu, computeScanlinePathsCpu, detectHighlightSeedsCpu}, explanation);
}

}  // namespace tissuemosaic::stereo
