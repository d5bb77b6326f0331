#pragma once
/// @file StereoKernels.h
/// @brief The per-pixel steps of section II, written once for both backends (TM_HOST_DEVICE).
///
/// Exactness: grey levels are integers 0..255 stored as float, so every window sum of pixels or of pixel
/// products is an integer below 2^24 and is exact in float whatever the summation order. ZNCC scores are then
/// derived from exact sums with the same IEEE operations on both backends (CUDA is built with -fmad=false), and
/// the discrete steps (outliers, holes) work on integers: the CPU and CUDA paths agree bit for bit up to the
/// refinement's floating-point averages, which also run in the same order on both.
#include "Core/Float3.h"
#include "Core/HostDevice.h"
#include "Core/Image.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

namespace tissuemosaic::stereo {

/// Discrete disparity maps hold int16; this marks "no estimate".
constexpr int16_t kNoDisparity = INT16_MIN;
/// The cost volume holds ZNCC * kZnccScale rounded; this marks "not computable" (outside the image, textureless).
constexpr int16_t kNoZncc = INT16_MIN;
constexpr float kZnccScale = 32000.0f;
constexpr int kZnccMax = 32000;  ///< ZNCC = 1

/// (x, y) of a pixel index with 32-bit arithmetic: images have fewer than 2^31 pixels, and a 64-bit division costs
/// several times more on the CPU and is a long software routine on the GPU.
TM_HOST_DEVICE TM_FORCE_INLINE void pixelCoordinates(int64_t index, int width, int& x, int& y) {
  const int i = static_cast<int>(index);
  y = i / width;
  x = i - y * width;
}

TM_HOST_DEVICE TM_FORCE_INLINE int clampIndex(int i, int size) { return i < 0 ? 0 : (i >= size ? size - 1 : i); }

/// Pixels in the chessboard window of radius r (side 2r+1) that contains its centre: offsets (dx, dy) with
/// dx + dy even. For r = 5 (the paper's 11x11) this is 61.
TM_HOST_DEVICE TM_FORCE_INLINE int chessboardPixelCount(int r) {
  const int even = 2 * (r / 2) + 1;  // even offsets in [-r, r]
  const int odd = 2 * r + 1 - even;
  return even * even + odd * odd;
}

/// Column sums of one image column for the chessboard window: `even` over rows y+dy with dy even, `odd` over dy
/// odd, |dy| <= r. sample(dy) returns the value at row offset dy (the caller clamps rows).
template <class Sample>
TM_HOST_DEVICE TM_FORCE_INLINE void chessboardColumnSums(const Sample& sample, int r, float& even, float& odd) {
  even = 0.0f;
  odd = 0.0f;
  TM_UNROLL
  for (int dy = -r; dy <= r; ++dy) {
    const float v = sample(dy);
    if ((dy & 1) == 0) even += v;
    else odd += v;
  }
}

/// Window sum at column x from column sums: columns x+dx with dx even contribute their `even` sum, dx odd their
/// `odd` sum. column(dx, even) returns that sum of column x+dx (only the one needed is read: on the GPU the column
/// sums live in shared memory, whose reads bound the cost volume's speed).
template <class Column>
TM_HOST_DEVICE TM_FORCE_INLINE float chessboardWindowSum(const Column& column, int r) {
  float sum = 0.0f;
  TM_UNROLL
  for (int dx = -r; dx <= r; ++dx) sum += column(dx, (dx & 1) == 0);
  return sum;
}

/// 1 / sqrt(n * sum(I^2) - sum(I)^2) of a window, or 0 when the window's grey-level standard deviation is below
/// minStdDev (textureless: ZNCC undefined). Double keeps n * sumSq exact.
TM_HOST_DEVICE TM_FORCE_INLINE float windowInverseNorm(float sum, float sumSq, int n, float minStdDev) {
  const double spread = static_cast<double>(n) * static_cast<double>(sumSq) - static_cast<double>(sum) * sum;
  const double minSpread = static_cast<double>(minStdDev) * minStdDev * n * n;
  if (!(spread > minSpread) || spread <= 0.0) return 0.0f;
  return static_cast<float>(1.0 / sqrt(spread));
}

/// ZNCC from exact window sums: (n * sumLR - sumL * sumR) * invNormL * invNormR, quantised to int16. Every term
/// of the numerator is an integer below 2^31 for windows up to 19x19 (n <= 181), so int32 arithmetic is exact and
/// vectorises on the CPU. Written without branches for the same reason.
TM_HOST_DEVICE TM_FORCE_INLINE int16_t quantisedZncc(float sumLR, float sumL, float sumR, float invNormL,
                                                     float invNormR, int n) {
  const int numerator = n * static_cast<int>(sumLR) - static_cast<int>(sumL) * static_cast<int>(sumR);
  // Rounded first, then clamped to [-1, 1] in integers: the same as clamping first, and branch-free.
  int q = static_cast<int>(nearbyintf(static_cast<float>(numerator) * invNormL * invNormR * kZnccScale));
  q = q < kZnccMax ? q : kZnccMax;
  q = q > -kZnccMax ? q : -kZnccMax;
  const bool textureless = (invNormL == 0.0f) | (invNormR == 0.0f);
  return static_cast<int16_t>(textureless ? kNoZncc : q);
}

/// Both 8-bit grey images widened to the float images the pipeline works on (exact: integers 0..255).
struct GreyToFloat {
  ImageView<const uint8_t> leftGrey, rightGrey;
  ImageView<float> left, right;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    left[index] = static_cast<float>(leftGrey[index]);
    right[index] = static_cast<float>(rightGrey[index]);
  }
};

