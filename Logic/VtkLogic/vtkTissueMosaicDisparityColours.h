#pragma once
/// @file vtkTissueMosaicDisparityColours.h
/// @brief The false-colour picture of a disparity map, and its legend: by disparity (turbo colour map from the
/// map's smallest to its largest disparity, so that the scene's own range is spread over the colours) or by depth
/// in millimetres (the same colours, red near, blue far). Black: no estimate. One source for the application's
/// video panel and vtkTissueMosaicReconstructionLogic::GetDisparityColorImage.
#include <opencv2/core.hpp>

namespace tissuemosaic {

struct RectifiedGeometry;

struct DisparityColouring {
  cv::Mat bgr;             ///< CV_8UC3, the map's size
  double lowPx = 0;        ///< disparity shown in the bottom colour (blue: far)
  double highPx = 0;       ///< disparity shown in the top colour (red: near)
  bool valid = false;      ///< some pixel has an estimate
};

/// Colours `disparityPx` (CV_32F, NaN = none) into `colouring.bgr` (reusing its buffer when the size is the same);
/// the range is the map's own, or [fallbackLowPx, fallbackHighPx] when it has no estimate.
void colourDisparity(const cv::Mat& disparityPx, double fallbackLowPx, double fallbackHighPx,
                     DisparityColouring& colouring);

/// The colour of a disparity in a colouring (the legend's colours), as BGR.
cv::Vec3b disparityColour(const DisparityColouring& colouring, double disparityPx);

/// Depth in mm of a disparity under `geometry` (focal length, baseline, disparity offset); infinity for a disparity
/// at or below -doffs.
double depthOfDisparityMm(const RectifiedGeometry& geometry, double disparityPx);

}  // namespace tissuemosaic
