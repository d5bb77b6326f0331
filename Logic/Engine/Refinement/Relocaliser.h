#pragma once
/// @file Relocaliser.h
/// @brief Finding the camera again after tracking was lost (not in the paper): a lost frame's ORB features are
/// matched with the key frames the refiner stored (their descriptors and world points), and R1PPnP (DynamicR1PPnP
/// with the next-best matches as candidates) solves the pose from each. Per frame it tries
/// TrackingParameters::relocalisationCandidates stored key frames: those in view from the last tracked pose first
/// (the scope is usually put back near where it was), then the others in turn, the newest first, so that over a
/// few lost frames every stored key frame is tried. The pose with the most inliers (at least
/// relocalisationMinInliers) is the answer; the caller checks it against the model (the model agreement) before
/// taking it.
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "Tracking/StereoFeatures.h"
#include "Tracking/TrackingParameters.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace tissuemosaic {

class KeyFrameRefiner;

struct RelocalisationResult {
  bool success = false;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  int inliers = 0;
  int keyFrame = -1;            ///< frame index of the stored key frame it was found against
  int keyFramesTried = 0;
  std::string message;          ///< why not (no success)
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

class Relocaliser {
public:
  /// Throws Error for invalid parameters or Device::Cuda where CUDA cannot be used.
  Relocaliser(const RectifiedGeometry& geometry, const TrackingParameters& tracking, const FeatureParameters& features,
              Device device);
  ~Relocaliser();
  Relocaliser(const Relocaliser&) = delete;
  Relocaliser& operator=(const Relocaliser&) = delete;

  /// Tries the next stored key frames of `refiner` on a lost frame's features (keypoints and descriptors; depth is
  /// not needed). T_world_lastTracked: where the camera was last seen.
  RelocalisationResult relocalise(const StereoFeatures& features, const KeyFrameRefiner& refiner,
                                  const Eigen::Matrix4d& T_world_lastTracked);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