/// Window statistics, pass 1: chessboard column sums of I and I^2 at every pixel.
struct WindowColumnSums {
  ImageView<const float> image;
  ImageView<float> evenSum, oddSum, evenSumSq, oddSumSq;
  int radius;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, image.width, x, y);
    float e, o, e2, o2;
    chessboardColumnSums([&](int dy) { return image.at(x, clampIndex(y + dy, image.height)); }, radius, e, o);
    chessboardColumnSums(
        [&](int dy) {
          const float v = image.at(x, clampIndex(y + dy, image.height));
          return v * v;
        },
        radius, e2, o2);
    evenSum[index] = e;
    oddSum[index] = o;
    evenSumSq[index] = e2;
    oddSumSq[index] = o2;
  }
};

/// Window statistics, pass 2: window sum of I and the inverse norm at every pixel (replicated border).
struct WindowStatistics {
  ImageView<const float> evenSum, oddSum, evenSumSq, oddSumSq;
  ImageView<float> sum, inverseNorm;
  int radius;
  float minStdDev;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int width = sum.width;
    int x, y;
    pixelCoordinates(index, width, x, y);
    const float s = chessboardWindowSum(
        [&](int dx, bool even) { return (even ? evenSum : oddSum).at(clampIndex(x + dx, width), y); }, radius);
    const float s2 = chessboardWindowSum(
        [&](int dx, bool even) { return (even ? evenSumSq : oddSumSq).at(clampIndex(x + dx, width), y); }, radius);
    sum[index] = s;
    inverseNorm[index] = windowInverseNorm(s, s2, chessboardPixelCount(radius), minStdDev);
  }
};

/// Where the ZNCC of pixel (x, y) at disparity index i lives: y * rowStride + x + i * disparityStride. The CPU keeps
/// each image row's disparity slices together (its row loop writes them contiguously and the re-selection finds a
/// pixel's candidates in cache); the GPU keeps whole-image slices (coalesced across threads).
struct VolumeLayout {
  int64_t rowStride;
  int64_t disparityStride;
  static VolumeLayout rowMajor(int width, int disparityCount) {
    return {static_cast<int64_t>(width) * disparityCount, width};
  }
  static VolumeLayout sliceMajor(int width, int height) {
    return {width, static_cast<int64_t>(width) * height};
  }
  TM_HOST_DEVICE int64_t index(int x, int y, int disparityIndex) const {
    return y * rowStride + x + disparityIndex * disparityStride;
  }
};

/// Inputs of the cost-volume pass, shared by the CPU and CUDA launchers.
struct ZnccVolumeInputs {
  ImageView<const float> left, right;
  ImageView<const float> sumLeft, inverseNormLeft, sumRight, inverseNormRight;
  int radius;
  int minDisparity;
  int disparityCount;
  int16_t* volume;
  VolumeLayout layout;
  ImageView<int16_t> bestDisparity;       ///< left-view winner
  ImageView<int16_t> rightBestDisparity;  ///< right-view winner (both launchers fill it in the same pass)
  uint32_t* rightWinnerKeys;              ///< GPU scratch, one per pixel: packRightWinner of the best so far

  TM_HOST_DEVICE int64_t volumeIndex(int disparityIndex, int x, int y) const { return layout.index(x, y, disparityIndex); }
};

