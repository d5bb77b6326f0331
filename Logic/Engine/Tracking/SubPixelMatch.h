#pragma once
/// @file SubPixelMatch.h
/// @brief Sub-pixel refinement of a feature match (not in the paper): ORB keypoints sit on a pixel (or pyramid
/// level) grid, good to about a pixel, and frame-to-frame pose noise accumulates as drift. A translation-only
/// inverse-compositional Lucas-Kanade moves the match so that the window around it best matches the window around the
/// reference pixel.
#include <opencv2/core.hpp>

namespace tissuemosaic {

/// Refines toPx (in grey, 8-bit) so that the (2 halfWindowPx + 1)^2 window there matches the window at fromPx in
/// referenceGrey. Returns false, leaving toPx as it was, when the window has too little texture, leaves the image,
/// does not converge, or moves farther than maxShiftPx.
bool refineMatchLucasKanade(const cv::Mat& referenceGrey, const cv::Mat& grey, const cv::Point2f& fromPx,
                            cv::Point2f& toPx, int halfWindowPx = 5, double maxShiftPx = 2.0);

}  // namespace tissuemosaic
