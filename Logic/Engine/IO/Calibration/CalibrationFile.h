#pragma once
/// @file CalibrationFile.h
/// @brief Stereo calibration files as the field ships them, recognised by their keys (docs/CALIBRATION.md):
/// OpenCV stereoCalibrate names, OpenCV's stereo_calib sample / SCARED / SurgT, ROS camera_info per eye, Kalibr
/// camchain.yaml, MATLAB stereoParameters. Files without an image size leave StereoCalibration::imageSize empty:
/// the frames give it (StereoCalibration::adoptFrameSize).
#include "Core/StereoRig.h"

#include <string>
#include <vector>

namespace tissuemosaic {

/// The files of one calibration: `calib` always; `extrinsics` for the stereo_calib sample's intrinsics.yml +
/// extrinsics.yml pair; `right` for layouts with one file per eye (ROS camera_info: `calib` is the left eye).
struct CalibrationFiles {
  std::string calib;
  std::string extrinsics;
  std::string right;
};

struct CalibrationFileContent {
  StereoCalibration calibration;
  std::string layout;  ///< the layout's name, e.g. "OpenCV stereo_calib sample / SCARED / SurgT"
};

/// Reads and validates the calibration. Throws Error "cannot read stereo calibration 'PATH': ..." naming the missing
/// or malformed key; when no layout matches, the message lists every layout understood with its keys.
CalibrationFileContent readCalibrationFiles(const CalibrationFiles& files);

/// The same from a list of files in any order (the app's multiple selection): one file, or two whose roles are
/// told by their content (an extrinsics file holds R and T but no camera matrix; of two ROS camera_info files the
/// left eye's projection has Tx = 0).
CalibrationFileContent readCalibrationFiles(const std::vector<std::string>& paths);

/// One file in any layout readCalibrationFiles understands (the layouts of two files need it). Throws as it does.
StereoCalibration readStereoCalibration(const std::string& path);

/// Writes cv::stereoCalibrate's keys K1 D1 K2 D2 R T and imageSize as [width, height]. Throws Error for a
/// calibration with its own rectification (that layout cannot hold it), without an image size, or that fails
/// StereoCalibration::validate.
void writeStereoCalibration(const StereoCalibration& calibration, const std::string& path);

/// "  NAME: KEYS" lines, one per layout understood.
std::string calibrationLayoutsText();

}  // namespace tissuemosaic
