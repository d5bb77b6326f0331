#pragma once
/// @file ScaredKeyframe.h
/// @brief A key-frame folder of the SCARED data set (MICCAI 2019 EndoVis, da Vinci Xi) as it ships:
/// endoscope_calibration.yaml (M1 D1 M2 D2 R T: IO/Calibration), data/rgb.mp4 (the left view stacked on top of the
/// right one in each frame), and where extracted, data/frame_data/frame_data*.json or data/frame_data*.json (one per
/// video frame, its
/// "camera-pose" a 4x4 matrix in mm: the scope's pose from the robot's kinematics). docs/INPUT.md.
#include "IO/TrajectoryTum.h"

#include <string>

namespace tissuemosaic {

struct ScaredKeyframe {
  std::string calibration;  ///< endoscope_calibration.yaml
  std::string video;        ///< data/rgb.mp4, eyes top (left) and bottom (right)
  /// The per-frame poses as T_world_camera at time index / fps (empty when the folder has none); the first is the
  /// reconstruction's start pose and the whole the ground truth of `track --groundtruth`.
  Trajectory poses;
  std::string posesNote;  ///< where the poses came from, or why there are none
};

/// Reads the folder. Throws Error naming the part that is missing or unreadable (the calibration, the video, a pose
/// file without a 4x4 "camera-pose").
ScaredKeyframe readScaredKeyframe(const std::string& folder);

}  // namespace tissuemosaic
