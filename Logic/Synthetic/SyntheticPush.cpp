#include "SyntheticPush.h"

#include "TissueSurface.h"

#include <algorithm>
#include <cmath>

namespace tissuemosaic::synthetic {

namespace {

double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

/// The instrument moved by `shiftMm` along -axis (toward the tissue), its jaws closed by `closing`.
InstrumentPose moved(const InstrumentPose& pose, double shiftMm, double closing) {
  InstrumentPose out = pose;
  const cv::Vec3d offset = -shiftMm * pose.axis;
  out.tipMm += offset;
  out.shaft.fromMm += offset;  // the trocar end stays: the shaft slides through it
  for (Capsule& jaw : out.jaws) {
    const double length = cv::norm(jaw.toMm - jaw.fromMm);
    const cv::Vec3d open = (jaw.toMm - jaw.fromMm) / length;
    const cv::Vec3d direction = cv::normalize((1 - closing) * open + closing * (-pose.axis));
    jaw.fromMm = out.tipMm;
    jaw.toMm = out.tipMm + length * direction;
  }
  return out;
}

/// The jaws' lowest point (largest Z: +Z is into the tissue): the bottom of the lower end ball.
cv::Vec3d lowestPoint(const InstrumentPose& pose) {
  const Capsule& jaw = pose.jaws[0].toMm[2] >= pose.jaws[1].toMm[2] ? pose.jaws[0] : pose.jaws[1];
  return jaw.toMm + cv::Vec3d(0, 0, jaw.radiusMm);
}

/// How far the lowest point lies below the tissue (mm, negative above it).
double depthBelow(const InstrumentPose& pose, const TissueSurface& tissue) {
  const cv::Vec3d p = lowestPoint(pose);
  return p[2] - tissue.heightMm(p[0], p[1]);
}

}  // namespace

double pushDentOuterRadiusMm(double pushMm) {
  SurfaceSwell unitBand;  // the steepest slope of a swell 1 mm high over a 1 mm band
  unitBand.innerRadiusMm = 0;
  unitBand.outerRadiusMm = 1;
  return kPushInnerRadiusMm + std::max(6.5, pushMm * unitBand.maxWeightSlopePerMm() / kPushMaxWallSlope);
}

double pushWeight(double u) { return smoothstep(0.3, 0.4, u) * (1 - smoothstep(0.6, 0.7, u)); }

PressedInstrument pressInstrument(const InstrumentPose& pose, double weight, double pushMm, const TissueSurface& tissue) {
  PressedInstrument result;
  result.pose = pose;
  result.dent.innerRadiusMm = kPushInnerRadiusMm;
  result.dent.outerRadiusMm = pushDentOuterRadiusMm(pushMm);
  result.lowestMm = lowestPoint(pose);
  if (weight <= 0) return result;
  // The shift along the shaft at which the closed jaws' end touches the tissue: depthBelow grows with the shift
  // (the shaft points down at 40-60 degrees and the tissue is far flatter), so bisection finds it.
  const InstrumentPose closed = moved(pose, 0, 1);
  double lo = 0, hi = 1;
  while (depthBelow(moved(closed, hi, 0), tissue) < 0 && hi < 400) hi *= 2;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (depthBelow(moved(closed, mid, 0), tissue) < 0 ? lo : hi) = mid;
  }
  const double down = std::max(1e-3, -pose.axis[2]);  // cos of the shaft's angle to the view axis
  result.pose = moved(pose, weight * (hi + pushMm / down), weight);
  result.lowestMm = lowestPoint(result.pose);
  const double depth = depthBelow(result.pose, tissue);
  if (depth > 0) {
    const cv::Vec2d centre = tissue.materialXYMm(result.lowestMm[0], result.lowestMm[1]);
    result.dent.centreXMm = centre[0];
    result.dent.centreYMm = centre[1];
    result.dent.amplitudeMm = depth;
  }
  return result;
}

}  // namespace tissuemosaic::synthetic
