#pragma once
/// @file AdCensusKernels.h
/// @brief The per-element steps of the AD-Census matcher (Mei et al., "On building an accurate stereo matching
/// system on graphics hardware", ICCV workshops 2011), the engine's optional alternative to the paper's ZNCC
/// pipeline (StereoParameters::method): census + absolute-difference cost, cross-based aggregation, four-direction
/// scanline optimisation and winner-takes-all with a parabola's sub-pixel offset. Written once for both backends.
///
/// Costs are integers in units of 1 / kAdCensusCostUnit (the robust functions 1 - exp(-c / lambda) are tabulated on
/// the host), so every sum is exact and the CPU and the GPU give the same volume bit for bit in any order.
///
/// Volumes are pixel-major: element (pixel, disparity index i) lies at pixel * disparityCount + i, pixel = y * width
/// + x. A left pixel x at disparity d = minDisparity + i matches the right pixel x - d.
#include "Core/HostDevice.h"
#include "Core/Image.h"
#include "StereoKernels.h"

#include <cstdint>

namespace tissuemosaic::stereo {

constexpr int kAdCensusCostUnit = 1024;  ///< a robust cost of 1.0
constexpr int kCensusMaxBits = 64;

/// The robust cost functions 1 - exp(-c / lambda), tabulated in cost units: census by Hamming distance, AD by grey
/// difference. Filled on the host (AdCensusCostTables::make in AdCensusPipeline) and passed by value.
struct AdCensusCostTables {
  int32_t census[kCensusMaxBits + 1];
  int32_t absoluteDifference[256];
};

/// Path penalties of the scanline optimisation by how many of the two images change by tauSo or more along the
/// step (0: neither, 1: one, 2: both), in cost units.
struct PathPenalties {
  int32_t small[3];
  int32_t large[3];
};

/// Census transform: one bit per window pixel other than the centre, set where the neighbour is darker than the
/// centre (rows top to bottom, columns left to right, the first pixel in the highest bit); borders replicated.
struct CensusTransform {
  ImageView<const uint8_t> grey;
  uint64_t* census;
  int halfWidth, halfHeight;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, grey.width, x, y);
    const int centre = grey[index];
    uint64_t bits = 0;
    for (int dy = -halfHeight; dy <= halfHeight; ++dy) {
      const int row = clampIndex(y + dy, grey.height);
      for (int dx = -halfWidth; dx <= halfWidth; ++dx) {
        if (dx == 0 && dy == 0) continue;
        bits = (bits << 1) | (grey.at(clampIndex(x + dx, grey.width), row) < centre ? 1u : 0u);
      }
    }
    census[index] = bits;
  }
};

/// Arm planes of a cross: reach to the left, right, up and down, in pixels, the pixel itself excluded.
enum ArmPlane { kArmLeft = 0, kArmRight = 1, kArmUp = 2, kArmDown = 3 };

/// Cross arms (Mei et al.'s rules on grey levels): an arm grows while the next pixel differs from the anchor by less
/// than limit and from its predecessor by less than limit, up to maxPx; beyond longPx the anchor difference must
/// also stay below limitLong. arms: 4 planes of pixelCount bytes (ArmPlane order).
struct CrossArms {
  ImageView<const uint8_t> grey;
  uint8_t* arms;
  int maxPx, longPx, limit, limitLong;

  TM_HOST_DEVICE int reach(int x, int y, int dx, int dy) const {
    const int anchor = grey.at(x, y);
    int length = 0;
    for (int s = 1; s <= maxPx; ++s) {
      const int xs = x + s * dx, ys = y + s * dy;
      if (!grey.contains(xs, ys)) break;
      const int value = grey.at(xs, ys), previous = grey.at(xs - dx, ys - dy);
      const int fromAnchor = value > anchor ? value - anchor : anchor - value;
      const int fromPrevious = value > previous ? value - previous : previous - value;
      if (fromAnchor >= limit || fromPrevious >= limit) break;
      if (s > longPx && fromAnchor >= limitLong) break;
      length = s;
    }
    return length;
  }
  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, grey.width, x, y);
    const int64_t plane = grey.pixelCount();
    arms[kArmLeft * plane + index] = static_cast<uint8_t>(reach(x, y, -1, 0));
    arms[kArmRight * plane + index] = static_cast<uint8_t>(reach(x, y, 1, 0));
    arms[kArmUp * plane + index] = static_cast<uint8_t>(reach(x, y, 0, -1));
    arms[kArmDown * plane + index] = static_cast<uint8_t>(reach(x, y, 0, 1));
  }
};

