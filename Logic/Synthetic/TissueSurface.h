#pragma once
/// @file TissueSurface.h
/// @brief A smooth, liver-like height field Z = h(X, Y) in the synthetic world frame (millimetres): a broad dome
/// that curves away from the scope, a few broad bumps and hollows, and many small gentle ones (undulations). The
/// bumps are compactly supported polynomials (1 - r^2/s^2)^3: smooth, and cheap to evaluate millions of times. The world Z axis
/// points into the tissue (away from the scope), so a camera looking "down" at the tissue looks along +Z.
/// Every term is analytic, so heights, normals and ray intersections are exact (to the Newton tolerance).
#include "SurfaceDeformation.h"
#include "SurfaceSwell.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace tissuemosaic::synthetic {

struct TissueSurfaceParameters {
  double domeDepthMm = 20.0;    ///< the dome's fall-off: h = domeDepthMm * (sqrt(1 + r^2 / domeRadiusMm^2) - 1)
  double domeRadiusMm = 60.0;
  double reliefMm = 4.0;        ///< largest amplitude of the random bumps (and hollows)
  int bumpCount = 9;
  double undulationMm = 0.6;    ///< largest amplitude of the small bumps (radius 5 - 10 mm)
  int undulationCount = 150;
  double extentMm = 70.0;       ///< bumps are placed with centres inside [-extentMm, extentMm]^2
};

class TissueSurface {
public:
  /// A random surface drawn deterministically from seed.
  TissueSurface(const TissueSurfaceParameters& parameters, uint32_t seed);

  /// Height h(x, y) in mm and its gradient.
  double heightMm(double xMm, double yMm, double* dhdx = nullptr, double* dhdy = nullptr) const;
  /// Unit normal pointing toward the scope (-Z side).
  cv::Vec3d normal(double xMm, double yMm) const;
  /// Distance of a point to the surface, to first order: |z - h(x, y)| times the normal's Z component (exact for a
  /// locally flat surface; the surface curves over 12 mm and more, so the error is negligible within a millimetre
  /// or so of it). For scoring reconstructed models against the truth.
  double distanceMm(double xMm, double yMm, double zMm) const;
  /// Largest |grad h| over a rectangle of the XY plane (sampled every 0.25 mm; the surface's features are
  /// 12 mm and larger). With slope * tan(ray angle to +Z) < 1 every ray meets the surface exactly once there, so
  /// nothing is self-occluded.
  double maxSlope(const cv::Rect2d& domainMm) const;
  /// Lower bound of h over the whole plane.
  double minHeightMm() const { return minHeightMm_; }
  /// This surface with `swell` added to its height (the breathing at one instant, SyntheticBreathing.h).
  TissueSurface swollen(const SurfaceSwell& swell) const;
  /// This surface (its swell kept) further deformed by `deformation` (SurfaceDeformation.h): the in-vivo tissue at
  /// one instant. Replaces any earlier deformation.
  TissueSurface deformed(const SurfaceDeformation& deformation) const;
  /// World XY at which the tissue point now above (x, y) rested (the slide's inverse): (x, y) itself without a slide.
  /// The texture is painted on these coordinates.
  cv::Vec2d materialXYMm(double xMm, double yMm) const;
  /// Where the material point that rests at XY (restXMm, restYMm) now lies: on this surface, world frame, mm (the
  /// slide's forward map, solved by fixed-point iteration to 1e-9 mm).
  cv::Vec3d materialPointMm(double restXMm, double restYMm) const;

  /// Ray parameter t > 0 where origin + t * direction meets the surface (direction need not be unit, but must
  /// point into the tissue: direction[2] > 0). warmStart: a nearby ray's t (0: none). Returns NaN if none.
  /// gradient (optional): grad h at the hit, for the normal, without evaluating the surface again.
  /// toleranceMm: accuracy of the hit along the ray (rendering needs little; ground truth uses the default).
  double intersect(const cv::Vec3d& origin, const cv::Vec3d& direction, double warmStart = 0,
                   cv::Vec2d* gradient = nullptr, double toleranceMm = 1e-8) const;

private:
  struct Bump { double x, y, inverseRadius2, amplitude; };
  TissueSurfaceParameters parameters_;
  std::vector<Bump> bumps_;
  // Bumps binned on a coarse grid so a height costs a handful of bumps, not all of them.
  double gridOriginMm_ = 0, gridCellMm_ = 1;
  int gridCells_ = 0;
  std::vector<std::vector<Bump>> grid_;
  double minHeightMm_ = 0;
  SurfaceSwell swell_;  ///< amplitude 0: none
  std::vector<SurfaceSwell> extraSwells_;  ///< the deformation's swells (deformed())
  SurfaceSlide slide_;

  /// h at material coordinates: the rest relief plus every swell (no slide).
  double materialHeightMm(double xMm, double yMm, double* dhdx, double* dhdy) const;
};

}  // namespace tissuemosaic::synthetic
