#pragma once
/// @file GuidedSearchKernels.h
/// @brief The guided ZNCC search (StereoSearch::Guided), per pixel for both backends: a half-resolution pair, each
/// full-resolution pixel's window of candidates from the half-resolution disparities, and the ZNCC of a window's cells
/// summed directly. The sums are the exhaustive volume's exact integers, so a scored cell holds the very score the
/// exhaustive search gives it, on either backend.
#include "StereoKernels.h"

namespace tissuemosaic::stereo {

/// Candidates added on either side of the doubled half-resolution disparities around a pixel: one half-resolution
/// disparity step is 2 px here, and the half-resolution winner may be one step off.
constexpr int kGuidedWindowMarginPx = 4;

/// Half-resolution 8-bit grey of both images: the rounded mean of each 2x2 block (integer grey levels keep the
/// window sums exact); an odd last row or column repeats itself.
struct HalveGrey {
  ImageView<const uint8_t> left, right;
  ImageView<uint8_t> halfLeft, halfRight;

  TM_HOST_DEVICE static uint8_t mean(ImageView<const uint8_t> image, int x0, int y0) {
    const int x1 = x0 + 1 < image.width ? x0 + 1 : x0, y1 = y0 + 1 < image.height ? y0 + 1 : y0;
    const int sum = image.at(x0, y0) + image.at(x1, y0) + image.at(x0, y1) + image.at(x1, y1);
    return static_cast<uint8_t>((sum + 2) / 4);
  }
  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, halfLeft.width, x, y);
    halfLeft[index] = mean(left, 2 * x, 2 * y);
    halfRight[index] = mean(right, 2 * x, 2 * y);
  }
};

/// Each pixel's candidate window low..high (disparities, inclusive): the doubled half-resolution disparities of the
/// 3x3 half-resolution pixels around it, widened by marginPx and cut to the range. Where none of them has an
/// estimate, or they lie outside the range, the prior is missing: the whole range.
struct CandidateWindows {
  ImageView<const int16_t> coarse;  ///< half-resolution disparities after outlier removal and filling
  ImageView<int16_t> low, high;
  int minDisparity, maxDisparity, marginPx;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, low.width, x, y);
    const int cx = x / 2, cy = y / 2;
    int lowest = 32767, highest = -32768;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int16_t c = coarse.at(clampIndex(cx + dx, coarse.width), clampIndex(cy + dy, coarse.height));
        if (c == kNoDisparity) continue;
        lowest = c < lowest ? c : lowest;
        highest = c > highest ? c : highest;
      }
    }
    int first = 2 * lowest - marginPx, last = 2 * highest + marginPx;
    first = first > minDisparity ? first : minDisparity;
    last = last < maxDisparity ? last : maxDisparity;
    const bool missing = lowest > highest || first > last;
    low[index] = static_cast<int16_t>(missing ? minDisparity : first);
    high[index] = static_cast<int16_t>(missing ? maxDisparity : last);
  }
};

/// The quantised ZNCC of left pixel (x, y) at disparity d, its window's product sum taken directly: the same
/// chessboard pixels and replicated borders as the exhaustive launchers, and exact integer sums, so the same score.
TM_HOST_DEVICE TM_FORCE_INLINE int16_t directZncc(const ImageView<const float>& left, const ImageView<const float>& right,
                                                  const ImageView<const float>& sumLeft,
                                                  const ImageView<const float>& inverseNormLeft,
                                                  const ImageView<const float>& sumRight,
                                                  const ImageView<const float>& inverseNormRight, int r, int x, int y,
                                                  int d) {
  const int xr = x - d, width = left.width;
  if (xr < 0 || xr >= width) return kNoZncc;
  float sum = 0.0f;
  // Every term is an integer and so is every partial sum (below 2^24): the order and the border's path change nothing.
  const bool inside = x - r >= 0 && x + r < width && xr - r >= 0 && xr + r < width && y - r >= 0 && y + r < left.height;
  if (inside) {
    for (int dy = -r; dy <= r; ++dy) {
      const float* leftRow = left.data + static_cast<int64_t>(y + dy) * width + x;
      const float* rightRow = right.data + static_cast<int64_t>(y + dy) * width + xr;
      for (int dx = -r + ((r + dy) & 1); dx <= r; dx += 2) sum += leftRow[dx] * rightRow[dx];
    }
  } else {
    for (int dy = -r; dy <= r; ++dy) {
      const int row = clampIndex(y + dy, left.height);
      for (int dx = -r + ((r + dy) & 1); dx <= r; dx += 2) {  // dx + dy even: the chessboard holding the centre
        sum += left.at(clampIndex(x + dx, width), row) * right.at(clampIndex(x + dx - d, width), row);
      }
    }
  }
  return quantisedZncc(sum, sumLeft.at(x, y), sumRight.at(xr, y), inverseNormLeft.at(x, y), inverseNormRight.at(xr, y),
                       chessboardPixelCount(r));
}

