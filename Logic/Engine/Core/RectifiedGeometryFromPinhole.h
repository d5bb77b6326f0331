#pragma once
/// @file RectifiedGeometryFromPinhole.h
/// @brief The geometry of frames that are already rectified, given by their pinhole numbers instead of a
/// calibration file (`--focal-px F --baseline-mm B [--cx-px X] [--cy-px Y] [--doffs-px D]`): cx and cy default to
/// the image centre, and Q is cv::stereoRectify's reprojection matrix for them.
#include "Core/Error.h"
#include "Core/StereoRig.h"

#include <cmath>

namespace tissuemosaic {

/// Throws Error naming the option when the focal length or the baseline is not a positive finite number.
inline RectifiedGeometry rectifiedGeometryFromPinhole(const cv::Size& imageSize, double focalPx, double baselineMm,
                                                      double cxPx, double cyPx, double doffsPx) {
  require(focalPx > 0 && std::isfinite(focalPx), "--focal-px must be a positive number of pixels");
  require(baselineMm > 0 && std::isfinite(baselineMm), "--baseline-mm must be a positive number of mm");
  // A principal point far outside the frames is a typo, and would only show later as "tracking was lost".
  const auto nearImage = [](double valuePx, int extentPx) {
    return std::isnan(valuePx) || (valuePx >= -extentPx && valuePx <= 2.0 * extentPx);
  };
  require(nearImage(cxPx, imageSize.width),
          "--cx-px " + cv::format("%g", cxPx) + " lies far outside the " + std::to_string(imageSize.width) +
              "-pixel-wide frames: the principal point must lie near the image (default: its centre)");
  require(nearImage(cyPx, imageSize.height),
          "--cy-px " + cv::format("%g", cyPx) + " lies far outside the " + std::to_string(imageSize.height) +
              "-pixel-high frames: the principal point must lie near the image (default: its centre)");
  require(std::isfinite(doffsPx) && std::abs(doffsPx) <= 2.0 * imageSize.width,
          "--doffs-px " + cv::format("%g", doffsPx) + " is not a plausible difference of principal points");
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
