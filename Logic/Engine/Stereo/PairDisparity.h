#pragma once
/// @file PairDisparity.h
/// @brief The left-view disparity of one rectified pair with its disparity range chosen as the parameters say
/// (automatic from the pair's feature matches, a working distance or a fixed range): what `tissuemosaic stereo` and
/// the Python module's stereo() compute.
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "Stereo/DisparityRangeFollower.h"
#include "Stereo/StereoExplanation.h"
#include "Stereo/StereoMatcher.h"
#include "Stereo/StereoParameters.h"

#include <opencv2/core.hpp>

#include <string>

namespace tissuemosaic {

struct PairDisparity {
  cv::Mat disparityPx;            ///< CV_32F, NaN = no estimate
  DisparityRangeHistory range;    ///< the range matched over (rowOffsetPx: the pair was out of rectification)
  std::string rangeDescription;   ///< DisparityRangeFollower::description()
  StereoTimingsMs timings;
  StereoExplanation explanation;  ///< filled when asked for
  RangeEndCounts rangeEnds;       ///< winners on the range's ends (rangeTooNarrowWarning)
  long long cellsScored = 0;      ///< (pixel, disparity) cells ZNCC scored (StereoMatcher::lastCellsScored; 0 unasked)
};

/// Matches a rectified pair (8-bit grey or BGR, same size). geometry: of the rectified pair (a default one when there
/// is none; a working distance then fails). Throws Error for invalid parameters or images, DisparityRangeError when the
/// automatic range finds too few feature matches.
PairDisparity computePairDisparity(const cv::Mat& leftRectified, const cv::Mat& rightRectified,
                                   const StereoParameters& parameters, const RectifiedGeometry& geometry, Device device,
                                   bool explain);

}  // namespace tissuemosaic
