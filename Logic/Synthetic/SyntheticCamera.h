#pragma once
/// @file SyntheticCamera.h
/// @brief A pinhole camera with OpenCV's 5-coefficient lens distortion (k1 k2 p1 p2 k3) placed in the synthetic
/// world: pixel rays for rendering and projection of world points. Camera frame: x right, y down, z forward.
#include <opencv2/core.hpp>

namespace tissuemosaic::synthetic {

struct SyntheticCamera {
  cv::Matx33d K = cv::Matx33d::eye();
  cv::Vec<double, 5> distortion{0, 0, 0, 0, 0};  ///< k1 k2 p1 p2 k3; all zero for the rectified cameras
  cv::Matx33d R_world_camera = cv::Matx33d::eye();  ///< rotates camera-frame vectors into the world frame
  cv::Vec3d centreWorldMm{0, 0, 0};
  cv::Size imageSize;

  /// Distorts normalised image coordinates (x/z, y/z) as cv::projectPoints does.
  cv::Vec2d distort(const cv::Vec2d& undistorted) const;
  /// Inverse of distort (fixed-point iteration to 1e-12: the distortions used here are small).
  cv::Vec2d undistort(const cv::Vec2d& distorted) const;
  /// World direction (not unit, camera-frame z = 1) of the ray through pixel (u, v); pixel centres are integers.
  cv::Vec3d rayWorld(double u, double v) const;
  /// rayWorld(u, v) and its derivatives along u and v: sub-pixel rays to first order (exact without distortion,
  /// off by ~1e-5 px at a quarter pixel with the distortions used here), at a fraction of the cost.
  cv::Vec3d rayWorld(double u, double v, cv::Vec3d& dRayDu, cv::Vec3d& dRayDv) const;
  /// Pixel of a world point and its depth (camera-frame z in mm; <= 0: behind the camera).
  cv::Vec2d project(const cv::Vec3d& pointWorldMm, double* depthMm = nullptr) const;
  bool hasDistortion() const { return cv::norm(distortion) > 0; }
};

}  // namespace tissuemosaic::synthetic
