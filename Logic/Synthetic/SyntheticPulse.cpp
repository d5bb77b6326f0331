#include "SyntheticPulse.h"

#include "Core/Error.h"

#include <cmath>

namespace tissuemosaic::synthetic {

SyntheticPulse::SyntheticPulse(double amplitudeMm, double periodS, const cv::Point2d& centreMm, double radiusMm)
    : amplitudeMm_(amplitudeMm), periodS_(periodS) {
  require(amplitudeMm > 0 && periodS > 0 && radiusMm > 0, "synthetic pulse: amplitude, period and radius must be positive");
  shape_.centreXMm = centreMm.x;
  shape_.centreYMm = centreMm.y;
  shape_.innerRadiusMm = kInnerShare * radiusMm;
  shape_.outerRadiusMm = radiusMm;
  shape_.amplitudeMm = 1;
}

SurfaceSwell SyntheticPulse::swellAt(double timeS) const {
  constexpr double twoPi = 6.283185307179586;
  SurfaceSwell swell = shape_;
  swell.amplitudeMm = active() ? -amplitudeMm_ * 0.5 * (1 - std::cos(twoPi * timeS / periodS_)) : 0.0;
  return swell;
}

SurfaceSwell SyntheticPulse::peakSwell() const {
  SurfaceSwell swell = shape_;
  swell.amplitudeMm = active() ? -amplitudeMm_ : 0.0;
  return swell;
}

double SyntheticPulse::peakDisplacementMm(double xMm, double yMm) const {
  return active() ? amplitudeMm_ * shape_.weight(xMm, yMm) : 0.0;
}

}  // namespace tissuemosaic::synthetic
