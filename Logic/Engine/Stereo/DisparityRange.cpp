#include "Stereo/DisparityRange.h"

#include "Core/Error.h"

#include <cmath>
#include <opencv2/core.hpp>

namespace tissuemosaic {

std::string DisparityRange::text() const { return std::to_string(minPx) + ".." + std::to_string(maxPx) + " px"; }

DisparityRange disparityRangeOnGrid(double lowPx, double highPx) {
  require(std::isfinite(lowPx) && std::isfinite(highPx) && lowPx <= highPx,
          "disparity range: the ends must be finite and in order");
  const double grid = kDisparityRangeGridPx;
  DisparityRange range;
  // Ends far outside int stay outside the accepted span after clamping, so the check below names them.
  const double low = std::floor(std::max(lowPx, -1e6) / grid) * grid;
  const double high = std::ceil((std::min(highPx, 1e6) + 1) / grid) * grid - 1;
  range.minPx = static_cast<int>(low);
  range.maxPx = static_cast<int>(std::max(high, low + 2 * grid - 1));
  require(range.minPx >= -1000 && range.maxPx <= 1000 && range.count() <= 1024,
          cv::format("disparity range %.1f..%.1f px is beyond what the matcher takes (-1000..1000 px, at most 1024 "
                     "candidates)",
                     lowPx, highPx));
  return range;
}

DisparityRange disparityRangeForDepthMm(const RectifiedGeometry& geometry, double nearMm, double farMm) {
  require(std::isfinite(nearMm) && std::isfinite(farMm) && nearMm > 0 && farMm > nearMm,
          cv::format("working distance %g..%g mm: the near distance must be positive and below the far one", nearMm,
                     farMm));
  require(geometry.focalPx > 0 && geometry.baselineMm > 0,
          "working distance: the rig's focal length and baseline are needed to turn millimetres into disparities");
  const double nearestPx = geometry.focalPx * geometry.baselineMm / nearMm - geometry.doffsPx;
  const double farthestPx = geometry.focalPx * geometry.baselineMm / farMm - geometry.doffsPx;
  try {
    return disparityRangeOnGrid(farthestPx, nearestPx);
  } catch (const Error&) {
    throw Error(cv::format("working distance %g..%g mm gives disparities %.1f..%.1f px with this rig (f %.1f px, B "
                           "%.2f mm): beyond what the matcher takes (-1000..1000 px, at most 1024 candidates)",
                           nearMm, farMm, farthestPx, nearestPx, geometry.focalPx, geometry.baselineMm));
  }
}

std::optional<DisparityRange> requestedDisparityRange(const StereoParameters& parameters,
                                                      const RectifiedGeometry* geometry) {
  switch (parameters.disparityRangeMode) {
    case DisparityRangeMode::Fixed: return DisparityRange{parameters.minDisparityPx, parameters.maxDisparityPx};
    case DisparityRangeMode::WorkingDistance:
      require(geometry != nullptr,
              "a working distance needs the rig's calibration (focal length and baseline) to become disparities");
      return disparityRangeForDepthMm(*geometry, parameters.workingDistanceNearMm, parameters.workingDistanceFarMm);
    default: return std::nullopt;
  }
}

}  // namespace tissuemosaic
