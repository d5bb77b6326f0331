#pragma once
/// @file SyntheticStereoScene.h
/// @brief A synthetic stereo-endoscope pair with exact ground truth, deterministic from a seed (DESIGN.md,
/// Testing). A liver-like textured surface (TissueSurface, TissueTexture) is seen by a calibrated stereo scope with
/// small lens distortion and a small rotation between the eyes. The rectified pair is rendered directly with the
/// rectified cameras of cv::stereoRectify (alpha 0, zero-disparity principal points, as StereoRectifier), so the
/// ground truth is exact for it; the unrectified ("raw") pair is rendered with the physical cameras.
#include "Core/StereoRig.h"
#include "SyntheticLighting.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace tissuemosaic::synthetic {

struct SyntheticStereoOptions {
  int width = 960, height = 540;   ///< image size in pixels (raw and rectified)
  uint32_t seed = 1;               ///< same seed and options: identical images, bit for bit
  double focalPx = 0;              ///< 0: 1000 px scaled by width / 960 (same field of view at any size)
  double baselineMm = 5.0;
  double workingDistanceMm = 85.0; ///< along the left optical axis to the tissue's reference point
  double tiltDeg = 15.0;           ///< angle between the optical axis and the tissue's mean normal
  double reliefMm = 4.0;           ///< amplitude of the random bumps on the liver-like dome
  double distortion = 1.0;         ///< scale of the lenses' built-in distortion (0: none)
  double eyeRotationDeg = 0.5;     ///< size of the rotation between the eyes (0: parallel eyes)
  double noiseStdGrey = 1.5;       ///< sensor read noise in 8-bit grey levels (0: noise-free)
  int supersampling = 2;           ///< n x n rays per pixel (anti-aliasing)
  SyntheticLighting lighting = SyntheticLighting::Standard;  ///< the look (SyntheticLighting.h)
  /// The rectified right view's rows lie this many px below the left's (negative: above), as with a calibration off
  /// in the vertical or a capture that shifts one eye: rightRectified is rendered so, the raw pair, the calibration
  /// and the ground truth (the left view's) are not. 0: a rectified pair.
  int rightRowsBelowPx = 0;

  /// The default scene's disparities lie within about [45, 75] px at 960x540, inside the paper's [-20, 80].
  /// This variant (close, oblique view, 8 mm baseline) spans about 100 px at 960 px wide (twice that at 1920) for
  /// benchmarks of wide searches. The view keeps its horizontal field of view at every size; a taller image (5:4
  /// rather than 16:9) sees more of the tissue above and below, so the tilt gives way by what the half vertical
  /// field of view gains, and the extreme rays stay as oblique as at 16:9.
  static SyntheticStereoOptions wideDisparity(int width = 960, int height = 540);
  /// Throws Error naming the first option out of range.
  void validate() const;
};

struct SyntheticStereoPair {
  cv::Mat leftRectified, rightRectified;  ///< CV_8UC3 BGR, rendered with the rectified cameras
  cv::Mat leftRaw, rightRaw;              ///< CV_8UC3 BGR, rendered with the physical (distorted, rotated) cameras
  cv::Mat disparityPx;  ///< CV_32F, rectified left view: x_left - x_right; NaN where not seen by both eyes
  cv::Mat depthMm;      ///< CV_32F, rectified left view: depth along the rectified left optical axis; NaN as above
  cv::Mat highlightMaskLeft;  ///< CV_8U, rectified left view: 255 on specular highlights (kHighlightMinGrey)
  StereoCalibration calibration;  ///< of the raw pair
  RectifiedGeometry geometry;     ///< of the rectified pair (equals StereoRectifier(calibration).geometry())
  cv::Mat R1, R2, P1, P2;         ///< cv::stereoRectify's outputs that the rectified renders used
};

/// The raw (unrectified) rig the scene uses for these options: slightly different lenses with small distortion and a
/// small rotation between the eyes. Shared with the synthetic scanning video (SyntheticScan.h).
StereoCalibration syntheticStereoCalibration(const SyntheticStereoOptions& options);

/// Renders the scene. Throws Error for invalid options or a surface too steep for the view (it would occlude
/// itself, which the ground truth does not model).
SyntheticStereoPair renderSyntheticStereoPair(const SyntheticStereoOptions& options);

/// Writes left.png right.png (rectified), left_raw.png right_raw.png, rig.yml (calibration of the raw pair),
/// disparity.pfm and depth_mm.pfm (rectified left view, NaN = invisible) and groundtruth/highlight_mask_left.png
/// (255 on highlights) into directory, which is created if needed. Returns the paths written. Throws Error when a
/// file cannot be written.
std::vector<std::string> writeSyntheticStereoPair(const SyntheticStereoPair& pair, const std::string& directory);

}  // namespace tissuemosaic::synthetic