/// Where a volume element's pixel and disparity lie.
struct VolumeGeometry {
  int width, height, minDisparity, disparityCount;
  TM_HOST_DEVICE void element(int64_t index, int& x, int& y, int& i) const {
    const int64_t pixel = index / disparityCount;
    i = static_cast<int>(index - pixel * disparityCount);
    pixelCoordinates(pixel, width, x, y);
  }
  TM_HOST_DEVICE int64_t pixelCount() const { return static_cast<int64_t>(width) * height; }
  TM_HOST_DEVICE int64_t elementCount() const { return pixelCount() * disparityCount; }
};

/// Runs an element functor (element(x, y, i, index)) over a whole volume, one element per call: the GPU's form, in
/// which neighbouring threads take neighbouring disparities.
template <class ElementFunctor>
struct VolumeElements {
  VolumeGeometry g;
  ElementFunctor f;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y, i;
    g.element(index, x, y, i);
    f.element(x, y, i, index);
  }
};

/// The same calls one image row per call: the CPU's form, which counts x and i instead of dividing them out of
/// every index (two 64-bit divisions per element bounded the CPU's cost and aggregation).
template <class ElementFunctor>
struct VolumeRows {
  VolumeGeometry g;
  ElementFunctor f;
  void operator()(int64_t row) const {
    const int y = static_cast<int>(row);
    int64_t index = row * g.width * g.disparityCount;
    for (int x = 0; x < g.width; ++x)
      for (int i = 0; i < g.disparityCount; ++i, ++index) f.element(x, y, i, index);
  }
};

/// Matching cost per element: census Hamming distance and grey difference through the robust tables, the right
/// pixel clamped into the image.
struct AdCensusCost {
  VolumeGeometry g;
  ImageView<const uint8_t> leftGrey, rightGrey;
  const uint64_t *leftCensus, *rightCensus;
  AdCensusCostTables tables;
  int32_t* cost;
  TM_HOST_DEVICE void element(int x, int y, int i, int64_t index) const {
    const int xr = clampIndex(x - (g.minDisparity + i), g.width);
    const int64_t left = static_cast<int64_t>(y) * g.width + x, right = static_cast<int64_t>(y) * g.width + xr;
    const int difference = leftGrey[left] - rightGrey[right];
    cost[index] = tables.census[popcount64(leftCensus[left] ^ rightCensus[right])] +
                  tables.absoluteDifference[difference < 0 ? -difference : difference];
  }
};

/// The support region of an element: the left pixel's arm, shortened to its match's arm in the right image (0 where
/// the match is outside the right image).
TM_HOST_DEVICE TM_FORCE_INLINE int combinedArm(const uint8_t* leftArms, const uint8_t* rightArms, int plane,
                                               const VolumeGeometry& g, int x, int y, int i) {
  const int64_t planeOffset = static_cast<int64_t>(plane) * g.pixelCount();
  const int leftArm = leftArms[planeOffset + static_cast<int64_t>(y) * g.width + x];
  const int xr = x - (g.minDisparity + i);
  if (xr < 0 || xr >= g.width) return 0;
  const int rightArm = rightArms[planeOffset + static_cast<int64_t>(y) * g.width + xr];
  return leftArm < rightArm ? leftArm : rightArm;
}

/// A window sum and its pixel count packed in one int64 (sum << 16 | count): prefix sums and their differences carry
/// both at once, exactly (a window holds at most 255 x 255 < 2^16 pixels, arms being at most 127 px; its sum of
/// costs of at most 2 kAdCensusCostUnit each stays below 2^28, so a window's sum fits an int32 as well).
constexpr int kPackedCountBits = 16;
static_assert(int64_t(2) * kAdCensusCostUnit * 255 * 255 < (int64_t(1) << 28), "window sums must fit 28 bits");
TM_HOST_DEVICE TM_FORCE_INLINE int64_t packSumCount(int64_t sum, int64_t count) {
  return sum * (int64_t(1) << kPackedCountBits) + count;
}
TM_HOST_DEVICE TM_FORCE_INLINE int64_t packedCount(int64_t packed) {
  return packed & ((int64_t(1) << kPackedCountBits) - 1);
}
TM_HOST_DEVICE TM_FORCE_INLINE int64_t packedSum(int64_t packed) { return packed >> kPackedCountBits; }

