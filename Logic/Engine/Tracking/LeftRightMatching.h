#pragma once
/// @file LeftRightMatching.h
/// @brief Sparse stereo: ORB features of the left and right rectified views matched along image rows. Rectified
/// views put a point on the same row in both, so each left feature is compared only with the right features of its
/// row band, and a pair is kept when each is the other's nearest descriptor (Hamming) and the nearest is clearly
/// nearer than the next (ratio test). Its disparities do not depend on a disparity range, which is why the automatic
/// range is measured from them (Stereo/DisparityRangeEstimator.h).
#include "Tracking/OrbFeatures.h"

#include <vector>

namespace tissuemosaic {

struct LeftRightMatchOptions {
  double rowTolerancePx = 1.5;  ///< a right feature more rows away than this (from rowOffsetPx) is not a candidate
  /// Where the band lies: a left feature's partner is sought about row left y + rowOffsetPx. 0 for a rectified pair;
  /// the automatic range measures a pair whose rows disagree (DisparityRangeEstimator) with its measured offset.
  double rowOffsetPx = 0;
  /// Candidates only with disparity (left x - right x) in [minDisparityPx, maxDisparityPx]: what a rectified rig can
  /// show at all (the caller sets it from the image width).
  double minDisparityPx = -1000, maxDisparityPx = 1000;
  int maxHammingDistance = 50;  ///< of 256 bits
  double maxRatio = 0.85;       ///< nearest distance < maxRatio x second nearest in the band (when there is one)
};

struct LeftRightMatch {
  int left = 0, right = 0;  ///< keypoint indices
  float disparityPx = 0;    ///< left x - right x
  float rowOffsetPx = 0;    ///< right y - left y
  int distance = 0;         ///< Hamming, bits
};

/// Mutual nearest matches of left to right features within their row bands, passing the distance and ratio tests,
/// in left keypoint order.
std::vector<LeftRightMatch> matchLeftRight(const OrbFeatures& left, const OrbFeatures& right,
                                           const LeftRightMatchOptions& options = {});

struct MatchConsistencyOptions {
  double neighbourhoodPx = 64;  ///< neighbours: the other matches within about this distance (cells of this size, 3x3)
  int minNeighbours = 3;        ///< a match with fewer cannot be checked and is dropped
  double minTolerancePx = 4;    ///< kept within max(this, spreadFactor x the neighbours' MAD) of their median
  double spreadFactor = 3;
};

/// The matches whose disparity agrees with their neighbours' (tissue is a surface: neighbouring features have nearby
/// disparities, while a wrong match along the row lands anywhere). A few percent of row matches are wrong, in every
/// frame, with any disparity the row allows: enough to move a robust end of the disparities by tens of pixels.
std::vector<LeftRightMatch> consistentMatches(const std::vector<LeftRightMatch>& matches, const OrbFeatures& left,
                                              const MatchConsistencyOptions& options = {});

}  // namespace tissuemosaic