/// One pixel's slice of the volume and its left winner (strictly best, the lowest disparity on ties, as the
/// exhaustive launchers): the cells of its window scored, every other cell kNoZncc (never a winner, skipped by the
/// re-selection). The window pass marks pixels whose prior failed: the winner on an edge of a window narrower than
/// the range (the peak may lie beyond it), or no winner in such a window under a textured left window. The fallback
/// pass scores the whole range at the marked pixels only.
struct ScoreGuidedCells {
  ImageView<const float> left, right, sumLeft, inverseNormLeft, sumRight, inverseNormRight;
  int radius, minDisparity, disparityCount;
  int16_t* volume;
  VolumeLayout layout;
  ImageView<const int16_t> low, high;
  ImageView<int16_t> bestDisparity;
  ImageView<uint8_t> fellBack;
  bool fallbackPass;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    if (fallbackPass && fellBack[index] == 0) return;
    int x, y;
    pixelCoordinates(index, left.width, x, y);
    const int first = fallbackPass ? 0 : low[index] - minDisparity;
    const int last = fallbackPass ? disparityCount - 1 : high[index] - minDisparity;
    int16_t best = kNoZncc;
    int bestIndex = -1;
    for (int i = 0; i < disparityCount; ++i) {
      const int16_t q = i >= first && i <= last
                            ? directZncc(left, right, sumLeft, inverseNormLeft, sumRight, inverseNormRight, radius, x,
                                         y, minDisparity + i)
                            : kNoZncc;
      volume[layout.index(x, y, i)] = q;
      if (q > best) {
        best = q;
        bestIndex = i;
      }
    }
    bestDisparity[index] = bestIndex < 0 ? kNoDisparity : static_cast<int16_t>(minDisparity + bestIndex);
    if (fallbackPass) return;
    const bool narrower = first > 0 || last < disparityCount - 1;
    const bool onEdge = bestIndex >= 0 && ((bestIndex == first && first > 0) || (bestIndex == last && last < disparityCount - 1));
    const bool none = bestIndex < 0 && inverseNormLeft[index] != 0.0f;
    fellBack[index] = narrower && (onEdge || none) ? 1 : 0;
  }
};

/// The right-view winners from a volume (the exhaustive launchers' rule: strictly best over ascending disparities):
/// right pixel xr's candidates are the left pixels xr + d.
struct RightWinnersFromVolume {
  const int16_t* volume;
  VolumeLayout layout;
  int minDisparity, disparityCount;
  ImageView<int16_t> rightBestDisparity;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int xr, y;
    pixelCoordinates(index, rightBestDisparity.width, xr, y);
    int16_t best = kNoZncc;
    int bestIndex = -1;
    for (int i = 0; i < disparityCount; ++i) {
      const int x = xr + minDisparity + i;
      if (x < 0 || x >= rightBestDisparity.width) continue;
      const int16_t q = volume[layout.index(x, y, i)];
      if (q > best) {
        best = q;
        bestIndex = i;
      }
    }
    rightBestDisparity[index] = bestIndex < 0 ? kNoDisparity : static_cast<int16_t>(minDisparity + bestIndex);
  }
};

/// Per image row: pixels with a left winner, and of those the winners on the range's first and on its last candidate
/// (3 counts per row). Many winners on an end candidate say that the scene's disparities reach beyond the range: the
/// cost was still improving there (StereoMatcher::lastRangeEndCounts).
struct CountRangeEndWinners {
  ImageView<const int16_t> winners;
  int minDisparity, maxDisparity;
  int32_t* rowCounts;

  TM_HOST_DEVICE void operator()(int64_t row) const {
    const int y = static_cast<int>(row);
    int32_t withWinner = 0, atMin = 0, atMax = 0;
    for (int x = 0; x < winners.width; ++x) {
      const int16_t d = winners.at(x, y);
      withWinner += d != kNoDisparity;
      atMin += d == minDisparity;
      atMax += d == maxDisparity;
    }
    rowCounts[3 * row] = withWinner;
    rowCounts[3 * row + 1] = atMin;
    rowCounts[3 * row + 2] = atMax;
  }
};

}  // namespace tissuemosaic::stereo
