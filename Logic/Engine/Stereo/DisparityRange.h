#pragma once
/// @file DisparityRange.h
/// @brief A disparity search range as the stereo matcher takes it, and the ways to one that need no image: the
/// parameters' fixed range, and a working distance in millimetres turned into disparities through the rig. The
/// automatic range (from the images) is DisparityRangeEstimator's.
#include "Core/StereoRig.h"
#include "Stereo/StereoParameters.h"

#include <optional>
#include <string>

namespace tissuemosaic {

/// Candidate disparities minPx..maxPx, both included (a left pixel x matches right pixel x - d).
struct DisparityRange {
  int minPx = 0, maxPx = 0;
  int count() const { return maxPx - minPx + 1; }
  bool contains(double disparityPx) const { return disparityPx >= minPx && disparityPx <= maxPx; }
  bool operator==(const DisparityRange& other) const { return minPx == other.minPx && maxPx == other.maxPx; }
  bool operator!=(const DisparityRange& other) const { return !(*this == other); }
  /// "64..95 px"
  std::string text() const;
};

/// Ranges chosen by the engine (automatic, from a working distance) have both ends on this grid: min and max + 1 are
/// multiples of it. So the count is a multiple of 4 (AD-Census's pixel-major cost rows of int32 start 16-byte
/// aligned, and its CPU loops over the disparities have no remainder at SSE width), and a range that only moves
/// with the tissue keeps its count, so that the matcher keeps its workspace (StereoMatcher::setDisparityRange).
constexpr int kDisparityRangeGridPx = 4;

/// The smallest range on the grid that holds [lowPx, highPx] (lowPx <= highPx, finite), at least two grid steps
/// wide (the matcher needs two candidates). Throws Error when the result lies outside what StereoParameters accepts
/// (-1000..1000 px, at most 1024 candidates).
DisparityRange disparityRangeOnGrid(double lowPx, double highPx);

/// The disparities of tissue nearMm..farMm in front of the left rectified camera (depth along its optical axis):
/// d = f B / Z - doffs (RectifiedGeometry::depthMm inverted), on the grid. Throws Error for 0 < near < far not
/// holding, a geometry without focal length or baseline, or a range StereoParameters cannot take.
DisparityRange disparityRangeForDepthMm(const RectifiedGeometry& geometry, double nearMm, double farMm);

/// The range the parameters ask for when it needs no image: Fixed: minDisparityPx..maxDisparityPx as given;
/// WorkingDistance: disparityRangeForDepthMm (Error when geometry is null: it needs the rig). Automatic: nullopt
/// (DisparityRangeEstimator measures it from the images).
std::optional<DisparityRange> requestedDisparityRange(const StereoParameters& parameters,
                                                      const RectifiedGeometry* geometry);

}  // namespace tissuemosaic