/// Lines of one aggregation pass: rows (horizontal) or columns. The prefix of a line has one more position than the
/// line: prefix(k) = sum of positions < k.
struct AggregationLines {
  VolumeGeometry g;
  bool horizontal;
  TM_HOST_DEVICE int lineCount() const { return horizontal ? g.height : g.width; }
  TM_HOST_DEVICE int lineLength() const { return horizontal ? g.width : g.height; }
  /// Volume element of position k on line `line`, disparity index i.
  TM_HOST_DEVICE int64_t element(int line, int k, int i) const {
    const int64_t pixel = horizontal ? static_cast<int64_t>(line) * g.width + k : static_cast<int64_t>(k) * g.width + line;
    return pixel * g.disparityCount + i;
  }
  /// Prefix entry k in [0, lineLength] of line `line`, disparity index i. Laid out as the volume with one more
  /// column (rows) or one more row (columns): an image row of elements finds both its prefix entries along an
  /// image row of the prefix, in order, in either direction (the CPU's window pass reads them as streams).
  TM_HOST_DEVICE int64_t prefix(int line, int k, int i) const {
    const int64_t entry =
        horizontal ? static_cast<int64_t>(line) * (g.width + 1) + k : static_cast<int64_t>(k) * g.width + line;
    return entry * g.disparityCount + i;
  }
};

/// Prefix sums along lines of packed (sum, count) values: the raw costs (count 1 each) in the first pass of an
/// aggregation iteration, the first pass's packed window sums in the second. operator() runs one disparity of one
/// line (the GPU's thread: neighbouring threads read neighbouring disparities); lineBlock() runs all disparities of
/// neighbouring lines, position by position (the CPU's task: a block of columns is contiguous in memory at each
/// position). Same additions either way.
struct PrefixAlongLines {
  AggregationLines lines;
  const int32_t* cost;     ///< first pass: raw costs (packed is null)
  const int64_t* packed;   ///< second pass: packed window sums
  int64_t* prefix;

  TM_HOST_DEVICE int64_t value(int64_t element) const {
    return packed ? packed[element] : packSumCount(cost[element], 1);
  }
  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int line = static_cast<int>(index / lines.g.disparityCount);
    const int i = static_cast<int>(index - static_cast<int64_t>(line) * lines.g.disparityCount);
    int64_t running = 0;
    prefix[lines.prefix(line, 0, i)] = 0;
    for (int k = 0; k < lines.lineLength(); ++k) {
      running += value(lines.element(line, k, i));
      prefix[lines.prefix(line, k + 1, i)] = running;
    }
  }
  void lineBlock(int firstLine, int endLine) const {
    const int count = lines.g.disparityCount;
    for (int line = firstLine; line < endLine; ++line) {
      int64_t* first = prefix + lines.prefix(line, 0, 0);
      for (int i = 0; i < count; ++i) first[i] = 0;
    }
    for (int k = 0; k < lines.lineLength(); ++k) {
      for (int line = firstLine; line < endLine; ++line) {
        const int64_t* before = prefix + lines.prefix(line, k, 0);
        int64_t* after = prefix + lines.prefix(line, k + 1, 0);
        const int64_t element = lines.element(line, k, 0);
        for (int i = 0; i < count; ++i) after[i] = before[i] + value(element + i);
      }
    }
  }
};

/// Window sums along lines from the prefix sums, over each element's combined arm (left/right on rows, up/down on
/// columns). First pass: writes the packed (sum, count); second pass: the aggregated cost sum / count (integer
/// division) back into cost.
struct WindowAlongLines {
  AggregationLines lines;
  const uint8_t *leftArms, *rightArms;
  const int64_t* prefix;
  int64_t* packedOut;  ///< first pass output (null in the second)
  int32_t* costOut;    ///< second pass output (null in the first)

