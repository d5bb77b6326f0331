#pragma once
/// @file SyntheticBreathing.h
/// @brief The breathing of part of the tissue: a flat-topped swell (SurfaceSwell.h) that rises toward the scope
/// and falls back once per breath, d(x, y, t) = A w(x, y) (1 - cos(2 pi t / T)) / 2 along world -Z: A at its
/// centre, exactly 0 outside its outer radius. The texture stays attached to the tissue (it is painted on X, Y, and
/// the tissue moves along Z only), so a breathing point is one material point at every instant.
///
/// Ground truth: the surface at a frame is TissueSurface::swollen(swellAt(t)); the part that never moves is where
/// the peak displacement A w is at most kStaticToleranceMm. A breath hold (the ventilator paused) stops the breath
/// where it is for its span; the breath then goes on from there.
///
/// A lateral part (setLateral, the in-vivo mode): with the breath the tissue also slides sideways, by up to
/// lateralMm along a direction of the XY plane, weighted by the same shape (SurfaceDeformation.h, SurfaceSlide):
/// abdominal wall and liver do not move along the view axis alone.
#include "SurfaceDeformation.h"
#include "SurfaceSwell.h"

#include <opencv2/core.hpp>

namespace tissuemosaic::synthetic {

class SyntheticBreathing {
public:
  /// A region no moving point is farther than this (mm) from its rest position: static_surface.ply keeps it.
  static constexpr double kStaticToleranceMm = 0.01;
  /// The flat top's share of the breathing radius (SyntheticHardModeOptions::breathingRadiusMm).
  static constexpr double kInnerShare = 10.0 / 18.0;

  SyntheticBreathing() = default;
  /// amplitudeMm > 0, periodS > 0: the swell centred at centreMm (world XY) with the given radii.
  SyntheticBreathing(double amplitudeMm, double periodS, const cv::Point2d& centreMm, double innerRadiusMm,
                     double outerRadiusMm);
  /// Pauses the breath from startS to endS (s), startS >= 0, endS > startS.
  void holdBreath(double startS, double endS);
  /// The breath's own time at scan time t (s): t before a hold, its start during it, t minus its span after it.
  double breathTimeS(double timeS) const;

  bool active() const { return amplitudeMm_ > 0; }
  /// The swell at time t (s): amplitude -A (1 - cos(2 pi b / T)) / 2 with b = breathTimeS(t), so at t = 0 the
  /// surface is at rest.
  SurfaceSwell swellAt(double timeS) const;
  /// The breath's phase at time t: (1 - cos(2 pi b / T)) / 2 with b = breathTimeS(t), 0 at rest, 1 at the peak.
  double phaseAt(double timeS) const;
  /// The sideways part: at the breath's peak the tissue where the shape's weight is 1 has slid by lateralMm along
  /// the unit XY direction. lateralMm >= 0.
  void setLateral(double lateralMm, const cv::Vec2d& direction);
  /// The slide at time t (inactive without a lateral part).
  SurfaceSlide slideAt(double timeS) const;
  double lateralMm() const { return lateralMm_; }
  const cv::Vec2d& lateralDirection() const { return lateralDirection_; }
  /// The swell at its peak (the surface nearest the scope).
  SurfaceSwell peakSwell() const;
  /// Largest displacement of the tissue at world (x, y) over a breath (mm).
  double peakDisplacementMm(double xMm, double yMm) const;
  /// True where the tissue never moves by more than kStaticToleranceMm.
  bool isStatic(double xMm, double yMm) const { return peakDisplacementMm(xMm, yMm) <= kStaticToleranceMm; }
  const SurfaceSwell& shape() const { return shape_; }
  double amplitudeMm() const { return amplitudeMm_; }
  double periodS() const { return periodS_; }

private:
  double amplitudeMm_ = 0, periodS_ = 4;
  double holdStartS_ = -1, holdEndS_ = -1;  ///< no hold: startS < 0
  SurfaceSwell shape_;  ///< amplitude 1 (the weight alone)
  double lateralMm_ = 0;
  cv::Vec2d lateralDirection_{1, 0};
};

}  // namespace tissuemosaic::synthetic
