#pragma once
/// @file CalibrationLayout.h
/// @brief One calibration file layout as the field ships it: the keys that identify it and a reader. Each layout
/// lives in its own file (OpenCvStereoCalibrateLayout.cpp, StereoCalibSampleLayout.cpp, RosCameraInfoLayout.cpp,
/// KalibrLayout.cpp, MatlabStereoParametersLayout.cpp); CalibrationFile.cpp tries them in order.
#include "Core/StereoRig.h"
#include "IO/Calibration/CalibrationDocument.h"

#include <functional>
#include <optional>
#include <string>

namespace tissuemosaic {

/// What the user gave: the main file (with an extrinsics file merged into it) and, for layouts with one file per
/// eye, the right eye's.
struct CalibrationInput {
  CalibrationDocument main;
  std::optional<CalibrationDocument> right;
};

struct CalibrationLayout {
  std::string name;  ///< e.g. "OpenCV stereoCalibrate"
  std::string keys;  ///< what identifies it and what it needs, for the error that lists the layouts understood
  std::function<bool(const CalibrationInput&)> matches;
  /// Reads the calibration; imageSize stays empty when the file has none (the frames give it). Throws Error
  /// naming the missing or malformed key.
  std::function<StereoCalibration(const CalibrationInput&)> read;
};

CalibrationLayout openCvStereoCalibrateLayout();
CalibrationLayout stereoCalibSampleLayout();
CalibrationLayout rosCameraInfoLayout();
CalibrationLayout kalibrLayout();
CalibrationLayout matlabStereoParametersLayout();
CalibrationLayout stereoMisIniLayout();

/// Shared by the readers: D as a 1xN row (column vectors accepted), T as 3x1, an optional image size from
/// "imageSize" ([width, height]) or "image_width" + "image_height" (empty Size when neither is there).
cv::Mat distortionRow(const cv::Mat& D);
cv::Mat translationColumn(const cv::Mat& T, const std::string& key);
cv::Size optionalImageSize(const YAML::Node& node);
/// One side of an image size in pixels from a file: a positive whole number of at most 100 000 (an Error naming
/// `key` otherwise; a value beyond int's range must not reach a cast: fuzz_calibration).
int imageSidePx(double value, const std::string& key);

}  // namespace tissuemosaic
