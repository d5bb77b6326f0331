#pragma once
/// @file HighlightKernels.h
/// @brief Specular highlight detection, written once for both backends (TM_HOST_DEVICE). Not in the paper.
///
/// A specular highlight is the light's mirror image in the wet tissue film: it sits on a different surface point in
/// each eye, so ZNCC matches the two highlights with each other, consistently but at a false depth. Its saturated
/// core fades through a tail of bright pixels, and the matching windows over both see the twin. Bright diffuse
/// tissue is seen alike by both eyes and must keep its estimates. A pixel is a highlight seed when it is
///  1. bright: grey >= the tail level, minGrey - minContrastGrey;
///  2. part of a small saturated spot: the runs of tail-level pixels from it along its row and column (up to
///     maxRadiusPx each way) reach a core pixel >= minGrey, and the core does not reach maxRadiusPx on both sides
///     along the row or the column (a saturated area that wide is bright tissue);
///  3. brighter than its surroundings: the spot's brightest pixel exceeds the mean of 8 ring samples by
///     minContrastGrey, or by half the headroom 255 - mean on bright tissue, where no highlight can stand out more;
///     the ring lies ringGapPx beyond the runs' farthest end (outside the matching windows that see the spot);
///  4. view-dependent, at the disparity of its surroundings (the median of the ring samples' winners): its own
///     winner differs from it by more than kHighlightMatchSlackPx (ZNCC matched the spot with its twin in the other
///     eye), or the other eye there is darker by more than viewToleranceGrey within +-kHighlightMatchSlackPx (the
///     other eye does not see the spot where the tissue is). A diffuse spot matches where its surroundings match,
///     and looks as bright to both eyes.
/// A seed carries the disparity of its surroundings. ZNCC windows that see a highlight's core can match its twin
/// well beyond the seeds (a highlight's soft tail, the window's radius): every estimate within specularMarginPx of
/// a seed (the left pixel, or its match in the right eye) that differs from the seeds' surroundings by more than
/// kHighlightKeepSlackPx is removed, and hole filling gives those pixels the surrounding tissue's disparity.
/// Estimates that agree with the tissue around the highlight keep their values.
/// All tests are on integer grey levels (exact in float) and integer disparities: both backends agree bit for bit.
#include "StereoKernels.h"

