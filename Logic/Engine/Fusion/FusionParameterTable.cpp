#include "Fusion/FusionParameterTable.h"

namespace tissuemosaic {
namespace {

const char* switchName(bool on) { return on ? "on" : "off"; }

}  // namespace

const parameters::Table<FusionParameters>& fusionParameterTable() {
  using parameters::choice;
  using parameters::number;
  using P = FusionParameters;
  static const parameters::Table<P> table("fusion", "fusion", {
    number("truncationMm", &P::truncationMm, 1e-3, 1000, "mm",
           "Paper III.E: a measurement within this distance along the ray of a model point is merged into it "
           "(running average); farther ones add new points."),
    number("maxWeight", &P::maxWeight, 1, 1e6, "", "Running-average cap: older observations keep at most this weight."),
    number("maxNormalAngleDeg", &P::maxNormalAngleDeg, 0, 180, "deg",
           "A model point merges only if its normal and the measured one differ less."),
    number("coverageRadiusPx", &P::coverageRadiusPx, 0, 8, "px",
           "A measured pixel counts as covered when an agreeing model point lands this close (no second layer)."),
    number("colourFullWeightFraction", &P::colourFullWeightFraction, 0, 1, "",
           "Full colour weight within this fraction of the half-diagonal from the image centre."),
    number("colourMinWeight", &P::colourMinWeight, 1e-3, 1, "",
           "Paper III.E: the colour weight falls from 1 in the image centre to this at the corners, so the model "
           "takes colours from where the scope's light is even."),
    number("maxPoints", &P::maxPoints, 1, 1 << 30, "points",
           "New points are refused once the model holds this many (memory bound of a long scan)."),
    number("newPointStepPx", &P::newPointStepPx, 1, 64, "px",
           "New model points at every k-th pixel in x and y (1: the video's full resolution, as the paper)."),
    number("conflictMinWeight", &P::conflictMinWeight, 0, 1000000, "observations",
           "A measurement that contradicts a model point seen at least this many times is taken as a stereo outlier "
           "and not added (0: off). Keeps long scans free of piled-up outliers."),
    number("minDepthMm", &P::minDepthMm, 0, 1e6, "mm", "Measurements nearer than this are not fused."),
    number("maxDepthMm", &P::maxDepthMm, 0, 1e6, "mm", "Measurements farther than this are not fused."),
    number("normalRadiusPx", &P::normalRadiusPx, 1, 32, "px", "Normals from neighbours this many pixels away."),
    number("maxDepthJumpMm", &P::maxDepthJumpMm, 1e-3, 1e6, "mm",
           "No normal where a neighbour's depth differs by more than this."),
    number("motionPenalty", &P::motionPenalty, 0, 1e6, "",
           "Weight a model point loses per frame that contradicts it; at 0 it leaves the model. 0: off."),
    number("motionMinThresholdMm", &P::motionMinThresholdMm, 0, 1000, "mm",
           "A frame contradicts a point beyond max(this, motionNoiseFactor x its median depth difference)."),
    number("motionNoiseFactor", &P::motionNoiseFactor, 0, 1000, "", "See motionMinThresholdMm."),
    number("occlusionMarginMm", &P::occlusionMarginMm, 0, 1000, "mm",
           "A measurement more than this in front of a point passes in front of it (an instrument)."),
    number("movedTissueRadiusMm", &P::movedTissueRadiusMm, 0, 1000, "mm",
           "A point that left by motion evidence keeps key frames from fusing within this of it."),
    // Counted in a float: exact to 2^24.
    number("markerRestFrames", &P::markerRestFrames, 0, 1000000, "frames",
           "Frames in a row that put a marker's tissue back (or elsewhere) before it is live again (or retired)."),
    number("seenThroughFrames", &P::seenThroughFrames, 0, 1000, "frames",
           "A once-fused point that this many frames in a row see through leaves the model. 0: off."),
    number("motionMinAgreementShare", &P::motionMinAgreementShare, 0, 1, "",
           "Frames whose share of depths within 1 mm of the model is below this give no motion evidence."),
    choice("deformation", &P::deformation, {true, false}, switchName,
           "Fit the deformation graph over the model to every tracked frame (docs/DEFORMATION.md)."),
  });
  return table;
}

}  // namespace tissuemosaic
