#include "Tracking/KeyFrameDecision.h"

#include <algorithm>
#include <cmath>

namespace tissuemosaic {

namespace {

/// Z-Y-X (yaw, pitch, roll) Euler angles in radians: yaw and roll in (-pi, pi], pitch in [-pi/2, pi/2].
Eigen::Vector3d eulerZyx(const Eigen::Matrix3d& R) {
  return {std::atan2(R(1, 0), R(0, 0)), std::asin(std::clamp(-R(2, 0), -1.0, 1.0)), std::atan2(R(2, 1), R(2, 2))};
}

}  // namespace

double keyFramePoseDifference(const Eigen::Matrix4d& T_world_cameraA, const Eigen::Matrix4d& T_world_cameraB) {
  Eigen::Vector3d dE = eulerZyx(T_world_cameraA.block<3, 3>(0, 0)) - eulerZyx(T_world_cameraB.block<3, 3>(0, 0));
  for (int k = 0; k < 3; ++k) dE[k] = std::remainder(dE[k], 2 * M_PI);
  const double e = dE.norm();
  const double dt = (T_world_cameraA.block<3, 1>(0, 3) - T_world_cameraB.block<3, 1>(0, 3)).norm();
  return dt + 20.0 * std::min(e, 2 * M_PI - e);
}

bool isKeyFrame(int inliers, int framesSinceKeyFrame, double poseDifferenceToKeyFrame,
                const TrackingParameters& parameters) {
  if (inliers < parameters.keyFrameMinInliers) return false;
  return framesSinceKeyFrame >= parameters.keyFrameMinGapFrames ||
         poseDifferenceToKeyFrame > parameters.keyFramePoseThreshold;
}

}  // namespace tissuemosaic
