#pragma once
/// @file PointModel.h
/// @brief The fused surface model as the host sees it: world-frame points with colour, normal and TSDF weight.
#include "Core/StereoRig.h"

#include <cstddef>
#include <vector>

namespace tissuemosaic {

/// Host copy of the fusion model. cloud.pointsMm are WORLD-frame positions (mm), cloud.normals world-frame unit
/// normals, cloud.colorsRgb the fused colours; weights[i] is point i's TSDF (position) weight, the number of merged
/// observations capped at FusionParameters::maxWeight.
struct ModelPoints {
  ColoredPointCloud cloud;
  std::vector<float> weights;
  std::size_t size() const { return cloud.size(); }
};

}  // namespace tissuemosaic
