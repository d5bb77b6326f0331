#include "TestRegistrationScene.h"

#include <Eigen/Geometry>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <cmath>

namespace tissuemosaic::test {

vtkSmartPointer<vtkPolyData> heightFieldMesh(double halfSizeMm, double spacingMm) {
  const int cells = static_cast<int>(std::lround(2 * halfSizeMm / spacingMm));
  const int side = cells + 1;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const double x = -halfSizeMm + i * spacingMm, y = -halfSizeMm + j * spacingMm;
      points->InsertNextPoint(x, y, height(x, y));
    }
  }
  vtkNew<vtkCellArray> triangles;
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const vtkIdType a = j * side + i, b = a + 1, c = a + side, d = c + 1;
      const vtkIdType first[3] = {a, b, d}, second[3] = {a, d, c};  // counter-clockwise seen from +z
      triangles->InsertNextCell(3, first);
      triangles->InsertNextCell(3, second);
    }
  }
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->SetPoints(points);
  mesh->SetPolys(triangles);
  return mesh;
}

ScanSample scanSample(int n, double halfSizeMm, double noiseMm, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> position(-halfSizeMm, halfSizeMm), unit(0, 1), offSurface(1.5, 4.0);
  std::normal_distribution<double> noise(0, noiseMm);
  ScanSample sample;
  for (int k = 0; k < n; ++k) {
    const double x = position(random), y = position(random);
    // A blob of tissue missing from the CT (radius 0.36 * halfSize: about 10% of the area) plus 11% scattered.
    const double blobRadius = 0.36 * halfSizeMm;
    const bool inBlob = std::hypot(x - 0.5 * halfSizeMm, y - 0.5 * halfSizeMm) < blobRadius;
    const bool off = inBlob || unit(random) < 0.11;
    const double offset = off ? offSurface(random) : noise(random);
    sample.pointsMm.push_back(Eigen::Vector3d(x, y, height(x, y)) + offset * surfaceNormal(x, y));
    sample.trueDistanceMm.push_back(std::abs(offset));
    sample.offSurfaceCount += off;
  }
  return sample;
}

Eigen::Matrix4d rigidTransform(const Eigen::Vector3d& axis, double angleDeg, const Eigen::Vector3d& centre,
                               const Eigen::Vector3d& translation) {
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angleDeg * M_PI / 180, axis.normalized()).toRotationMatrix();
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  transform.topLeftCorner<3, 3>() = rotation;
  transform.topRightCorner<3, 1>() = centre - rotation * centre + translation;
  return transform;
}

}  // namespace tissuemosaic::test
