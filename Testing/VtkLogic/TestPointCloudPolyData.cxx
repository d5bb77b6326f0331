// pointCloudToPolyData: every point, its colour and normal arrive in the vtkPolyData unchanged.
#include "vtkTissueMosaicPointCloud.h"

#include "Core/StereoRig.h"

#include <gtest/gtest.h>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

using namespace tissuemosaic;

TEST(PointCloudPolyData, PointsColorsNormalsAndOneVertexPerPoint) {
  ColoredPointCloud cloud;
  for (int i = 0; i < 50; ++i) {
    cloud.pointsMm.emplace_back(0.5f * i, -1.0f * i, 40.0f + i);
    cloud.colorsRgb.emplace_back(static_cast<uchar>(i), static_cast<uchar>(2 * i), static_cast<uchar>(255 - i));
    cloud.normals.emplace_back(0.0f, 0.6f, -0.8f);
  }
  const vtkSmartPointer<vtkPolyData> polyData = pointCloudToPolyData(cloud);

  ASSERT_EQ(polyData->GetNumberOfPoints(), 50);
  EXPECT_EQ(polyData->GetNumberOfVerts(), 50);
  EXPECT_EQ(polyData->GetNumberOfCells(), 50);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(polyData->GetPointData()->GetScalars());
  ASSERT_NE(colors, nullptr);
  EXPECT_STREQ(colors->GetName(), "RGB");
  EXPECT_EQ(colors->GetNumberOfComponents(), 3);
  vtkDataArray* normals = polyData->GetPointData()->GetNormals();
  ASSERT_NE(normals, nullptr);

  vtkCellArray* vertices = polyData->GetVerts();
  vtkIdType cellSize = 0;
  const vtkIdType* cellPoints = nullptr;
  for (vtkIdType i = 0; i < 50; ++i) {
    double point[3];
    polyData->GetPoint(i, point);
    EXPECT_FLOAT_EQ(point[0], cloud.pointsMm[i].x);
    EXPECT_FLOAT_EQ(point[1], cloud.pointsMm[i].y);
    EXPECT_FLOAT_EQ(point[2], cloud.pointsMm[i].z);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(colors->GetValue(3 * i + c), cloud.colorsRgb[i][c]);
    EXPECT_FLOAT_EQ(normals->GetComponent(i, 1), 0.6f);
    vertices->GetCellAtId(i, cellSize, cellPoints);
    ASSERT_EQ(cellSize, 1);
    EXPECT_EQ(cellPoints[0], i);
  }
  double bounds[6];
  polyData->GetBounds(bounds);
  EXPECT_FLOAT_EQ(bounds[4], 40.0f);
  EXPECT_FLOAT_EQ(bounds[5], 89.0f);
}

TEST(PointCloudPolyData, NoNormalsWhenTheCloudHasNone) {
  ColoredPointCloud cloud;
  cloud.pointsMm = {{1, 2, 3}, {4, 5, 6}};
  cloud.colorsRgb = {{1, 2, 3}, {4, 5, 6}};
  const vtkSmartPointer<vtkPolyData> polyData = pointCloudToPolyData(cloud);
  EXPECT_EQ(polyData->GetNumberOfPoints(), 2);
  EXPECT_EQ(polyData->GetPointData()->GetNormals(), nullptr);
}

TEST(PointCloudPolyData, EmptyCloudGivesEmptyPolyData) {
  const vtkSmartPointer<vtkPolyData> polyData = pointCloudToPolyData(ColoredPointCloud{});
  EXPECT_EQ(polyData->GetNumberOfPoints(), 0);
  EXPECT_EQ(polyData->GetNumberOfVerts(), 0);
}
