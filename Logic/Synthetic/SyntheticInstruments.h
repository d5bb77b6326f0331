#pragma once
/// @file SyntheticInstruments.h
/// @brief Rigid laparoscopic instruments for the synthetic scans: a 5 mm steel shaft with dark marking bands and
/// two serrated jaws that open and close, pivoting about a trocar above the tissue. Each instrument enters along its
/// shaft during its own span of frames, works over the tissue (its tip wanders 6-17 mm above it) and withdraws. The
/// geometry is exact (capsules: segments with a radius), so that renders, masks and distances agree; every part
/// keeps at least kClearanceMm from the tissue at its highest (breathing included), so the instruments never
/// touch it and a model point within 1 mm of an instrument's surface is always an instrument artefact.
#include "IO/MeshPly.h"
#include "RayOccluder.h"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace tissuemosaic::synthetic {

class TissueSurface;

/// A segment from `fromMm` to `toMm` swept by a ball of radiusMm (world frame, mm).
struct Capsule {
  cv::Vec3d fromMm{0, 0, 0}, toMm{0, 0, 0};
  double radiusMm = 1;
  /// Signed distance of a point to the capsule's surface (negative inside).
  double distanceMm(const cv::Vec3d& pointMm) const;
};

/// One instrument at one instant.
struct InstrumentPose {
  int instrument = 0;             ///< which instrument (0 ..)
  cv::Vec3d tipMm{0, 0, 0};       ///< end of the shaft, where the jaws hinge
  cv::Vec3d axis{0, 0, -1};       ///< unit, from the tip along the shaft toward the trocar
  Capsule shaft;                  ///< from the tip to the trocar
  std::array<Capsule, 2> jaws;    ///< from the tip outward
};

/// The instruments present at one instant as renderView's occluder, and their left-view mask.
class InstrumentOccluder : public RayOccluder {
public:
  explicit InstrumentOccluder(std::vector<InstrumentPose> poses) : poses_(std::move(poses)) {}
  bool shade(const cv::Vec3d& origin, const cv::Vec3d& direction, double tMax, const ShadingParameters& shading,
             cv::Vec3d& radianceBgr) const override;
  /// True when the ray meets an instrument at some t > 0 (t in units of direction).
  bool hits(const cv::Vec3d& origin, const cv::Vec3d& direction) const;
  bool empty() const { return poses_.empty(); }

private:
  std::vector<InstrumentPose> poses_;
};

class SyntheticInstruments {
public:
  static constexpr double kClearanceMm = 3.0;  ///< least distance of any instrument part to the tissue
  static constexpr double kShaftRadiusMm = 2.5, kJawRadiusMm = 1.1, kJawLengthMm = 9.0;
  /// The shaft's part that the ground-truth mesh holds (mm from the tip): beyond it the shaft is out of view.
  static constexpr double kMeshedShaftLengthMm = 80.0;

  SyntheticInstruments() = default;
  /// `count` instruments over frames [0, frames) at `fps`, each in view for its own span (the spans of N
  /// instruments start at 5 % + 50 % i / N of the scan and last 40 % of it). viewCentreMm(frame, point) gives the
  /// tissue point at the centre of the view at a frame (false for a frame without tissue): an instrument works
  /// around where the scope looks in the middle of its span. highest: the tissue at its highest (breathing at its
  /// peak), for the clearance.
  /// borderReachMm (in-vivo, SyntheticInVivoOptions::instrumentsAtBorder): when not zero, each tip works this far
  /// from the view's centre (world X, Y semi-axes of an ellipse, mm) toward its trocar, near the view's border.
  SyntheticInstruments(int count, int frames, double fps, uint32_t seed,
                       const std::function<bool(int, cv::Vec3d&)>& viewCentreMm, const TissueSurface& highest,
                       const cv::Vec2d& borderReachMm = {0, 0});

  int count() const { return static_cast<int>(plans_.size()); }
  /// The instruments in the scene at frame `index` (those whose span holds it), offsetS seconds after the frame's
  /// time (a sub-frame instant of a blurred or interlaced frame; the span is the frame's).
  std::vector<InstrumentPose> posesAt(int index, double offsetS = 0) const;
  /// How far through its span instrument i is at frame index + offsetS: 0 at its first frame, 1 at its last.
  double spanFraction(int instrument, int index, double offsetS = 0) const;
  /// First and last frame of instrument i's span.
  std::pair<int, int> span(int instrument) const;
  /// Triangles of every instrument at each listed frame (shaft meshed kMeshedShaftLengthMm from the tip), one mesh:
  /// the union of the instruments' surfaces over those frames (world frame, mm).
  TriangleMesh surfaceMesh(const std::vector<int>& frames) const;
  /// Least distance of a point to any instrument's surface at any of the listed frames (mm; +inf when none).
  double distanceMm(const cv::Vec3d& pointMm, const std::vector<int>& frames) const;

private:
  /// One instrument's plan over its span: where it works and how it moves.
  struct Plan {
    int instrument = 0;
    int enter = 0, leave = 0;       ///< first and last frame in the scene
    cv::Vec2d anchorMm{0, 0};       ///< world XY the tip works around
    cv::Vec3d trocarMm{0, 0, 0};
    double wanderMm[2] = {0, 0}, wanderOmega[2] = {0, 0}, wanderPhase[2] = {0, 0};
    double hoverMm = 10, hoverOmega = 1, hoverPhase = 0;
    double jawOmega = 1, jawPhase = 0, rollOmega = 1, rollPhase = 0;
    const TissueSurface* highest = nullptr;  ///< the tissue at its highest, for the clearance
  };
  InstrumentPose pose(const Plan& plan, int index, double offsetS) const;
  std::vector<Plan> plans_;
  double fps_ = 30;
};

}  // namespace tissuemosaic::synthetic
