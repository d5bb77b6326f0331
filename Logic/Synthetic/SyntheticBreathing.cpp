#include "SyntheticBreathing.h"

#include "Core/Error.h"

#include <cmath>

namespace tissuemosaic::synthetic {

SyntheticBreathing::SyntheticBreathing(double amplitudeMm, double periodS, const cv::Point2d& centreMm,
                                       double innerRadiusMm, double outerRadiusMm)
    : amplitudeMm_(amplitudeMm), periodS_(periodS) {
  require(amplitudeMm > 0 && periodS > 0 && innerRadiusMm >= 0 && outerRadiusMm > innerRadiusMm,
          "synthetic breathing: amplitude, period and radii must be positive, the outer radius beyond the inner");
  shape_.centreXMm = centreMm.x;
  shape_.centreYMm = centreMm.y;
  shape_.innerRadiusMm = innerRadiusMm;
  shape_.outerRadiusMm = outerRadiusMm;
  shape_.amplitudeMm = 1;
}

void SyntheticBreathing::holdBreath(double startS, double endS) {
  require(startS >= 0 && endS > startS, "synthetic breathing: a hold needs 0 <= start < end");
  holdStartS_ = startS;
  holdEndS_ = endS;
}

double SyntheticBreathing::breathTimeS(double timeS) const {
  if (holdStartS_ < 0 || timeS < holdStartS_) return timeS;
  return timeS < holdEndS_ ? holdStartS_ : timeS - (holdEndS_ - holdStartS_);
}

SurfaceSwell SyntheticBreathing::swellAt(double timeS) const {
  SurfaceSwell swell = shape_;
  constexpr double twoPi = 6.283185307179586;
  swell.amplitudeMm = active() ? -amplitudeMm_ * 0.5 * (1 - std::cos(twoPi * breathTimeS(timeS) / periodS_)) : 0.0;
  return swell;
}

double SyntheticBreathing::phaseAt(double timeS) const {
  constexpr double twoPi = 6.283185307179586;
  return active() ? 0.5 * (1 - std::cos(twoPi * breathTimeS(timeS) / periodS_)) : 0.0;
}

void SyntheticBreathing::setLateral(double lateralMm, const cv::Vec2d& direction) {
  require(lateralMm >= 0 && cv::norm(direction) > 0, "synthetic breathing: the lateral part needs mm >= 0 and a direction");
  lateralMm_ = lateralMm;
  lateralDirection_ = direction / cv::norm(direction);
}

SurfaceSlide SyntheticBreathing::slideAt(double timeS) const {
  SurfaceSlide slide;
  slide.shape = shape_;
  if (lateralMm_ > 0) slide.displacementMm = lateralMm_ * phaseAt(timeS) * lateralDirection_;
  return slide;
}

SurfaceSwell SyntheticBreathing::peakSwell() const {
  SurfaceSwell swell = shape_;
  swell.amplitudeMm = -amplitudeMm_;
  return swell;
}

double SyntheticBreathing::peakDisplacementMm(double xMm, double yMm) const {
  return active() ? amplitudeMm_ * shape_.weight(xMm, yMm) : 0.0;
}

}  // namespace tissuemosaic::synthetic
