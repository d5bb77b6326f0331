#pragma once
/// @file SyntheticPulse.h
/// @brief The pulsation of the in-vivo scans (SyntheticInVivo.h): a small patch of tissue over an artery rises toward
/// the scope and falls back once per heartbeat, d(x, y, t) = A w(x, y) (1 - cos(2 pi t / T)) / 2 along world -Z, w a
/// SurfaceSwell's weight (flat over kInnerShare of the radius, 0 beyond it). Faster and far more local than the
/// breathing, and it goes on through a breath hold. At t = 0 the tissue is at rest.
#include "SurfaceSwell.h"

#include <opencv2/core.hpp>

namespace tissuemosaic::synthetic {

class SyntheticPulse {
public:
  /// The flat top's share of the radius: a pulse peaks over the artery and fades around it.
  static constexpr double kInnerShare = 0.25;

  SyntheticPulse() = default;
  /// amplitudeMm > 0, periodS > 0, radiusMm > 0: the patch centred at centreMm (world XY, material coordinates).
  SyntheticPulse(double amplitudeMm, double periodS, const cv::Point2d& centreMm, double radiusMm);

  bool active() const { return amplitudeMm_ > 0; }
  /// The swell at time t (s): amplitude -A (1 - cos(2 pi t / T)) / 2 (toward the scope).
  SurfaceSwell swellAt(double timeS) const;
  /// The swell at its peak (the surface nearest the scope).
  SurfaceSwell peakSwell() const;
  /// Largest displacement of the tissue at world (x, y) over a beat (mm).
  double peakDisplacementMm(double xMm, double yMm) const;
  const SurfaceSwell& shape() const { return shape_; }
  double amplitudeMm() const { return amplitudeMm_; }
  double periodS() const { return periodS_; }

private:
  double amplitudeMm_ = 0, periodS_ = 1;
  SurfaceSwell shape_;  ///< amplitude 1 (the weight alone)
};

}  // namespace tissuemosaic::synthetic
