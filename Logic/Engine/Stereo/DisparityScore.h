#pragma once
/// @file DisparityScore.h
/// @brief Accuracy of a disparity map against ground truth, as the Middlebury evaluation reports it: density over
/// the evaluated pixels, and bad-N over the pixels that carry an estimate.
#include <opencv2/core.hpp>

namespace tissuemosaic {

struct DisparityScore {
  long evaluated = 0;       ///< pixels with known ground truth inside the mask
  long estimated = 0;       ///< of those, pixels with an estimate
  double density = 0;       ///< estimated / evaluated
  double badOver1 = 1;      ///< share of estimated pixels with |error| > 1 px
  double badOver2 = 1;      ///< share of estimated pixels with |error| > 2 px
  double meanAbsError = 0;  ///< over estimated pixels, px
};

/// estimate and groundTruth: CV_32F of one size, NaN = none / unknown; mask: empty (all pixels) or CV_8U of the
/// same size (nonzero = evaluate). Throws Error on mismatched sizes or types.
DisparityScore scoreDisparity(const cv::Mat& estimate, const cv::Mat& groundTruth, const cv::Mat& mask = cv::Mat());

}  // namespace tissuemosaic