/// The 8 radial directions (E, SE, S, SW, W, NW, N, NE): direction k and k + 4 are opposite.
TM_HOST_DEVICE TM_FORCE_INLINE void radialDirection(int k, int& dx, int& dy) {
  const int table[8][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
  dx = table[k][0];
  dy = table[k][1];
}

/// Steps s >= 1 for which (x + s dx, y + s dy) stays inside a width x height image, capped at maxSteps.
TM_HOST_DEVICE TM_FORCE_INLINE int stepsInside(int x, int y, int dx, int dy, int width, int height, int maxSteps) {
  int steps = maxSteps;
  if (dx > 0) steps = steps < width - 1 - x ? steps : width - 1 - x;
  if (dx < 0) steps = steps < x ? steps : x;
  if (dy > 0) steps = steps < height - 1 - y ? steps : height - 1 - y;
  if (dy < 0) steps = steps < y ? steps : y;
  return steps;
}

/// Ray walks fetch this many steps before looking at them: independent loads in flight instead of one load per
/// decision (the GPU walk is latency-bound otherwise). Results are those of a one-step-at-a-time walk.
constexpr int kRayFetch = 4;

/// Steps s0 .. s0 + kRayFetch - 1 of the ray from (x, y) along (dx, dy); kNoDisparity beyond its last in-image step.
TM_HOST_DEVICE TM_FORCE_INLINE void fetchRaySteps(ImageView<const int16_t> input, int x, int y, int dx, int dy, int s0,
                                                  int inImage, int16_t (&values)[kRayFetch]) {
  TM_UNROLL
  for (int j = 0; j < kRayFetch; ++j) {
    values[j] = s0 + j <= inImage ? input.at(x + (s0 + j) * dx, y + (s0 + j) * dy) : kNoDisparity;
  }
}

/// II.B outlier test: a disparity is kept when along at least one of the 8 radial directions, within radius r,
/// consecutive estimates change by at most maxStepPx and at least half of the ray's in-image pixels carry one.
struct RemoveOutliers {
  ImageView<const int16_t> input;
  ImageView<int16_t> output;
  int radius;
  float maxStepPx;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, input.width, x, y);
    const int16_t centre = input[index];
    output[index] = centre;
    if (centre == kNoDisparity) return;
    for (int k = 0; k < 8; ++k) {
      int dx, dy;
      radialDirection(k, dx, dy);
      const int inImage = stepsInside(x, y, dx, dy, input.width, input.height, radius);
      int previous = centre;
      int estimates = 0;
      bool smooth = true;
      for (int s0 = 1; s0 <= inImage && smooth; s0 += kRayFetch) {
        int16_t values[kRayFetch];
        fetchRaySteps(input, x, y, dx, dy, s0, inImage, values);
        TM_UNROLL
        for (int j = 0; j < kRayFetch; ++j) {
          const int16_t value = values[j];
          if (!smooth || value == kNoDisparity) continue;
          const int step = value - previous;
          if (static_cast<float>(step < 0 ? -step : step) > maxStepPx) {
            smooth = false;
          } else {
            previous = value;
            ++estimates;
          }
        }
      }
      if (smooth && inImage > 0 && 2 * estimates >= inImage) return;  // one smooth ray is enough
    }
    output[index] = kNoDisparity;
  }
};

/// Disparity change per pixel that a filled line may span on a smooth surface: tissue stays well below it, while a
/// depth edge jumps by several pixels at once.
constexpr float kFillSlopeAllowance = 0.25f;

/// II.B hole filling, method 1, given the nearest estimate along each of the 8 rays (distance 0 = none within the
/// radius): every pair of opposite rays that both hit gives a linear interpolation, unless its two ends differ by
/// more than maxEndDifferencePx plus the slope allowance (a depth edge); with at least minLines such lines the hole
/// takes their distance-weighted mean, rounded to the candidate disparities.
TM_HOST_DEVICE TM_FORCE_INLINE int16_t radialFillValue(const int* hitValue, const int* hitDistance, int minLines,
                                                       float maxEndDifferencePx) {
  int lines = 0;
  float weightedSum = 0.0f, weightSum = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const int a = hitDistance[k], b = hitDistance[k + 4];
    if (a == 0 || b == 0) continue;
    const int endDifference = hitValue[k] > hitValue[k + 4] ? hitValue[k] - hitValue[k + 4] : hitValue[k + 4] - hitValue[k];
    if (static_cast<float>(endDifference) > maxEndDifferencePx + kFillSlopeAllowance * static_cast<float>(a + b)) continue;
    const float interpolated = static_cast<float>(hitValue[k] * b + hitValue[k + 4] * a) / static_cast<float>(a + b);
    const float weight = 1.0f / static_cast<float>(a + b);
    weightedSum += weight * interpolated;
    weightSum += weight;
    ++lines;
  }
  return lines >= minLines ? static_cast<int16_t>(floorf(weightedSum / weightSum + 0.5f)) : kNoDisparity;
}

/// The nearest estimate from (x, y) along radial direction k within radius px: its value and its distance in steps
/// (0: none). The ray walk of hole filling method 1.
TM_HOST_DEVICE TM_FORCE_INLINE void nearestAlongRay(ImageView<const int16_t> input, int x, int y, int k, int radius,
                                                    int& value, int& distance) {
  int dx, dy;
  radialDirection(k, dx, dy);
  distance = 0;
  value = 0;
  const int inImage = stepsInside(x, y, dx, dy, input.width, input.height, radius);
  for (int s0 = 1; s0 <= inImage && distance == 0; s0 += kRayFetch) {
    int16_t values[kRayFetch];
    fetchRaySteps(input, x, y, dx, dy, s0, inImage, values);
    TM_UNROLL
    for (int j = 0; j < kRayFetch; ++j) {
      if (distance == 0 && values[j] != kNoDisparity) {
        distance = s0 + j;
        value = values[j];
      }
    }
  }
}