  TM_HOST_DEVICE void element(int x, int y, int i, int64_t index) const {
    const int line = lines.horizontal ? y : x, k = lines.horizontal ? x : y;
    const int before = combinedArm(leftArms, rightArms, lines.horizontal ? kArmLeft : kArmUp, lines.g, x, y, i);
    const int after = combinedArm(leftArms, rightArms, lines.horizontal ? kArmRight : kArmDown, lines.g, x, y, i);
    const int64_t window = prefix[lines.prefix(line, k + after + 1, i)] - prefix[lines.prefix(line, k - before, i)];
    if (packedOut) {
      packedOut[index] = window;
    } else {
      // In 32 bits (see packSumCount): a 64-bit division is several times slower on both backends.
      costOut[index] = static_cast<int32_t>(packedSum(window)) / static_cast<int32_t>(packedCount(window));
    }
  }
  /// The elements of lines [firstLine, endLine), position by position (the CPU's form; see PrefixAlongLines).
  void lineBlock(int firstLine, int endLine) const {
    for (int k = 0; k < lines.lineLength(); ++k) {
      for (int line = firstLine; line < endLine; ++line) {
        const int x = lines.horizontal ? k : line, y = lines.horizontal ? line : k;
        const int64_t first = lines.element(line, k, 0);
        for (int i = 0; i < lines.g.disparityCount; ++i) element(x, y, i, first + i);
      }
    }
  }
};

/// The scanline optimisation over all four directions: along each direction r,
/// L(p, d) = C(p, d) + min(L(p-r, d), L(p-r, d +- 1) + P1, min L(p-r) + P2) - min L(p-r), with the penalties chosen
/// by the grey steps of both images along r (PathPenalties); pathCost receives the sum of the four L. Each backend
/// has its own launcher (computeScanlinePathsCpu: a thread per path; computeScanlinePathsCuda: a warp per path, the
/// disparities across its lanes), both built from the element rules below.
struct ScanlineInputs {
  VolumeGeometry g;
  ImageView<const uint8_t> leftGrey, rightGrey;
  const int32_t* cost;
  int32_t* pathCost;
  PathPenalties penalties;
  int edgeGrey;  ///< a grey step of this much or more is an edge
};

constexpr int kScanlineDirectionCount = 4;

/// Scanline direction k (0: left to right, 1: right to left, 2: top to bottom, 3: bottom to top). Its paths are
/// image rows for horizontal directions and columns otherwise; step s + 1 of a path lies at step s + (dx, dy).
struct ScanlineDirection {
  int dx, dy;
  TM_HOST_DEVICE static ScanlineDirection number(int k) {
    return {k == 0 ? 1 : (k == 1 ? -1 : 0), k == 2 ? 1 : (k == 3 ? -1 : 0)};
  }
  TM_HOST_DEVICE int pathCount(const VolumeGeometry& g) const { return dx != 0 ? g.height : g.width; }
  TM_HOST_DEVICE int length(const VolumeGeometry& g) const { return dx != 0 ? g.width : g.height; }
  /// The pixel of a path's first step.
  TM_HOST_DEVICE void start(const VolumeGeometry& g, int path, int& x, int& y) const {
    x = dx > 0 ? 0 : (dx < 0 ? g.width - 1 : path);
    y = dy > 0 ? 0 : (dy < 0 ? g.height - 1 : path);
  }
};

/// Whether the grey step between two pixels of one image is an edge.
TM_HOST_DEVICE inline bool greyEdge(ImageView<const uint8_t> grey, int x, int y, int px, int py, int edgeGrey) {
  const int step = grey.at(x, y) - grey.at(px, py);
  return (step < 0 ? -step : step) >= edgeGrey;
}

/// How many of the two images have an edge along the step from (px, py) to (x, y) at disparity index i (the index
/// into PathPenalties): the left image's step is given; the right image's is taken at x - d, and counts as an edge
/// where either end leaves the image.
TM_HOST_DEVICE inline int pathEdges(const ScanlineInputs& in, bool leftEdge, int x, int y, int px, int py, int i) {
  const int d = in.g.minDisparity + i, xr = x - d, pxr = px - d;
  const bool inside = xr >= 0 && xr < in.g.width && pxr >= 0 && pxr < in.g.width;
  const bool rightEdge = !inside || greyEdge(in.rightGrey, xr, y, pxr, py, in.edgeGrey);
  return (leftEdge ? 1 : 0) + (rightEdge ? 1 : 0);
}

