#pragma once
/// @file RayOccluder.h
/// @brief Something between the scope and the tissue that renderView draws in front of it (the instruments of
/// SyntheticInstruments.h): its own shape and material, the renderer's camera response (vignetting, gamma, noise).
#include <opencv2/core.hpp>

namespace tissuemosaic::synthetic {

struct ShadingParameters;

class RayOccluder {
public:
  virtual ~RayOccluder() = default;
  /// When origin + t * direction meets the occluder at some 0 < t < tMax (t in units of `direction`, which need not
  /// be unit): true, with the linear BGR radiance seen there under `shading`'s light. False when the ray misses it
  /// or meets it only beyond tMax (e.g. behind the tissue).
  virtual bool shade(const cv::Vec3d& origin, const cv::Vec3d& direction, double tMax, const ShadingParameters& shading,
                     cv::Vec3d& radianceBgr) const = 0;
};

}  // namespace tissuemosaic::synthetic