/// II.B hole filling, method 1 (the GPU's form): walks the rays of each hole up to radius px for the nearest
/// estimate, then radialFillValue. A line needs a hit at both ends, so the opposite ray of a ray without a hit is not
/// walked, and the walks stop once fewer than minLines lines remain possible: holes far from any estimate (an
/// image border that no disparity can match) cost a few walks instead of eight, with the same result.
struct FillHolesRadial {
  ImageView<const int16_t> input;
  ImageView<int16_t> output;
  int radius;
  int minLines;
  float maxEndDifferencePx;  ///< a line whose ends differ by more (plus the slope allowance) crosses a depth edge

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t centre = input[index];
    output[index] = centre;
    if (centre != kNoDisparity) return;
    int x, y;
    pixelCoordinates(index, input.width, x, y);
    int hitValue[8];
    int hitDistance[8];
    int linesWithoutEnd = 0;
    for (int k = 0; k < 4; ++k) {
      nearestAlongRay(input, x, y, k, radius, hitValue[k], hitDistance[k]);
      hitValue[k + 4] = 0;
      hitDistance[k + 4] = 0;
      if (hitDistance[k] > 0) nearestAlongRay(input, x, y, k + 4, radius, hitValue[k + 4], hitDistance[k + 4]);
      if (hitDistance[k + 4] == 0 && ++linesWithoutEnd > 4 - minLines) return;  // stays a hole
    }
    output[index] = radialFillValue(hitValue, hitDistance, minLines, maxEndDifferencePx);
  }
};

/// II.B hole filling, method 1 (the CPU's form): the nearest estimates along each ray come from precomputed
/// per-direction maps (StereoBackendCpu.cpp builds them with one sweep per direction), then radialFillValue.
struct FillHolesRadialFromHits {
  ImageView<const int16_t> input;
  ImageView<int16_t> output;
  const int16_t* hitDistance;  ///< [8][pixels]
  const int16_t* hitValue;     ///< [8][pixels]
  int minLines;
  float maxEndDifferencePx;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t centre = input[index];
    output[index] = centre;
    if (centre != kNoDisparity) return;
    const int64_t pixels = input.pixelCount();
    int value[8], distance[8];
    for (int k = 0; k < 8; ++k) {
      distance[k] = hitDistance[k * pixels + index];
      value[k] = hitValue[k * pixels + index];
    }
    output[index] = radialFillValue(value, distance, minLines, maxEndDifferencePx);
  }
};

/// Box sums work on exact fixed-point integers (a value v enters as v * scale rounded half to even, as llrint), so
/// any summation order gives the same sums: the CPU uses prefix sums along rows and running sums down columns, the
/// GPU direct sums per pixel (parallel, coalesced), and both produce identical results.
constexpr double kFixedPointScale = 65536.0;  ///< 1/65536 px resolution for real-valued maps
/// Real values enter the box sums only up to this magnitude; larger ones count as no value, as NaN does. Disparities
/// are int16, so the real maps (corrections of disparities) never come near it. It bounds every fixed-point value by
/// 2^32 and every box sum (windows up to 401 x 401 pixels) by 2^50, where the conversions below are exact.
constexpr float kMaxFixedPointInput = 65536.0f;

/// 1.5 * 2^52: adding it to a double of magnitude below 2^51 leaves that value rounded half to even (the default
/// rounding mode) in the low mantissa bits, whose pattern is then the integer plus kShifterBits.
constexpr double kShifter = 6755399441055744.0;
constexpr int64_t kShifterBits = 0x4338000000000000LL;

/// llrint(x) for |x| < 2^51, without a conversion instruction, so that it vectorises on AVX2 (which has no double to
/// int64 conversion); device and host alike.
TM_HOST_DEVICE TM_FORCE_INLINE int64_t roundToInt64(double x) {
  const double shifted = x + kShifter;
  int64_t bits;
  memcpy(&bits, &shifted, sizeof bits);
  return bits - kShifterBits;
}

/// static_cast<double>(i) for |i| < 2^51 (exact), by the same trick in reverse.
TM_HOST_DEVICE TM_FORCE_INLINE double int64ToDouble(int64_t i) {
  const int64_t bits = i + kShifterBits;
  double shifted;
  memcpy(&shifted, &bits, sizeof shifted);
  return shifted - kShifter;
}

/// Box sums, pass 1 on the CPU (one row per call): sums over x of a value and a validity count, radius r, as
/// differences of the row's prefix sums. The values are gathered in one vectorised pass; only the prefix is serial.
template <class Value>
struct BoxRowSums {
  Value value;  ///< value(x, y, out) -> bool valid; out is the fixed-point value
  int width, radius;
  int64_t* rowSum;
  int* rowCount;

