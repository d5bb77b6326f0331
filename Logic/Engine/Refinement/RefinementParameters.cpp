#include "RefinementParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kRefinement{"refinement"};

}  // namespace

void RefinementParameters::validate() const {
  kRefinement.requireRange("icpWeightFactor", icpWeightFactor, 0.0, 1e6);
  kRefinement.requireRange("icpTukeyMm", icpTukeyMm, 0.001, 1000.0);
  kRefinement.requireRange("baHuberPx", baHuberPx, 0.01, 1000.0);
  kRefinement.requireRange("icpSamples", icpSamples, 0, 10000000);
  kRefinement.requireRange("alternations", alternations, 1, 1000);
  kRefinement.requireRange("lmIterations", lmIterations, 1, 1000);
  kRefinement.requireRange("initialLambda", initialLambda, 1e-12, 1e6);
  kRefinement.requireRange("maxMatchedKeyFrames", maxMatchedKeyFrames, 0, 1000);
  kRefinement.requireRange("minKeyFrameOverlap", minKeyFrameOverlap, 0.0, 1.0);
  kRefinement.requireRange("minKeyFrameInliers", minKeyFrameInliers, 4, 100000);
  kRefinement.requireRange("minFrameInliers", minFrameInliers, 4, 100000);
  kRefinement.requireRange("maxIntermediateFrames", maxIntermediateFrames, 0, 1000);
  kRefinement.requireRange("maxSolveHypotheses", maxSolveHypotheses, 1, 100000);
  kRefinement.requireRange("guidedSearchRadiusPx", guidedSearchRadiusPx, 0.0, 10000.0);
  kRefinement.requireRange("storedFeaturesPerKeyFrame", storedFeaturesPerKeyFrame, 4, 1000000);
  kRefinement.requireRange("maxStoredKeyFrames", maxStoredKeyFrames, 1, 10000000);
  kRefinement.requireRange("minIcpPoints", minIcpPoints, 1, 10000000);
  kRefinement.requireRange("maxCorrectionMm", maxCorrectionMm, 0.0, 1e6);
  kRefinement.requireRange("maxCorrectionDeg", maxCorrectionDeg, 0.0, 180.0);
}

void RefinementParameters::write(cv::FileStorage& storage) const {
  storage << "refinement" << "{";
  storage << "icpWeightFactor" << icpWeightFactor << "icpTukeyMm" << icpTukeyMm << "baHuberPx" << baHuberPx;
  storage << "icpSamples" << icpSamples << "alternations" << alternations << "lmIterations" << lmIterations;
  storage << "initialLambda" << initialLambda << "maxMatchedKeyFrames" << maxMatchedKeyFrames;
  storage << "minKeyFrameOverlap" << minKeyFrameOverlap << "minKeyFrameInliers" << minKeyFrameInliers;
  storage << "minFrameInliers" << minFrameInliers << "maxIntermediateFrames" << maxIntermediateFrames;
  storage << "maxSolveHypotheses" << maxSolveHypotheses << "guidedSearchRadiusPx" << guidedSearchRadiusPx;
  storage << "storedFeaturesPerKeyFrame" << storedFeaturesPerKeyFrame << "maxStoredKeyFrames" << maxStoredKeyFrames;
  storage << "minIcpPoints" << minIcpPoints << "maxCorrectionMm" << maxCorrectionMm;
  storage << "maxCorrectionDeg" << maxCorrectionDeg;
  storage << "}";
}

RefinementParameters RefinementParameters::read(const cv::FileNode& node) {
  RefinementParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'refinement' parameter node must be a map");
  kRefinement.readKey(node, "icpWeightFactor", p.icpWeightFactor);
  kRefinement.readKey(node, "icpTukeyMm", p.icpTukeyMm);
  kRefinement.readKey(node, "baHuberPx", p.baHuberPx);
  kRefinement.readKey(node, "icpSamples", p.icpSamples);
  kRefinement.readKey(node, "alternations", p.alternations);
  kRefinement.readKey(node, "lmIterations", p.lmIterations);
  kRefinement.readKey(node, "initialLambda", p.initialLambda);
  kRefinement.readKey(node, "maxMatchedKeyFrames", p.maxMatchedKeyFrames);
  kRefinement.readKey(node, "minKeyFrameOverlap", p.minKeyFrameOverlap);
  kRefinement.readKey(node, "minKeyFrameInliers", p.minKeyFrameInliers);
  kRefinement.readKey(node, "minFrameInliers", p.minFrameInliers);
  kRefinement.readKey(node, "maxIntermediateFrames", p.maxIntermediateFrames);
  kRefinement.readKey(node, "maxSolveHypotheses", p.maxSolveHypotheses);
  kRefinement.readKey(node, "guidedSearchRadiusPx", p.guidedSearchRadiusPx);
  kRefinement.readKey(node, "storedFeaturesPerKeyFrame", p.storedFeaturesPerKeyFrame);
  kRefinement.readKey(node, "maxStoredKeyFrames", p.maxStoredKeyFrames);
  kRefinement.readKey(node, "minIcpPoints", p.minIcpPoints);
  kRefinement.readKey(node, "maxCorrectionMm", p.maxCorrectionMm);
  kRefinement.readKey(node, "maxCorrectionDeg", p.maxCorrectionDeg);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