namespace tissuemosaic::stereo {

/// Disparity difference (px) up to which a spot matches where its surroundings do: the ring's median is that of a
/// slanted surface's centre only to about a pixel, and bad-2 counts errors above 2 px.
constexpr int kHighlightMatchSlackPx = 2;

/// Near a highlight, an estimate within this of its surroundings' disparity (an integer median, within half a pixel
/// of the tissue's) is the tissue's and stays; any farther is refilled from the tissue around.
constexpr int kHighlightKeepSlackPx = 1;

struct HighlightRule {
  float minGrey;
  int maxRadiusPx;
  int ringGapPx;
  float minContrastGrey;
  float viewToleranceGrey;
};

/// Offset of ring sample k (the radial directions of radialDirection): axis samples at r, diagonal ones at
/// round(r / sqrt(2)), so all lie about r from the centre.
TM_HOST_DEVICE TM_FORCE_INLINE void ringOffset(int k, int r, int& dx, int& dy) {
  radialDirection(k, dx, dy);
  const int step = (dx != 0 && dy != 0) ? (r * 181 + 128) >> 8 : r;
  dx *= step;
  dy *= step;
}

/// True where pixel (x, y) of `image` is a highlight seed (the four tests above). `disparity` holds the winners of
/// image's own view, `other` is the other eye's image, and a pixel x of image matches other's x + sign * d (left
/// view: sign -1; right view: +1).
/// The run from (x, y) along (dx, dy), at most cap steps, over which the image stays >= level: its length, the
/// farthest step on it that is >= coreLevel (0: none), and the brightest value met (folded into peak).
TM_HOST_DEVICE TM_FORCE_INLINE void brightRun(ImageView<const float> image, int x, int y, int dx, int dy, float level,
                                              float coreLevel, int cap, int& length, int& farthestCore, float& peak) {
  const int steps = stepsInside(x, y, dx, dy, image.width, image.height, cap);
  length = 0;
  farthestCore = 0;
  for (int s = 1; s <= steps; ++s) {
    const float v = image.at(x + s * dx, y + s * dy);
    if (!(v >= level)) break;
    length = s;
    farthestCore = v >= coreLevel ? s : farthestCore;
    peak = fmaxf(peak, v);
  }
}

/// At a highlight seed (the four tests above), the disparity of its surroundings; elsewhere kNoDisparity.
/// `disparity` holds the winners of image's own view, `other` is the other eye's image, and a pixel x of image
/// matches other's x + sign * d (left view: sign -1; right view: +1).
TM_HOST_DEVICE TM_FORCE_INLINE int16_t highlightSurroundings(ImageView<const float> image, ImageView<const float> other,
                                                    ImageView<const int16_t> disparity, int sign, int x, int y,
                                                    const HighlightRule& rule) {
  const float grey = image.at(x, y);
  const float tail = rule.minGrey - rule.minContrastGrey;
  if (!(grey >= tail)) return kNoDisparity;
  // The bright runs through x along its row and column, up to maxRadiusPx each way: a core that reaches that far is
  // a saturated area larger than any highlight (bright tissue).
  float peak = grey;
  int tailExtent = 0, coreExtent = 0, coreReach[4];
  for (int k = 0; k < 8; k += 2) {  // E, S, W, N
    int dx, dy, length;
    radialDirection(k, dx, dy);
    brightRun(image, x, y, dx, dy, tail, rule.minGrey, rule.maxRadiusPx, length, coreReach[k / 2], peak);
    tailExtent = length > tailExtent ? length : tailExtent;
    coreExtent = coreReach[k / 2] > coreExtent ? coreReach[k / 2] : coreExtent;
  }
  // A core that reaches maxRadiusPx on both sides along the row or the column: a saturated area wider than any
  // highlight (bright tissue). One side alone is the rim of a highlight as wide as 2 maxRadiusPx.
  const int far = rule.maxRadiusPx;
  if ((coreReach[0] >= far && coreReach[2] >= far) || (coreReach[1] >= far && coreReach[3] >= far)) {
    return kNoDisparity;
  }
  if (!(peak >= rule.minGrey)) return kNoDisparity;  // no saturated core: bright tissue
  // The ring: beyond the core and its tail, which is followed at most 2 gaps past the core (on bright tissue the
  // tail level runs on), then one gap further, outside the matching windows that see the spot.
  const int beyondCore = coreExtent + 2 * rule.ringGapPx;
  const int radius = (tailExtent < beyondCore ? tailExtent : beyondCore) + rule.ringGapPx;
  float ringSum = 0.0f;
  int16_t sorted[8];
  int count = 0;
  for (int k = 0; k < 8; ++k) {
    int dx, dy;
    ringOffset(k, radius, dx, dy);
    const int xx = clampIndex(x + dx, image.width), yy = clampIndex(y + dy, image.height);
    ringSum += image.at(xx, yy);  // integers: exact in any order
    const int16_t d = disparity.at(xx, yy);
    if (d == kNoDisparity) continue;
    int i = count++;  // insertion sort: at most 8 values
    for (; i > 0 && sorted[i - 1] > d; --i) sorted[i] = sorted[i - 1];
    sorted[i] = d;
  }
  // As bright as its surroundings: tissue. Near saturation the contrast a highlight can have shrinks, so half the
  // headroom above the surroundings is enough there.
  const float surroundingGrey = ringSum * 0.125f;
  const float neededContrast = fminf(rule.minContrastGrey, 0.5f * (255.0f - surroundingGrey));
  if (!(peak - surroundingGrey >= neededContrast)) return kNoDisparity;
  // The surroundings must be one smooth surface to test against (and to refill from): at least half the ring with
  // estimates whose middle half spans no more than a slanted surface would (a depth edge mixes two).
  if (count < 4) return kNoDisparity;
  if (sorted[(3 * count) / 4] - sorted[count / 4] > kHighlightMatchSlackPx + radius / 8) return kNoDisparity;
  const int surroundings = (sorted[(count - 1) / 2] + sorted[count / 2]) >> 1;
  // (A highlight may sit so far apart in the two eyes that the other eye's twin lies outside any window here: its
  // twin is not looked for. Seen by one eye only, it still disagrees with the other eye at the tissue's match.)
  const int xo = x + sign * surroundings;
  const int own = disparity.at(x, y);
  if (own != kNoDisparity && (own - surroundings > kHighlightMatchSlackPx || surroundings - own > kHighlightMatchSlackPx)) {
    return static_cast<int16_t>(surroundings);  // matched elsewhere than the tissue around it: with its twin
  }
  float brightest = -1.0f;
  for (int k = -kHighlightMatchSlackPx; k <= kHighlightMatchSlackPx; ++k) {
    const int xx = xo + k;
    if (xx >= 0 && xx < other.width) brightest = fmaxf(brightest, other.at(xx, y));
  }
  if (brightest < 0.0f) return kNoDisparity;  // the match leaves the other image: nothing to compare with
  return grey - brightest > rule.viewToleranceGrey ? static_cast<int16_t>(surroundings) : kNoDisparity;
}

/// The seeds of both eyes, as their surroundings' disparity (kNoDisparity elsewhere): left with the left winners,
/// right with the right-view winners.
struct DetectHighlightSeeds {
  ImageView<const float> left, right;
  ImageView<const int16_t> leftDisparity, rightDisparity;
  ImageView<int16_t> leftSeeds, rightSeeds;
  HighlightRule rule;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    int x, y;
    pixelCoordinates(index, left.width, x, y);
    leftSeeds[index] = highlightSurroundings(left, right, leftDisparity, -1, x, y, rule);
    rightSeeds[index] = highlightSurroundings(right, left, rightDisparity, 1, x, y, rule);
  }
};