  void operator()(int64_t row) const {
    // Locals, so that the compiler knows the stores below do not change them (and vectorises).
    const int y = static_cast<int>(row), w = width, r = radius;
    const Value rowValue = value;
    thread_local std::vector<int64_t> prefixStore;
    thread_local std::vector<int> prefixCountStore;
    prefixStore.resize(static_cast<std::size_t>(w) + 1);
    prefixCountStore.resize(static_cast<std::size_t>(w) + 1);
    int64_t* __restrict prefix = prefixStore.data();  // prefix[x]: sum of the values left of x
    int* __restrict prefixCount = prefixCountStore.data();
    for (int x = 0; x < w; ++x) {
      int64_t v = 0;
      const bool valid = rowValue(x, y, v);
      prefix[x + 1] = valid ? v : 0;
      prefixCount[x + 1] = valid ? 1 : 0;
    }
    prefix[0] = 0;
    prefixCount[0] = 0;
    for (int x = 1; x <= w; ++x) {
      prefix[x] += prefix[x - 1];
      prefixCount[x] += prefixCount[x - 1];
    }
    int64_t* __restrict sums = rowSum + static_cast<int64_t>(y) * w;
    int* __restrict counts = rowCount + static_cast<int64_t>(y) * w;
    const auto clippedWindowSums = [&](int begin, int end) {  // x in [begin, end): window [x - r, x + r] clipped
      for (int x = begin; x < end; ++x) {
        const int lo = x - r < 0 ? 0 : x - r, hi = x + r + 1 > w ? w : x + r + 1;
        sums[x] = prefix[hi] - prefix[lo];
        counts[x] = prefixCount[hi] - prefixCount[lo];
      }
    };
    // Windows that lie inside the row: contiguous differences, vectorised.
    const int innerBegin = r < w ? r : w;
    const int innerEnd = w - r - 1 > innerBegin ? w - r - 1 : innerBegin;
    clippedWindowSums(0, innerBegin);
    const int64_t* __restrict entering = prefix + r + 1;
    const int64_t* __restrict leaving = prefix - r;
    const int* __restrict enteringCount = prefixCount + r + 1;
    const int* __restrict leavingCount = prefixCount - r;
    for (int x = innerBegin; x < innerEnd; ++x) {
      sums[x] = entering[x] - leaving[x];
      counts[x] = enteringCount[x] - leavingCount[x];
    }
    clippedWindowSums(innerEnd, w);
  }
};

/// Box sums, pass 1 on the GPU (one pixel per call): the same sums, added directly.
template <class Value>
struct BoxRowSumsDirect {
  Value value;
  int width, radius;
  int64_t* rowSum;
  int* rowCount;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, width, x, y);
    const int x0 = x - radius < 0 ? 0 : x - radius, x1 = x + radius >= width ? width - 1 : x + radius;
    int64_t sum = 0, v = 0;
    int count = 0;
    for (int xx = x0; xx <= x1; ++xx) {
      if (value(xx, y, v)) { sum += v; ++count; }
    }
    rowSum[index] = sum;
    rowCount[index] = count;
  }
};

/// True for box-sum consumers that take a whole row segment at once (consumeRow(firstIndex, sums, counts, n)): the
/// CPU's vectorised forms of a per-pixel consumer.
template <class Consumer, class = void>
struct ConsumesRows : std::false_type {};
template <class Consumer>
struct ConsumesRows<Consumer, std::void_t<decltype(std::declval<const Consumer&>().consumeRow(
                                  int64_t{}, static_cast<const int64_t*>(nullptr), static_cast<const int*>(nullptr), 0))>>
    : std::true_type {};

/// Box sums, pass 2 on the CPU (one block of kColumnsPerTask columns per call, row-contiguous): running sums over y,
/// handed to consumer(pixelIndex, sum, count), or a row segment at a time to consumer.consumeRow, as soon as each is
/// complete (no box-sum image is stored).
template <int kColumnsPerTask, class Consumer>
struct BoxColumnSums {
  const int64_t* rowSum;
  const int* rowCount;
  int width, height, radius;
  Consumer consumer;

  static constexpr int64_t taskCount(int width) { return (width + kColumnsPerTask - 1) / kColumnsPerTask; }

  TM_HOST_DEVICE void operator()(int64_t task) const {
    const int x0 = static_cast<int>(task) * kColumnsPerTask;
    const int columns = width - x0 < kColumnsPerTask ? width - x0 : kColumnsPerTask;
    int64_t sum[kColumnsPerTask];
    int count[kColumnsPerTask];
    for (int c = 0; c < columns; ++c) {
      sum[c] = 0;
      count[c] = 0;
    }
    for (int y = 0; y < radius && y < height; ++y) {
      for (int c = 0; c < columns; ++c) {
        sum[c] += rowSum[static_cast<int64_t>(y) * width + x0 + c];
        count[c] += rowCount[static_cast<int64_t>(y) * width + x0 + c];
      }
    }
    for (int y = 0; y < height; ++y) {
      const int enter = y + radius, leave = y - radius - 1;
      if (enter < height) {
        for (int c = 0; c < columns; ++c) {
          sum[c] += rowSum[static_cast<int64_t>(enter) * width + x0 + c];
          count[c] += rowCount[static_cast<int64_t>(enter) * width + x0 + c];
        }
      }
      if (leave >= 0) {
        for (int c = 0; c < columns; ++c) {
          sum[c] -= rowSum[static_cast<int64_t>(leave) * width + x0 + c];
          count[c] -= rowCount[static_cast<int64_t>(leave) * width + x0 + c];
        }
      }
      const int64_t firstIndex = static_cast<int64_t>(y) * width + x0;
      if constexpr (ConsumesRows<Consumer>::value) {
        consumer.consumeRow(firstIndex, sum, count, columns);
      } else {
        for (int c = 0; c < columns; ++c) consumer(firstIndex + c, sum[c], count[c]);
      }
    }
  }
};

