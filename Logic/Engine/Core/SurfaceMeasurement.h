#pragma once
/// @file SurfaceMeasurement.h
/// @brief One stereo frame as a surface seen from the left rectified camera: per pixel the 3D point, its normal and
/// its colour. Key-frame refinement (the ICP term's q_i and n_i, paper eq. ICPterm) and TSDF fusion both read it.
#include "Core/Device.h"
#include "Core/StereoRig.h"

#include <opencv2/core.hpp>

namespace tissuemosaic {

/// All maps have the rectified image size; "no estimate" is NaN in every channel.
struct SurfaceMeasurement {
  cv::Mat pointsCameraMm;  ///< CV_32FC3: X Y Z in the left rectified camera frame (x right, y down, z forward), mm
  cv::Mat normalsCamera;   ///< CV_32FC3: unit normals in the same frame, turned toward the camera (n . p < 0)
  cv::Mat colourBgr;       ///< CV_8UC3: the rectified left image
  int validPixels = 0;     ///< pixels with both a point and a normal

  bool empty() const { return pointsCameraMm.empty(); }
};

/// Builds the measurement from a left-view disparity (CV_32F, NaN = none) and the rectified left image (8-bit grey,
/// BGR or BGRA, same size): points as disparityToDepthMm / reconstructScene, normals from the cross product of the
/// central differences of the neighbouring points `normalRadiusPx` away (NaN where a neighbour is missing or the
/// depth jumps by more than `maxDepthJumpMm`). Runs on `device`. Throws Error on empty or mismatched inputs.
SurfaceMeasurement measureSurface(const cv::Mat& disparityPx, const cv::Mat& leftRectified,
                                  const RectifiedGeometry& geometry, Device device, int normalRadiusPx = 2,
                                  double maxDepthJumpMm = 2.0);

}  // namespace tissuemosaic