/// A box-sum consumer of DiscreteDisparityValue over the seeds: near[i] = the seeds' surroundings disparity within
/// the box (their rounded mean), kNoDisparity where no seed lies within it.
struct MarkNearHighlight {
  ImageView<int16_t> near;
  TM_HOST_DEVICE void operator()(int64_t index, int64_t boxSum, int count) const {
    const double mean = floor(int64ToDouble(boxSum) / (count != 0 ? count : 1) + 0.5);  // exact: integers
    near[index] = count != 0 ? static_cast<int16_t>(static_cast<int>(mean)) : kNoDisparity;
  }
};

/// A box-sum consumer of DiscreteDisparityValue over the left seeds: mask[i] = 1 where a seed lies within the box,
/// else 0. Tracking and fusion leave those pixels out: a highlight slides over the tissue as the camera moves, so a
/// feature on it, or a point fused from it, carries the wrong surface point even where its refilled depth is right.
struct MarkHighlightNeighbourhood {
  ImageView<uint8_t> mask;
  TM_HOST_DEVICE void operator()(int64_t index, int64_t, int count) const { mask[index] = count != 0 ? 1 : 0; }
};

/// True where disparity d of left pixel (x, y) lies near a highlight of either eye (the left pixel, or its match
/// x - d in the right eye) and differs from that highlight's surroundings by more than kHighlightKeepSlackPx.
TM_HOST_DEVICE TM_FORCE_INLINE bool disagreesWithHighlight(ImageView<const int16_t> leftNear,
                                                           ImageView<const int16_t> rightNear, int x, int y, int d) {
  const auto differs = [d](int16_t surroundings) {
    return surroundings != kNoDisparity &&
           (d - surroundings > kHighlightKeepSlackPx || surroundings - d > kHighlightKeepSlackPx);
  };
  if (differs(leftNear.at(x, y))) return true;
  const int xr = x - d;
  return xr >= 0 && xr < rightNear.width && differs(rightNear.at(xr, y));
}

/// Not in the paper: removes the estimates that disagree with a nearby highlight's surroundings (see the top of
/// this file).
struct DropHighlightDiscrete {
  ImageView<const int16_t> leftNear, rightNear;
  ImageView<int16_t> disparity;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int16_t d = disparity[index];
    if (d == kNoDisparity) return;
    int x, y;
    pixelCoordinates(index, disparity.width, x, y);
    if (disagreesWithHighlight(leftNear, rightNear, x, y, d)) disparity[index] = kNoDisparity;
  }
};

/// The same on a float map (AD-Census's output), at the rounded disparity.
struct DropHighlightFloat {
  ImageView<const int16_t> leftNear, rightNear;
  ImageView<float> disparity;
  TM_HOST_DEVICE void operator()(int64_t index) const {
    const float d = disparity[index];
    if (!isFinite(d)) return;
    int x, y;
    pixelCoordinates(index, disparity.width, x, y);
    if (disagreesWithHighlight(leftNear, rightNear, x, y, static_cast<int>(floorf(d + 0.5f)))) disparity[index] = NAN;
  }
};

/// The disparity that tracking and fusion take: the final disparity with NaN within the highlight neighbourhood
/// (MarkHighlightNeighbourhood), where a highlight slides over the tissue as the camera moves. Made on the device
/// that matched, so that only this map comes down instead of the mask and a host copy.
struct DisparityAwayFromHighlights {
  ImageView<const float> disparity;
  ImageView<const uint8_t> neighbourhood;
  ImageView<float> kept;
  TM_HOST_DEVICE void operator()(int64_t index) const { kept[index] = neighbourhood[index] != 0 ? NAN : disparity[index]; }
};

}  // namespace tissuemosaic::stereo
