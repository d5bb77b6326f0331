#include "Refinement/RefinementParameterTable.h"

namespace tissuemosaic {

const parameters::Table<RefinementParameters>& refinementParameterTable() {
  using parameters::number;
  using P = RefinementParameters;
  static const parameters::Table<P> table("refinement", "refinement", {
    number("icpWeightFactor", &P::icpWeightFactor, 0, 1e6, "",
           "Paper III.D: beta = factor * feature residuals / ICP points balances bundle adjustment against "
           "point-to-plane ICP. Paper: 0.1."),
    number("icpTukeyMm", &P::icpTukeyMm, 0.001, 1000, "mm",
           "Paper III.D: point-to-plane residuals beyond this are outliers (Tukey's biweight)."),
    number("baHuberPx", &P::baHuberPx, 0.01, 1000, "px",
           "Huber's constant of the reprojection term (not in the paper): beyond it, linear."),
    number("icpSamples", &P::icpSamples, 0, 10000000, "points",
           "Model points used per key frame (an even subsample of those visible)."),
    number("alternations", &P::alternations, 1, 1000, "", "Point step + pose step rounds of the LM refinement."),
    number("lmIterations", &P::lmIterations, 1, 1000, "iterations", "LM iterations of each step (per point, per pose)."),
    number("initialLambda", &P::initialLambda, 1e-12, 1e6, "", "LM's lambda at the start."),
    number("maxMatchedKeyFrames", &P::maxMatchedKeyFrames, 0, 1000, "",
           "Earlier key frames matched at most when refining a key frame (the most overlapping first)."),
    number("minKeyFrameOverlap", &P::minKeyFrameOverlap, 0, 1, "",
           "An earlier key frame is a candidate when this share of its stored points projects into the view."),
    number("minKeyFrameInliers", &P::minKeyFrameInliers, 4, 100000, "",
           "DynamicR1PPnP inliers for a match with an earlier key frame to count."),
    number("minFrameInliers", &P::minFrameInliers, 4, 100000, "",
           "DynamicR1PPnP inliers for an intermediate frame to join the bundle adjustment."),
    number("maxIntermediateFrames", &P::maxIntermediateFrames, 0, 1000, "frames",
           "Intermediate frames kept per key frame (thinned evenly beyond)."),
    number("maxSolveHypotheses", &P::maxSolveHypotheses, 1, 100000, "",
           "DynamicR1PPnP hypotheses tried at most per match with an earlier key frame or an intermediate frame."),
    number("guidedSearchRadiusPx", &P::guidedSearchRadiusPx, 0, 10000, "px",
           "Matching guided by the tracked poses looks this far from where a point projects; 0: all descriptors."),
    number("storedFeaturesPerKeyFrame", &P::storedFeaturesPerKeyFrame, 4, 1000000, "",
           "Strongest features with depth kept per key frame for later matching."),
    number("maxStoredKeyFrames", &P::maxStoredKeyFrames, 1, 10000000, "",
           "Beyond this the oldest key frame is forgotten (memory bound of a long scan)."),
    number("minIcpPoints", &P::minIcpPoints, 1, 10000000, "points", "Fewer valid model points than this: no ICP term."),
    number("maxCorrectionMm", &P::maxCorrectionMm, 0, 1e6, "mm",
           "A refined pose farther than this from the tracked one is rejected."),
    number("maxCorrectionDeg", &P::maxCorrectionDeg, 0, 180, "deg", "The same bound for rotation."),
  });
  return table;
}

}  // namespace tissuemosaic
