#include "Tracking/TrackingParameterTable.h"

namespace tissuemosaic {

const parameters::Table<TrackingParameters>& trackingParameterTable() {
  using parameters::number;
  using P = TrackingParameters;
  static const parameters::Table<P> table("tracking", "tracking", {
    number("inlierThresholdPx", &P::inlierThresholdPx, 0.01, 100, "px",
           "DynamicR1PPnP (paper III.B): a match whose reprojection error is at most H pixels is an inlier; it is also "
           "the knee of the re-weighting. Paper: 5 px."),
    number("candidateEta", &P::candidateEta, 1, 10, "",
           "DynamicR1PPnP: a further candidate match enters when its error is below eta * H (eta > 1). Paper: 2."),
    number("candidateRampIterations", &P::candidateRampIterations, 1, 100, "iterations",
           "DynamicR1PPnP: a newly admitted candidate's weight ramps in over T iterations. Paper: 5."),
    number("maxRansacIterations", &P::maxRansacIterations, 1, 100000, "",
           "Most control points (1-point RANSAC hypotheses) tried per solve."),
    number("ransacConfidence", &P::ransacConfidence, 0.5, 0.999999, "",
           "Stop once a better pose is this unlikely (1-point RANSAC bound)."),
    number("maxInnerIterations", &P::maxInnerIterations, 2, 1000, "iterations",
           "Most re-weighting iterations per hypothesis (not in the paper)."),
    number("minInliers", &P::minInliers, 4, 100000, "",
           "Fewer inliers than this: the solve reports failure (not in the paper)."),
    number("keyFrameMinInliers", &P::keyFrameMinInliers, 4, 100000, "",
           "Paper III.C: a key frame needs at least this many DynamicR1PPnP inliers. Paper: 50."),
    number("keyFrameMinGapFrames", &P::keyFrameMinGapFrames, 0, 100000, "frames",
           "Paper III.C: at least this many frames since the last key frame. Paper: 10."),
    number("keyFramePoseThreshold", &P::keyFramePoseThreshold, 0, 1e6, "",
           "Paper III.C: a new key frame when the pose difference ||dt|| (mm) + 20 min(||dE||, 2 pi - ||dE||) to the "
           "last key frame exceeds this. Paper: 10 for most videos (3 to 5 for slow, close scans)."),
    number("dynamicResidualPx", &P::dynamicResidualPx, 0, 100, "px",
           "Scene motion: most a moved feature's match may land off its projection before it scores as moved "
           "(docs/SCENE_MOTION.md); 0 switches the image test and the final fit off."),
    number("dynamicDisparityPx", &P::dynamicDisparityPx, 0, 1000, "px",
           "Scene motion: least disparity difference from the predicted depth that marks a feature as moved; 0 "
           "switches the depth test off."),
    number("dynamicScoreDecay", &P::dynamicScoreDecay, 0, 1, "",
           "Scene motion: a feature's motion score is multiplied by this per tracked frame."),
    number("dynamicExcludeScore", &P::dynamicExcludeScore, 0, 1, "",
           "Scene motion: features scoring above this do not steer the pose and are not stored."),
    number("priorStepMm", &P::priorStepMm, 0, 1000, "mm",
           "Motion prior: a pose within this of the one predicted from the last two frames continues that motion."),
    number("priorStepDeg", &P::priorStepDeg, 0, 180, "deg", "Motion prior: the same bound for rotation."),
    number("relocalisationMinInliers", &P::relocalisationMinInliers, 4, 100000, "",
           "A relocalised pose needs this many inliers."),
    number("relocalisationCandidates", &P::relocalisationCandidates, 0, 1000, "",
           "Stored key frames tried per lost frame."),
  });
  return table;
}

}  // namespace tissuemosaic
