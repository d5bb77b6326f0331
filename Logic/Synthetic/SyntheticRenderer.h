#pragma once
/// @file SyntheticRenderer.h
/// @brief Ray casts a camera's pixels onto the tissue surface and shades them like an endoscope: Lambert plus
/// Blinn-Phong highlights lit from the scope tip (so each eye sees its own highlights), inverse-square light
/// fall-off, vignetting of the physical lens, gamma, and sensor noise. Also computes ground-truth depth and
/// disparity for a rectified pair.
#include "RayOccluder.h"
#include "SyntheticCamera.h"
#include "SyntheticLighting.h"
#include "TissueSurface.h"
#include "TissueTexture.h"

#include <opencv2/core.hpp>

#include <cstdint>

namespace tissuemosaic::synthetic {

struct ShadingParameters {
  cv::Vec3d lightWorldMm{0, 0, 0};  ///< the light at the scope tip
  double lightReferenceMm = 80.0;   ///< distance at which a frontally lit surface is exposed to about mid-grey
  double ambient = 0.08;            ///< fraction of the diffuse light that reaches every point (scattering)
  double specularStrength = 1.2;
  int shininess = 900;              ///< Blinn-Phong exponent: wet tissue gives small, bright highlights
  double vignetting = 0.35;         ///< brightness lost at the image corner of the physical lens
  double noiseStdGrey = 1.5;        ///< read noise (8-bit grey levels); shot noise is added on top
  int supersampling = 2;            ///< n x n rays per pixel
  /// Realistic lighting (SyntheticLighting.h) instead of the terms above, and sensor clipping; null: the standard look.
  const RealisticLighting* realistic = nullptr;
  /// 0 or 1: render only the even or the odd rows (one field of an interlaced frame), the others left black; -1: all.
  int rowParity = -1;
};

/// Renders one 8-bit BGR image seen by `camera`. `lensCamera` is the physical (unrectified) camera of the same
/// eye: its vignetting is applied, so a rectified render matches the raw render after rectification. The noise
/// is a function of (seed, noiseStream, pixel) only, so the result does not depend on threading. highlightMask
/// (optional): CV_8U, 255 where the specular reflection raises the grey level by kHighlightMinGrey or more.
/// occluder (optional): drawn wherever it is nearer than the tissue (the instruments), with the same camera response.
cv::Mat renderView(const SyntheticCamera& camera, const SyntheticCamera& lensCamera, const TissueSurface& surface,
                   const TissueTexture& texture, const ShadingParameters& shading, uint32_t seed, uint32_t noiseStream,
                   cv::Mat* highlightMask = nullptr, const RayOccluder* occluder = nullptr);

/// Ground truth for a rectified pair (rectified cameras: no distortion, same orientation, right of left along x):
/// per left pixel centre, depth in mm along the left optical axis and left-view disparity (x_left - x_right);
/// NaN where the surface point is outside the right image.
void renderRectifiedGroundTruth(const SyntheticCamera& leftRectified, const SyntheticCamera& rightRectified,
                                const TissueSurface& surface, cv::Mat& disparityPx, cv::Mat& depthMm);

}  // namespace tissuemosaic::synthetic