/// Stands for L(p-r, d +- 1) beyond the disparity range: above any path cost plus P1 (costs are at most
/// 2 * kAdCensusCostUnit and the penalties at most 100 * kAdCensusCostUnit), and far from overflow.
constexpr int32_t kPathUnreachable = 1 << 29;

/// One element of the recurrence: L(p, d) from C(p, d), the previous step's L at d - 1, d, d + 1 and its minimum.
TM_HOST_DEVICE inline int32_t pathCostStep(int32_t cost, int32_t lower, int32_t same, int32_t upper,
                                           int32_t previousMin, int32_t small, int32_t large) {
  int32_t best = same;
  if (lower + small < best) best = lower + small;
  if (upper + small < best) best = upper + small;
  if (previousMin + large < best) best = previousMin + large;
  return cost + best - previousMin;
}

/// Left winners (lowest disparity on ties) with the parabola's sub-pixel offset through the neighbouring costs,
/// and right-view winners along the volume's diagonal (x = xr + d inside the image). A pixel whose costs are all
/// equal (a uniform patch: black, saturated, featureless) has no winner: kNoDisparity, dropped at the end.
struct AdCensusWinners {
  VolumeGeometry g;
  const int32_t* pathCost;
  ImageView<int16_t> leftDisparity, rightDisparity;
  ImageView<float> subpixelDisparity;

  TM_HOST_DEVICE void operator()(int64_t pixel) const {
    int x, y;
    pixelCoordinates(pixel, g.width, x, y);
    const int D = g.disparityCount;
    const int32_t* costs = pathCost + pixel * D;
    int best = 0;
    int32_t worst = costs[0];
    for (int i = 1; i < D; ++i) {
      best = costs[i] < costs[best] ? i : best;
      worst = costs[i] > worst ? costs[i] : worst;
    }
    const int d = g.minDisparity + best;
    leftDisparity[pixel] = costs[best] == worst ? kNoDisparity : static_cast<int16_t>(d);
    float value = static_cast<float>(d);
    if (best > 0 && best + 1 < D) {
      const int64_t below = costs[best - 1], centre = costs[best], above = costs[best + 1];
      const int64_t curvature = below + above - 2 * centre;
      if (curvature > 0) value -= static_cast<float>(above - below) / static_cast<float>(2 * curvature);
    }
    subpixelDisparity[pixel] = value;

    int rightBest = -1;
    int32_t rightCost = 0;
    for (int i = 0; i < D; ++i) {
      const int xl = x + g.minDisparity + i;
      if (xl < 0 || xl >= g.width) continue;
      const int32_t c = pathCost[(static_cast<int64_t>(y) * g.width + xl) * D + i];
      if (rightBest < 0 || c < rightCost) {
        rightBest = i;
        rightCost = c;
      }
    }
    rightDisparity[pixel] = rightBest < 0 ? kNoDisparity : static_cast<int16_t>(g.minDisparity + rightBest);
  }
};

/// 3x3 median of a float map (borders replicated, as OpenCV's medianBlur).
struct Median3x3 {
  ImageView<const float> input;
  ImageView<float> output;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, input.width, x, y);
    float v[9];
    int n = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) v[n++] = input.at(clampIndex(x + dx, input.width), clampIndex(y + dy, input.height));
    for (int a = 1; a < 9; ++a) {  // insertion sort: nine values
      const float key = v[a];
      int b = a - 1;
      while (b >= 0 && v[b] > key) {
        v[b + 1] = v[b];
        --b;
      }
      v[b + 1] = key;
    }
    output[index] = v[4];
  }
};

/// NaN where the discrete map has no disparity (after the left-right check).
struct DropWhereNoDiscrete {
  ImageView<const int16_t> discrete;
  ImageView<float> disparity;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    if (discrete[index] == kNoDisparity) disparity[index] = NAN;
  }
};

}  // namespace tissuemosaic::stereo
