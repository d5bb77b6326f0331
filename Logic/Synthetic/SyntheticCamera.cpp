#include "SyntheticCamera.h"

#include <cmath>

namespace tissuemosaic::synthetic {

cv::Vec2d SyntheticCamera::distort(const cv::Vec2d& p) const {
  const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3], k3 = distortion[4];
  const double x = p[0], y = p[1], r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

cv::Vec2d SyntheticCamera::undistort(const cv::Vec2d& distorted) const {
  if (!hasDistortion()) return distorted;
  cv::Vec2d p = distorted;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const cv::Vec2d error = distort(p) - distorted;
    p -= error;
    if (error.dot(error) < 1e-22) break;  // 1e-11 in normalised units: 1e-8 px
  }
  return p;
}

cv::Vec3d SyntheticCamera::rayWorld(double u, double v) const {
  const cv::Vec2d distorted((u - K(0, 2) - K(0, 1) * (v - K(1, 2)) / K(1, 1)) / K(0, 0), (v - K(1, 2)) / K(1, 1));
  const cv::Vec2d p = undistort(distorted);
  return R_world_camera * cv::Vec3d(p[0], p[1], 1.0);
}

cv::Vec3d SyntheticCamera::rayWorld(double u, double v, cv::Vec3d& dRayDu, cv::Vec3d& dRayDv) const {
  const double fx = K(0, 0), fy = K(1, 1), skew = K(0, 1);
  const cv::Vec2d distorted((u - K(0, 2) - skew * (v - K(1, 2)) / fy) / fx, (v - K(1, 2)) / fy);
  const cv::Vec2d p = undistort(distorted);
  // Jacobian of distort at p, inverted: d(undistorted) / d(distorted).
  const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3], k3 = distortion[4];
  const double x = p[0], y = p[1], r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double dRadial = k1 + r2 * (2.0 * k2 + 3.0 * k3 * r2);  // d radial / d r2
  const cv::Matx22d J(radial + 2.0 * x * x * dRadial + 2.0 * p1 * y + 6.0 * p2 * x,
                      2.0 * x * y * dRadial + 2.0 * p1 * x + 2.0 * p2 * y,
                      2.0 * x * y * dRadial + 2.0 * p1 * x + 2.0 * p2 * y,
                      radial + 2.0 * y * y * dRadial + 6.0 * p1 * y + 2.0 * p2 * x);
  const cv::Matx22d inverse = J.inv();
  const cv::Vec2d du = inverse * cv::Vec2d(1.0 / fx, 0.0);
  const cv::Vec2d dv = inverse * cv::Vec2d(-skew / (fx * fy), 1.0 / fy);
  dRayDu = R_world_camera * cv::Vec3d(du[0], du[1], 0.0);
  dRayDv = R_world_camera * cv::Vec3d(dv[0], dv[1], 0.0);
  return R_world_camera * cv::Vec3d(p[0], p[1], 1.0);
}

cv::Vec2d SyntheticCamera::project(const cv::Vec3d& pointWorldMm, double* depthMm) const {
  const cv::Vec3d c = R_world_camera.t() * (pointWorldMm - centreWorldMm);
  if (depthMm) *depthMm = c[2];
  const cv::Vec2d p = distort(cv::Vec2d(c[0] / c[2], c[1] / c[2]));
  return {K(0, 0) * p[0] + K(0, 1) * p[1] + K(0, 2), K(1, 1) * p[1] + K(1, 2)};
}

}  // namespace tissuemosaic::synthetic
