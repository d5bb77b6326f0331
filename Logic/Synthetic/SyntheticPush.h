#pragma once
/// @file SyntheticPush.h
/// @brief Tissue pushed by an instrument (the in-vivo mode's --push-mm): in the middle of its span each instrument
/// closes its jaws, goes down along its shaft until their end touches the tissue and presses on by up to pushMm,
/// then lifts off again. The tissue under the jaws' end gives way: a dent (a SurfaceSwell into the tissue, +Z) whose
/// flat bottom holds the jaws' lowest point exactly, so that instrument and tissue touch without passing through
/// each other; it follows the jaws while they press. Without contact there is no dent.
#include "SurfaceSwell.h"
#include "SyntheticInstruments.h"

#include <utility>

namespace tissuemosaic::synthetic {

class TissueSurface;

/// The dent's flat bottom (about the closed jaws' width).
constexpr double kPushInnerRadiusMm = 1.5;
/// The dent's walls are no steeper than this (soft tissue dimples wide around a deep press): together with the
/// relief's own slope the views still see every point once.
constexpr double kPushMaxWallSlope = 0.35;
/// Where a dent pushMm deep fades out: at least 8 mm, wider for deeper presses (kPushMaxWallSlope).
double pushDentOuterRadiusMm(double pushMm);

/// How far into its press an instrument is at a fraction u of its span (0 at entry, 1 at exit): 0 before 0.3 and
/// after 0.7, 1 over [0.4, 0.6], smooth between.
double pushWeight(double spanFraction);

struct PressedInstrument {
  InstrumentPose pose;   ///< moved down its shaft, jaws closed by the weight
  SurfaceSwell dent;     ///< amplitudeMm >= 0 (into the tissue); 0 while the jaws do not reach the tissue
  cv::Vec3d lowestMm{0, 0, 0};  ///< the jaws' lowest point (the contact point while pressing)
};

/// `pose` (SyntheticInstruments, which keeps it clear of the tissue) pressed with `weight` in [0, 1]: the jaws close
/// by weight, the instrument goes down its shaft by weight x (the distance at which the jaws' end touches `tissue` +
/// pushMm along the shaft's slant), and where the jaws' lowest point is then below `tissue` the dent reaches it.
/// `tissue`: the tissue at that instant without any dent.
PressedInstrument pressInstrument(const InstrumentPose& pose, double weight, double pushMm, const TissueSurface& tissue);

}  // namespace tissuemosaic::synthetic
