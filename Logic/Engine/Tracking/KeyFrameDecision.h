#pragma once
/// @file KeyFrameDecision.h
/// @brief Paper III.C: which tracked frames become key frames (refinement and fusion run on those).
#include "Tracking/TrackingParameters.h"

#include <Eigen/Core>

namespace tissuemosaic {

/// The paper's pose difference ||t_a - t_b|| + 20 min(||E_a - E_b||, 2 pi - ||E_a - E_b||) of two T_world_camera
/// poses: t the camera positions (mm), E the Euler angles (Z-Y-X, radians), each angle difference wrapped to
/// (-pi, pi].
double keyFramePoseDifference(const Eigen::Matrix4d& T_world_cameraA, const Eigen::Matrix4d& T_world_cameraB);

/// A frame is a key frame when DynamicR1PPnP found at least keyFrameMinInliers inliers, and either at least
/// keyFrameMinGapFrames frames have passed since the last key frame or the pose difference to it exceeds
/// keyFramePoseThreshold.
bool isKeyFrame(int inliers, int framesSinceKeyFrame, double poseDifferenceToKeyFrame,
                const TrackingParameters& parameters);

}  // namespace tissuemosaic
