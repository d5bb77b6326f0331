#pragma once
/// @file SurfaceSwell.h
/// @brief A smooth, flat-topped displacement of part of a height field: amplitudeMm over a disc of innerRadiusMm,
/// falling to exactly 0 at outerRadiusMm and staying 0 beyond, with a continuous slope everywhere. The breathing
/// of the synthetic scans (SyntheticBreathing.h) is a swell whose amplitude follows the breath; TissueSurface adds
/// it to its height (TissueSurface::swollen).
#include <cmath>

namespace tissuemosaic::synthetic {

struct SurfaceSwell {
  double centreXMm = 0, centreYMm = 0;
  double innerRadiusMm = 10, outerRadiusMm = 18;
  double amplitudeMm = 0;  ///< height change along world +Z (into the tissue): negative rises toward the scope

  /// The shape w in [0, 1] at (x, y) and its gradient: 1 within innerRadiusMm, (1 - s^2)^3 with
  /// s = (r - inner) / (outer - inner) across the band, 0 beyond outerRadiusMm.
  double weight(double xMm, double yMm, double* dwdx = nullptr, double* dwdy = nullptr) const {
    const double dx = xMm - centreXMm, dy = yMm - centreYMm, r = std::sqrt(dx * dx + dy * dy);
    double w = 0, dwdr = 0;
    if (r <= innerRadiusMm) {
      w = 1;
    } else if (r < outerRadiusMm) {
      const double band = outerRadiusMm - innerRadiusMm, s = (r - innerRadiusMm) / band, q = 1 - s * s;
      w = q * q * q;
      dwdr = -6 * s * q * q / band;
    }
    if (dwdx) *dwdx = r > 0 ? dwdr * dx / r : 0;
    if (dwdy) *dwdy = r > 0 ? dwdr * dy / r : 0;
    return w;
  }
  /// Largest |grad w| (at s = 1 / sqrt(5) of the band), per mm: times |amplitudeMm| the swell's steepest slope.
  double maxWeightSlopePerMm() const { return 1.7173 / (outerRadiusMm - innerRadiusMm); }
};

}  // namespace tissuemosaic::synthetic
