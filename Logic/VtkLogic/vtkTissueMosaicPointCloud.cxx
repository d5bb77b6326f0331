#include "vtkTissueMosaicPointCloud.h"

#include "Core/StereoRig.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cstring>
#include <numeric>

namespace tissuemosaic {

namespace {

/// Copies n packed 3-float vectors (cv::Point3f is three contiguous floats) into a new 3-component array.
vtkSmartPointer<vtkFloatArray> toFloatArray(const cv::Point3f* data, vtkIdType n) {
  static_assert(sizeof(cv::Point3f) == 3 * sizeof(float), "cv::Point3f must be three packed floats");
  auto array = vtkSmartPointer<vtkFloatArray>::New();
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(n);
  if (n > 0) std::memcpy(array->GetPointer(0), data, static_cast<std::size_t>(n) * sizeof(cv::Point3f));
  return array;
}

}  // namespace

vtkSmartPointer<vtkPolyData> pointCloudToPolyData(const ColoredPointCloud& cloud) {
  const auto n = static_cast<vtkIdType>(cloud.pointsMm.size());
  auto polyData = vtkSmartPointer<vtkPolyData>::New();

  vtkNew<vtkPoints> points;
  points->SetData(toFloatArray(cloud.pointsMm.data(), n));
  polyData->SetPoints(points);

  // Uniform cells of size 1: the connectivity is simply 0 .. n-1.
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(n);
  std::iota(connectivity->GetPointer(0), connectivity->GetPointer(0) + n, vtkIdType(0));
  vtkNew<vtkCellArray> vertices;
  vertices->SetData(1, connectivity);
  polyData->SetVerts(vertices);

  if (cloud.colorsRgb.size() == cloud.pointsMm.size()) {
    static_assert(sizeof(cv::Vec3b) == 3, "cv::Vec3b must be three packed bytes");
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName(kPointCloudColorArrayName);
    colors->SetNumberOfComponents(3);
    colors->SetNumberOfTuples(n);
    if (n > 0) std::memcpy(colors->GetPointer(0), cloud.colorsRgb.data(), static_cast<std::size_t>(n) * 3);
    polyData->GetPointData()->SetScalars(colors);
  }
  if (n > 0 && cloud.normals.size() == cloud.pointsMm.size()) {
    auto normals = toFloatArray(cloud.normals.data(), n);
    normals->SetName("Normals");
    polyData->GetPointData()->SetNormals(normals);
  }
  return polyData;
}

}  // namespace tissuemosaic
