#pragma once
/// @file RectifiedGeometryFromPinhole.h
/// @brief The geometry of frames that are already rectified, given by their pinhole numbers instead of a
/// calibration file (`--focal-px F --baseline-mm B [--cx-px X] [--cy-px Y] [--doffs-px D]`): cx and cy default to
/// the image centre, and Q is cv::stereoRectify's reprojection matrix for them.
#include "Core/ParameterError.h"
#include "Core/StereoRig.h"

#include <cmath>

namespace tissuemosaic {

/// Throws ParameterError naming the value (focalPx, baselineMm, cxPx, cyPx, doffsPx) when the focal length or the
/// baseline is not a positive finite number, or the principal point or doffs is implausible for the image.
inline RectifiedGeometry rectifiedGeometryFromPinhole(const cv::Size& imageSize, double focalPx, double baselineMm,
                                                      double cxPx, double cyPx, double doffsPx) {
  requireParameter(focalPx > 0 && std::isfinite(focalPx), "focalPx",
                   "the focal length must be a positive number of pixels, not " + cv::format("%g", focalPx));
  requireParameter(baselineMm > 0 && std::isfinite(baselineMm), "baselineMm",
                   "the baseline must be a positive number of mm, not " + cv::format("%g", baselineMm));
  // A principal point far outside the frames is a typo, and would only show later as "tracking was lost".
  const auto nearImage = [](double valuePx, int extentPx) {
    return std::isnan(valuePx) || (valuePx >= -extentPx && valuePx <= 2.0 * extentPx);
  };
  requireParameter(nearImage(cxPx, imageSize.width), "cxPx",
                   "the principal point's x " + cv::format("%g", cxPx) + " px lies far outside the " +
                       std::to_string(imageSize.width) +
                       "-pixel-wide frames: the principal point must lie near the image (default: its centre)");
  requireParameter(nearImage(cyPx, imageSize.height), "cyPx",
                   "the principal point's y " + cv::format("%g", cyPx) + " px lies far outside the " +
                       std::to_string(imageSize.height) +
                       "-pixel-high frames: the principal point must lie near the image (default: its centre)");
  requireParameter(std::isfinite(doffsPx) && std::abs(doffsPx) <= 2.0 * imageSize.width, "doffsPx",
                   "doffs " + cv::format("%g", doffsPx) + " px is not a plausible difference of principal points");
  RectifiedGeometry geometry;
  geometry.imageSize = imageSize;
  geometry.focalPx = focalPx;
  geometry.baselineMm = baselineMm;
  geometry.cxLeftPx = std::isfinite(cxPx) ? cxPx : (imageSize.width - 1) / 2.0;
  geometry.cyPx = std::isfinite(cyPx) ? cyPx : (imageSize.height - 1) / 2.0;
  geometry.doffsPx = doffsPx;
  geometry.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -geometry.cxLeftPx, 0, 1, 0, -geometry.cyPx, 0, 0, 0,
                geometry.focalPx, 0, 0, 1.0 / geometry.baselineMm, geometry.doffsPx / geometry.baselineMm);
  return geometry;
}

}  // namespace tissuemosaic
