#pragma once
/// @file StereoMisSequence.h
/// @brief A StereoMIS sequence (Hayoz et al. 2023, da Vinci Xi): a side-by-side stereo video (left half the left
/// view) with StereoCalibration.ini beside it (IO/Calibration/StereoMisIniLayout.cpp). Given a folder, its one video
/// (.mp4, .avi, .mkv, .mov) and its StereoCalibration.ini; given a video, the StereoCalibration.ini beside it.
/// docs/INPUT.md.
#include <string>

namespace tissuemosaic {

struct StereoMisSequence {
  std::string video;        ///< side by side, full-width halves
  std::string calibration;  ///< StereoCalibration.ini
};

/// Finds the parts. Throws Error naming what is missing (no video, several, no calibration).
StereoMisSequence findStereoMisSequence(const std::string& folderOrVideo);

}  // namespace tissuemosaic