/// Box sums, pass 2 on the GPU (one pixel per call): the same sums, added directly, handed to the consumer.
template <class Consumer>
struct BoxColumnSumsDirect {
  const int64_t* rowSum;
  const int* rowCount;
  int width, height, radius;
  Consumer consumer;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, width, x, y);
    const int y0 = y - radius < 0 ? 0 : y - radius, y1 = y + radius >= height ? height - 1 : y + radius;
    int64_t sum = 0;
    int count = 0;
    for (int yy = y0; yy <= y1; ++yy) {
      sum += rowSum[static_cast<int64_t>(yy) * width + x];
      count += rowCount[static_cast<int64_t>(yy) * width + x];
    }
    consumer(index, sum, count);
  }
};

/// A box-sum consumer that stores the sums (tests, inspection).
struct StoreBoxSums {
  int64_t* boxSum;
  int* boxCount;
  TM_HOST_DEVICE void operator()(int64_t index, int64_t sum, int count) const {
    boxSum[index] = sum;
    boxCount[index] = count;
  }
};

/// Box-sum inputs: a discrete disparity map (valid where != kNoDisparity), scale 1.
struct DiscreteDisparityValue {
  ImageView<const int16_t> disparity;
  static constexpr double kScale = 1.0;
  using TileSum = int32_t;  ///< exact for |d| <= 1000 over windows up to 41x41 (GPU tiles keep it in shared memory)
  TM_HOST_DEVICE bool operator()(int x, int y, int64_t& value) const {
    const int16_t d = disparity.at(x, y);
    value = d;
    return d != kNoDisparity;
  }
};

/// Box-sum inputs: a float map (valid where finite and within kMaxFixedPointInput) in fixed point.
struct FloatValue {
  ImageView<const float> map;
  static constexpr double kScale = kFixedPointScale;
  using TileSum = int64_t;
  TM_HOST_DEVICE bool operator()(int x, int y, int64_t& value) const {
    const float v = map.at(x, y);
    const bool valid = fabsf(v) <= kMaxFixedPointInput;  // false for NaN
    value = valid ? roundToInt64(static_cast<double>(v) * kScale) : 0;
    return valid;
  }
};

/// True where left pixel (x, y) or its match x - d lies near a highlight of its eye (near: HighlightKernels.h's
/// MarkNearHighlight maps, kNoDisparity where none).
TM_HOST_DEVICE TM_FORCE_INLINE bool nearHighlight(ImageView<const int16_t> leftNear, ImageView<const int16_t> rightNear,
                                                  int x, int y, int d) {
  if (leftNear.at(x, y) != kNoDisparity) return true;
  const int xr = x - d;
  return xr >= 0 && xr < rightNear.width && rightNear.at(xr, y) != kNoDisparity;
}

/// A left pixel whose ZNCC window around its match x - d would leave the right image cannot have been measured:
/// its value came from filling or smoothing across the image border, or from a winner among the few candidates
/// left there (at the left border such winners are metres away). No estimate there.
struct DropOutsideRightView {
  ImageView<float> disparity;
  int windowRadiusPx;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    const float d = disparity[index];
    if (!isFinite(d)) return;
    int x, y;
    pixelCoordinates(index, disparity.width, x, y);
    const int xr = x - static_cast<int>(floorf(d + 0.5f));
    if (xr - windowRadiusPx < 0 || xr + windowRadiusPx > disparity.width - 1) disparity[index] = NAN;
  }
};

/// II.B hole filling, method 2: a hole whose square neighbourhood of radius r (inside the image) is at least
/// minValidFraction valid takes the neighbourhood's mean, rounded to the candidate disparities.
/// A box-sum consumer: sum and count are those of DiscreteDisparityValue (scale 1) over the radius.
struct FillHolesDisc {
  ImageView<const int16_t> input;
  ImageView<int16_t> output;
  int radius;
  float minValidFraction;

  /// The rule for one pixel whose box (area pixels inside the image) holds count estimates summing to boxSum:
  /// a hole with enough estimates around it takes their rounded mean; anything else keeps its value. Branch-free.
  TM_HOST_DEVICE static int16_t filled(int16_t centre, int64_t boxSum, int count, int area, float minValidFraction) {
    const bool fills = (centre == kNoDisparity) & (count != 0) &
                       !(static_cast<float>(count) < minValidFraction * static_cast<float>(area));
    const double mean = floor(int64ToDouble(boxSum) / (count != 0 ? count : 1) + 0.5);  // exact: |boxSum| < 2^34
    return fills ? static_cast<int16_t>(static_cast<int>(mean)) : centre;
  }
  /// Pixels of the box around x that lie inside [0, size).
  TM_HOST_DEVICE static int insideSpan(int x, int radius, int size) {
    const int lo = x - radius < 0 ? 0 : x - radius, hi = x + radius >= size ? size - 1 : x + radius;
    return hi - lo + 1;
  }

