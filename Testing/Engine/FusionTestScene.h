#pragma once
// Analytic scenes for the fusion tests (TestFusion.cpp, TestFusionCuda.cpp): a small rectified camera and planar
// patches seen from any pose, rendered as left-view disparity maps with optional depth noise, so that the truth of
// every point is known exactly.
#include "Core/StereoRig.h"
#include "Core/SurfaceMeasurement.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cmath>
#include <limits>

namespace tissuemosaic::test {

/// A rectified pair of size width x height: focal length, centred principal point, 5 mm baseline, doffs.
inline RectifiedGeometry fusionGeometry(int width = 320, int height = 240, double focalPx = 300, double doffsPx = 0) {
  RectifiedGeometry g;
  g.imageSize = {width, height};
  g.focalPx = focalPx;
  g.cxLeftPx = 0.5 * (width - 1);
  g.cyPx = 0.5 * (height - 1);
  g.doffsPx = doffsPx;
  g.baselineMm = 5.0;
  // cv::stereoRectify's Q: [x y d 1] -> [x - cx, y - cy, f, (d + doffs) / B].
  g.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -g.cxLeftPx, 0, 1, 0, -g.cyPx, 0, 0, 0, focalPx, 0, 0, 1.0 / g.baselineMm,
         doffsPx / g.baselineMm);
  return g;
}

/// Camera -> world from a position and a rotation (axis * angle in degrees).
inline Eigen::Matrix4d cameraPose(const Eigen::Vector3d& positionMm, const Eigen::Vector3d& axis = Eigen::Vector3d::UnitX(),
                                  double degrees = 0) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  T.block<3, 1>(0, 3) = positionMm;
  return T;
}

/// The plane normal . X = offsetMm (world, mm), limited to |X| <= halfXMm, |Y| <= halfYMm (0: unlimited).
struct PlanePatch {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offsetMm = 100;
  double halfXMm = 0, halfYMm = 0;

  double distanceMm(const Eigen::Vector3d& pointWorldMm) const { return normal.normalized().dot(pointWorldMm) - offsetMm; }
  /// Depth along the camera's optical axis of the patch at pixel (x, y), NaN where the ray misses it.
  double depthMm(const RectifiedGeometry& g, const Eigen::Matrix4d& T_world_camera, int x, int y) const {
    const Eigen::Vector3d n = normal.normalized();
    const Eigen::Vector3d ray = T_world_camera.block<3, 3>(0, 0) *
                                Eigen::Vector3d((x - g.cxLeftPx) / g.focalPx, (y - g.cyPx) / g.focalPx, 1.0);
    const Eigen::Vector3d origin = T_world_camera.block<3, 1>(0, 3);
    const double along = n.dot(ray);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (std::abs(along) < 1e-9) return nan;
    const double depth = (offsetMm - n.dot(origin)) / along;  // ray has unit z in the camera: t is the depth
    if (!(depth > 0)) return nan;
    const Eigen::Vector3d hit = origin + depth * ray;
    if ((halfXMm > 0 && std::abs(hit.x()) > halfXMm) || (halfYMm > 0 && std::abs(hit.y()) > halfYMm)) return nan;
    return depth;
  }
};

/// Left-view disparity of the patch seen from T_world_camera, depth perturbed by N(0, depthNoiseMm) per pixel.
inline cv::Mat patchDisparity(const RectifiedGeometry& g, const PlanePatch& patch, const Eigen::Matrix4d& T_world_camera,
                              double depthNoiseMm = 0, cv::RNG* rng = nullptr) {
  cv::Mat disparity(g.imageSize, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  for (int y = 0; y < g.imageSize.height; ++y)
    for (int x = 0; x < g.imageSize.width; ++x) {
      double depth = patch.depthMm(g, T_world_camera, x, y);
      if (!std::isfinite(depth)) continue;
      if (depthNoiseMm > 0) depth += rng->gaussian(depthNoiseMm);
      disparity.at<float>(y, x) = static_cast<float>(g.focalPx * g.baselineMm / depth - g.doffsPx);
    }
  return disparity;
}

/// A uniform BGR image of the geometry's size.
inline cv::Mat uniformImage(const RectifiedGeometry& g, const cv::Scalar& bgr = cv::Scalar(90, 120, 200)) {
  return cv::Mat(g.imageSize, CV_8UC3, bgr);
}

/// measureSurface of the patch on the CPU (default normal radius and depth-jump threshold).
inline SurfaceMeasurement patchMeasurement(const RectifiedGeometry& g, const PlanePatch& patch,
                                           const Eigen::Matrix4d& T_world_camera, double depthNoiseMm = 0,
                                           cv::RNG* rng = nullptr, const cv::Scalar& bgr = cv::Scalar(90, 120, 200),
                                           Device device = Device::Cpu) {
  return measureSurface(patchDisparity(g, patch, T_world_camera, depthNoiseMm, rng), uniformImage(g, bgr), g, device);
}

}  // namespace tissuemosaic::test
