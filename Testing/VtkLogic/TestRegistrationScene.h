#pragma once
// Ground truth for the registration tests: a smooth tissue-like height field (bowl plus three Gaussian bumps,
// curvature radius >= 16 mm everywhere), its triangulated mesh (the "CT surface"), and a scan-like sample of it
// with 0.1 mm noise along the normal plus points lying 1.5-4 mm off the surface (20%: a blob and scattered
// ones). Because every offset is along the normal and smaller than the curvature radius, a sample's true
// distance to the surface is exactly |offset|.
#include <Eigen/Core>
#include <vtkSmartPointer.h>

#include <cmath>
#include <random>
#include <vector>

class vtkPolyData;

namespace tissuemosaic::test {

inline double height(double x, double y) {
  const auto bump = [](double x, double y, double cx, double cy, double amplitude, double sigma) {
    return amplitude * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * sigma * sigma));
  };
  return 0.004 * (x * x + 0.5 * y * y) + bump(x, y, 8, -5, 6, 10) + bump(x, y, -10, 8, -4, 8) +
         bump(x, y, -5, -15, 2, 6);
}

inline Eigen::Vector3d surfaceNormal(double x, double y) {
  const double h = 1e-5;
  const double dx = (height(x + h, y) - height(x - h, y)) / (2 * h);
  const double dy = (height(x, y + h) - height(x, y - h)) / (2 * h);
  return Eigen::Vector3d(-dx, -dy, 1).normalized();
}

/// The height field over [-halfSize, halfSize]^2 as a triangle mesh with the given grid spacing.
vtkSmartPointer<vtkPolyData> heightFieldMesh(double halfSizeMm, double spacingMm);

struct ScanSample {
  std::vector<Eigen::Vector3d> pointsMm;  ///< in the surface's frame
  std::vector<double> trueDistanceMm;     ///< |offset along the normal|
  std::size_t offSurfaceCount = 0;
};

/// n points over [-halfSize, halfSize]^2, deterministic from the seed.
ScanSample scanSample(int n, double halfSizeMm, double noiseMm, unsigned seed);

/// A rigid transform: rotation by angleDeg about axis through `centre`, then a translation.
Eigen::Matrix4d rigidTransform(const Eigen::Vector3d& axis, double angleDeg, const Eigen::Vector3d& centre,
                               const Eigen::Vector3d& translation);

}  // namespace tissuemosaic::test
