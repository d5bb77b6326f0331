#include "IO/StereoGeometry.h"

#include "Core/RectifiedGeometryFromPinhole.h"

#include <limits>

namespace tissuemosaic {

StereoGeometry resolveStereoGeometry(const StereoGeometrySpec& spec, const cv::Size& frameSize,
                                     const std::string& framesDescription) {
  StereoGeometry geometry;
  if (spec.calibration) {
    StereoCalibration calibration = spec.calibration->calibration;
    geometry.calibrationLayout = spec.calibration->layout;
    geometry.imageSizeFromFrames = calibration.imageSize.empty();
    calibration.adoptFrameSize(frameSize, framesDescription);
    auto rectifier = std::make_shared<const StereoRectifier>(calibration);
    geometry.rectified = rectifier->geometry();
    geometry.calibration = calibration;
    if (!spec.framesRectified) geometry.rectifier = rectifier;
    return geometry;
  }
  const double unset = std::numeric_limits<double>::quiet_NaN();  // the image centre
  geometry.rectified = rectifiedGeometryFromPinhole(frameSize, spec.focalPx, spec.baselineMm, spec.cxPx.value_or(unset),
                                                    spec.cyPx.value_or(unset), spec.doffsPx);
  return geometry;
}

}  // namespace tissuemosaic
