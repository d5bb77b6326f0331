#pragma once
/// @file StereoGeometry.h
/// @brief What a rig's description means for frames of one size: a calibration (the frames are rectified from it,
/// or already are) or the rectified pinhole values. The command line's geometry options and the Python module's
/// Rig both resolve through here, so that they accept and refuse the same things with the same messages.
#include "Core/StereoRig.h"
#include "IO/Calibration/CalibrationFile.h"

#include <memory>
#include <optional>
#include <string>

namespace tissuemosaic {

/// A rig as given, before the frames' size is known.
struct StereoGeometrySpec {
  std::optional<CalibrationFileContent> calibration;  ///< read by readCalibrationFiles; else the pinhole values
  bool framesRectified = false;  ///< with a calibration: the frames are already rectified as StereoRectifier makes them
  double focalPx = 0, baselineMm = 0;
  std::optional<double> cxPx, cyPx;  ///< the image centre when unset
  double doffsPx = 0;
};

/// What the spec means for frames of one size.
struct StereoGeometry {
  RectifiedGeometry rectified;                       ///< of the rectified frames the engine works on
  std::optional<StereoCalibration> calibration;      ///< the rig, when a calibration was given
  std::shared_ptr<const StereoRectifier> rectifier;  ///< set when the frames must be rectified first
  std::string calibrationLayout;                     ///< the calibration file's layout, e.g. "Kalibr camchain.yaml"
  bool imageSizeFromFrames = false;                  ///< the calibration file gave no image size
};

/// Checks that a calibration is for frames of `frameSize` (Error naming `framesDescription` otherwise; a calibration
/// without image size takes `frameSize`) or that the pinhole values are plausible for it (Error naming the option).
StereoGeometry resolveStereoGeometry(const StereoGeometrySpec& spec, const cv::Size& frameSize,
                                     const std::string& framesDescription);

}  // namespace tissuemosaic
