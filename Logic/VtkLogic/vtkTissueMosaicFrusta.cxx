#include "vtkTissueMosaicFrusta.h"

#include "Core/StereoRig.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <numeric>
#include <vector>

namespace tissuemosaic {

Eigen::Vector3d pixelToWorldMm(const RectifiedGeometry& geometry, const Eigen::Matrix4d& T_world_camera, double xPx,
                               double yPx, double depthMm) {
  const Eigen::Vector4d cameraMm((xPx - geometry.cxLeftPx) / geometry.focalPx * depthMm,
                                 (yPx - geometry.cyPx) / geometry.focalPx * depthMm, depthMm, 1.0);
  return (T_world_camera * cameraMm).head<3>();
}

void updateCameraFrusta(vtkPolyData* polyData, const CameraPoses& cameras, const RectifiedGeometry& geometry,
                        double depthMm) {
  // Pixel centres are at integers: the image's outer edges are half a pixel beyond the first and last centres.
  const double left = -0.5, top = -0.5;
  const double right = geometry.imageSize.width - 0.5, bottom = geometry.imageSize.height - 0.5;
  const double corners[4][2] = {{left, top}, {right, top}, {right, bottom}, {left, bottom}};

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> frameIndices;
  frameIndices->SetName(kFrustumFrameIndexArrayName);
  for (const CameraPose& camera : cameras) {
    const vtkIdType apex = points->InsertNextPoint(camera.T_world_camera.block<3, 1>(0, 3).data());
    for (const auto& corner : corners) {
      points->InsertNextPoint(pixelToWorldMm(geometry, camera.T_world_camera, corner[0], corner[1], depthMm).data());
    }
    for (int i = 0; i < 4; ++i) {
      const vtkIdType edge[2] = {apex, apex + 1 + i};
      const vtkIdType side[2] = {apex + 1 + i, apex + 1 + (i + 1) % 4};
      lines->InsertNextCell(2, edge);
      lines->InsertNextCell(2, side);
    }
    for (int i = 0; i < 8; ++i) frameIndices->InsertNextValue(camera.frameIndex);
  }
  polyData->Initialize();
  polyData->SetPoints(points);
  polyData->SetLines(lines);
  polyData->GetCellData()->AddArray(frameIndices);
  polyData->Modified();
}

vtkSmartPointer<vtkPolyData> cameraFrustaToPolyData(const CameraPoses& cameras, const RectifiedGeometry& geometry,
                                                    double depthMm) {
  auto polyData = vtkSmartPointer<vtkPolyData>::New();
  updateCameraFrusta(polyData, cameras, geometry, depthMm);
  return polyData;
}

void updateCameraPath(vtkPolyData* polyData, const CameraPoses& cameras) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const CameraPose& camera : cameras) points->InsertNextPoint(camera.T_world_camera.block<3, 1>(0, 3).data());
  vtkNew<vtkCellArray> lines;
  if (cameras.size() >= 2) {
    std::vector<vtkIdType> ids(cameras.size());
    std::iota(ids.begin(), ids.end(), vtkIdType(0));
    lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  }
  polyData->Initialize();
  polyData->SetPoints(points);
  polyData->SetLines(lines);
  polyData->Modified();
}

}  // namespace tissuemosaic