  TM_HOST_DEVICE void operator()(int64_t index, int64_t boxSum, int count) const {
    int x, y;
    pixelCoordinates(index, input.width, x, y);
    const int area = insideSpan(x, radius, input.width) * insideSpan(y, radius, input.height);
    output[index] = filled(input[index], boxSum, count, area, minValidFraction);
  }
  /// The CPU's form (BoxColumnSums hands it a row segment): the same rule, vectorised.
  void consumeRow(int64_t firstIndex, const int64_t* __restrict boxSums, const int* __restrict boxCounts,
                  int columns) const {
    int x0, y;
    pixelCoordinates(firstIndex, input.width, x0, y);
    const int rows = insideSpan(y, radius, input.height), width = input.width, r = radius;
    const float fraction = minValidFraction;
    const int16_t* __restrict in = &input[firstIndex];
    int16_t* __restrict out = &output[firstIndex];
    for (int c = 0; c < columns; ++c) {
      out[c] = filled(in[c], boxSums[c], boxCounts[c], insideSpan(x0 + c, r, width) * rows, fraction);
    }
  }
};

/// II.C initial state: d^(0) = o (float), NaN where there is no estimate.
struct InitialiseSmoothed {
  ImageView<const int16_t> discrete;
  ImageView<float> smoothed;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t o = discrete[index];
    smoothed[index] = o == kNoDisparity ? NAN : static_cast<float>(o);
  }
};

/// II.C eq. (1) and (2): d^(k) = average(o_j); b = d^(k) - alpha o - (1 - alpha) d^(k-1). A box-sum consumer of
/// DiscreteDisparityValue (scale 1).
struct LaplacianStep {
  ImageView<const int16_t> discrete;
  ImageView<const float> previous;
  ImageView<float> current, correction;
  float alpha;

  /// The step for one pixel, branch-free: NaN for both where there is no estimate or none around it.
  TM_HOST_DEVICE static void step(int16_t o, int64_t boxSum, int boxCount, float previousValue, float alpha,
                                  float& currentValue, float& correctionValue) {
    const bool valid = (o != kNoDisparity) & (boxCount != 0);
    const float average = static_cast<float>(int64ToDouble(boxSum) / (valid ? boxCount : 1));  // exact: < 2^34
    currentValue = valid ? average : NAN;
    correctionValue = valid ? average - alpha * static_cast<float>(o) - (1.0f - alpha) * previousValue : NAN;
  }

  TM_HOST_DEVICE void operator()(int64_t index, int64_t boxSum, int boxCount) const {
    step(discrete[index], boxSum, boxCount, previous[index], alpha, current[index], correction[index]);
  }
  /// The CPU's form (BoxColumnSums hands it a row segment): the same step, vectorised.
  void consumeRow(int64_t firstIndex, const int64_t* __restrict boxSums, const int* __restrict boxCounts,
                  int columns) const {
    const int16_t* __restrict o = &discrete[firstIndex];
    const float* __restrict before = &previous[firstIndex];
    float* __restrict now = &current[firstIndex];
    float* __restrict b = &correction[firstIndex];
    const float a = alpha;
    for (int c = 0; c < columns; ++c) step(o[c], boxSums[c], boxCounts[c], before[c], a, now[c], b[c]);
  }
};

/// II.C eq. (3): d^(k) -= average(b_j), from the fixed-point box sum of the corrections b.
TM_HOST_DEVICE TM_FORCE_INLINE float correctedDisparity(float current, int64_t correctionBoxSum, int boxCount) {
  return current - static_cast<float>(int64ToDouble(correctionBoxSum) / (FloatValue::kScale * boxCount));
}

/// The re-selection cost of candidate disparity o* with positive quantised ZNCC q at smoothed disparity d:
/// 1/ZNCC + eta (o* - d)^2.
TM_HOST_DEVICE TM_FORCE_INLINE float reselectionCost(int16_t q, int candidateDisparity, float d, float eta) {
  const float offset = static_cast<float>(candidateDisparity) - d;
  return kZnccScale / static_cast<float>(q) + eta * offset * offset;
}

/// II.C eq. (3) and the re-selection of o_i: d^(k) -= average(b_j); then o_i := the candidate in d^(k) +- search
/// with the lowest reselectionCost, the lowest disparity on ties (candidates without a positive ZNCC are skipped).
/// A box-sum consumer of FloatValue (fixed point) over the corrections b. The CPU runs the same rule a row segment
/// at a time (ReselectDiscreteRows, vectorised).
struct ReselectDiscrete {
  const int16_t* volume;
  VolumeLayout layout;
  int minDisparity, disparityCount, search;
  float eta;
  ImageView<float> current;
  ImageView<int16_t> discrete;
  /// The near-highlight maps (null data: none). Where the pixel or its match x - o_i lies near a highlight, the cost
  /// volume holds the highlights' false matches: o_i keeps the value it has, the tissue's (d_i is still smoothed).
  ImageView<const int16_t> leftHighlights{}, rightHighlights{};

