#pragma once
/// @file vtkTissueMosaicPointCloud.h
/// @brief Engine point clouds as VTK data, for the 3D view and for writing .vtp/.ply files.
#include <vtkSmartPointer.h>

class vtkPolyData;

namespace tissuemosaic {

struct ColoredPointCloud;

/// Name of the per-point colour array (unsigned char, 3 components, RGB order).
constexpr const char* kPointCloudColorArrayName = "RGB";

/// One VTK point per cloud point (coordinates in mm, in the cloud's frame), one vertex cell per point so that
/// every point is drawn, colours as the active scalars "RGB", and the normals as point normals when the cloud
/// has one per point.
vtkSmartPointer<vtkPolyData> pointCloudToPolyData(const ColoredPointCloud& cloud);

}  // namespace tissuemosaic
