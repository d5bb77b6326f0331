#pragma once
/// @file vtkTissueMosaicFrusta.h
/// @brief Camera poses as VTK line data for the 3D view: one viewing pyramid (frustum) per key frame, and the
/// camera path as a polyline. Poses are T_world_camera of the left rectified camera (x right, y down, z forward),
/// in millimetres, as the engine gives them.
#include <Eigen/Core>
#include <Eigen/StdVector>
#include <vtkSmartPointer.h>

#include <vector>

class vtkPolyData;

namespace tissuemosaic {

struct RectifiedGeometry;

/// Name of the integer cell array that says which frame each frustum line belongs to.
constexpr const char* kFrustumFrameIndexArrayName = "FrameIndex";

/// One camera to draw: its pose and the frame it belongs to.
struct CameraPose {
  int frameIndex = 0;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using CameraPoses = std::vector<CameraPose, Eigen::aligned_allocator<CameraPose>>;

/// The world position (mm) of image pixel (xPx, yPx) seen at depth depthMm by a camera with this geometry and pose.
Eigen::Vector3d pixelToWorldMm(const RectifiedGeometry& geometry, const Eigen::Matrix4d& T_world_camera, double xPx,
                               double yPx, double depthMm);

/// Per camera 5 points, in this order: the optical centre, then the image's four outer corners (top-left,
/// top-right, bottom-right, bottom-left: pixel edges, not centres) at depthMm in front of it; and 8 line cells
/// (4 edges from the centre, the 4 sides of the image rectangle) carrying the camera's frame index in the cell
/// array kFrustumFrameIndexArrayName. The geometry gives the field of view (focal length, principal point, size).
vtkSmartPointer<vtkPolyData> cameraFrustaToPolyData(const CameraPoses& cameras, const RectifiedGeometry& geometry,
                                                    double depthMm);

/// Rewrites `polyData` in place with the frusta (same content as cameraFrustaToPolyData), so that mappers holding
/// it see the change.
void updateCameraFrusta(vtkPolyData* polyData, const CameraPoses& cameras, const RectifiedGeometry& geometry,
                        double depthMm);

/// The optical centres of the cameras, in order, as one polyline (no cell when fewer than 2 cameras).
void updateCameraPath(vtkPolyData* polyData, const CameraPoses& cameras);

}  // namespace tissuemosaic