  TM_HOST_DEVICE bool keepsFilledValue(int x, int y, int16_t o) const {
    return leftHighlights.data != nullptr && nearHighlight(leftHighlights, rightHighlights, x, y, o);
  }
  /// Pixels with an estimate and corrections around them take part.
  TM_HOST_DEVICE static bool takesPart(int16_t discreteDisparity, int boxCount) {
    return (discreteDisparity != kNoDisparity) & (boxCount != 0);
  }
  TM_HOST_DEVICE bool reselects(int64_t index, int boxCount) const { return takesPart(discrete[index], boxCount); }
  /// Index of the candidate nearest to the smoothed disparity d (finite).
  TM_HOST_DEVICE int centreIndex(float d) const { return static_cast<int>(floorf(d + 0.5f)) - minDisparity; }

  TM_HOST_DEVICE void operator()(int64_t index, int64_t boxSum, int boxCount) const {
    if (!reselects(index, boxCount)) return;
    int x, y;
    pixelCoordinates(index, current.width, x, y);
    const float d = correctedDisparity(current[index], boxSum, boxCount);
    current[index] = d;
    if (!isFinite(d) || keepsFilledValue(x, y, discrete[index])) return;
    const int centre = centreIndex(d);
    float bestCost = INFINITY;
    int best = -1;
    for (int i = centre - search; i <= centre + search; ++i) {
      if (i < 0 || i >= disparityCount) continue;
      const int16_t q = volume[layout.index(x, y, i)];
      if (q <= 0) continue;  // kNoZncc or non-positive correlation: 1/ZNCC is not a cost
      const float cost = reselectionCost(q, i + minDisparity, d, eta);
      if (cost < bestCost) {
        bestCost = cost;
        best = i;
      }
    }
    if (best >= 0) discrete[index] = static_cast<int16_t>(best + minDisparity);
  }
};

/// Discrete map to float disparity (NaN where none), e.g. for inspecting intermediate stages.
struct DiscreteToFloat {
  ImageView<const int16_t> discrete;
  ImageView<float> output;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t o = discrete[index];
    output[index] = o == kNoDisparity ? NAN : static_cast<float>(o);
  }
};

/// The right-view winner as one integer whose maximum is the best score, ties going to the lowest disparity index
/// (the CPU's rule): lets GPU threads merge candidates with atomicMax. 0 means "none".
TM_HOST_DEVICE TM_FORCE_INLINE uint32_t packRightWinner(int16_t score, int disparityIndex) {
  return (static_cast<uint32_t>(score + 32768) << 16) | static_cast<uint32_t>(0xFFFF - disparityIndex);
}
TM_HOST_DEVICE TM_FORCE_INLINE int16_t unpackRightWinner(uint32_t key, int minDisparity) {
  return key == 0 ? kNoDisparity : static_cast<int16_t>(minDisparity + (0xFFFF - static_cast<int>(key & 0xFFFF)));
}

/// The left winners kept for the outlier removal. A winner within rangeEndMarginPx of either end of the range
/// (minDisparity..maxDisparity) is dropped where that test is on (margin >= 0): its cost was still improving at the
/// range's end, so its match most likely lies beyond. Left-right consistency, where on (maxDifferencePx >= 0): a
/// left winner d at x survives when the right view's winner at x - d is within maxDifferencePx of d (occlusions and
/// window fattening at depth edges fail it).
struct KeepWinners {
  ImageView<const int16_t> leftDisparity, rightDisparity;
  ImageView<int16_t> output;
  int minDisparity, maxDisparity;
  int rangeEndMarginPx;
  int maxDifferencePx;

  TM_HOST_DEVICE bool nearRangeEnd(int d) const {
    return rangeEndMarginPx >= 0 && (d - minDisparity <= rangeEndMarginPx || maxDisparity - d <= rangeEndMarginPx);
  }

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t d = leftDisparity[index];
    output[index] = d;
    if (d == kNoDisparity) return;
    if (nearRangeEnd(d)) {
      output[index] = kNoDisparity;
      return;
    }
    if (maxDifferencePx < 0) return;
    int x, y;
    pixelCoordinates(index, leftDisparity.width, x, y);
    const int xr = x - d;
    const int16_t other = xr >= 0 && xr < leftDisparity.width ? rightDisparity.at(xr, y) : kNoDisparity;
    const int difference = other == kNoDisparity ? maxDifferencePx + 1 : (other > d ? other - d : d - other);
    if (difference > maxDifferencePx) output[index] = kNoDisparity;
  }
};

/// The refined output: the smoothed d_i where it agrees with the re-selected discrete o_i within maxDeviationPx
/// (smoothing supplies sub-pixel precision on smooth surfaces); o_i where it does not (depth edges, where a
/// neighbourhood average is meaningless).
struct FinalDisparity {
  ImageView<const int16_t> discrete;
  ImageView<float> smoothed;
  float maxDeviationPx;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t o = discrete[index];
    if (o == kNoDisparity) {
      smoothed[index] = NAN;
      return;
    }
    const float d = smoothed[index];
    const float deviation = fabsf(d - static_cast<float>(o));
    if (!(deviation <= maxDeviationPx)) smoothed[index] = static_cast<float>(o);
  }
};

}  // namespace tissuemosaic::stereo
