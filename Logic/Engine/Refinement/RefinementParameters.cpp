#include "RefinementParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

template <class T>
void requireRange(const char* name, T value, T low, T high) {
  parameters::requireRange("refinement", name, value, low, high);
}

template <class T>
void readKey(const cv::FileNode& node, const char* name, T& value) {
  parameters::readKey("refinement", node, name, value);
}

}  // namespace

void RefinementParameters::validate() const {
  requireRange("icpWeightFactor", icpWeightFactor, 0.0, 1e6);
  requireRange("icpTukeyMm", icpTukeyMm, 0.001, 1000.0);
  requireRange("baHuberPx", baHuberPx, 0.01, 1000.0);
  requireRange("icpSamples", icpSamples, 0, 10000000);
  requireRange("alternations", alternations, 1, 1000);
  requireRange("lmIterations", lmIterations, 1, 1000);
  requireRange("initialLambda", initialLambda, 1e-12, 1e6);
  requireRange("maxMatchedKeyFrames", maxMatchedKeyFrames, 0, 1000);
  requireRange("minKeyFrameOverlap", minKeyFrameOverlap, 0.0, 1.0);
  requireRange("minKeyFrameInliers", minKeyFrameInliers, 4, 100000);
  requireRange("minFrameInliers", minFrameInliers, 4, 100000);
  requireRange("maxIntermediateFrames", maxIntermediateFrames, 0, 1000);
  requireRange("maxSolveHypotheses", maxSolveHypotheses, 1, 100000);
  requireRange("guidedSearchRadiusPx", guidedSearchRadiusPx, 0.0, 10000.0);
  requireRange("storedFeaturesPerKeyFrame", storedFeaturesPerKeyFrame, 4, 1000000);
  requireRange("maxStoredKeyFrames", maxStoredKeyFrames, 1, 10000000);
  requireRange("minIcpPoints", minIcpPoints, 1, 10000000);
  requireRange("maxCorrectionMm", maxCorrectionMm, 0.0, 1e6);
  requireRange("maxCorrectionDeg", maxCorrectionDeg, 0.0, 180.0);
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
  readKey(node, "icpWeightFactor", p.icpWeightFactor);
  readKey(node, "icpTukeyMm", p.icpTukeyMm);
  readKey(node, "baHuberPx", p.baHuberPx);
  readKey(node, "icpSamples", p.icpSamples);
  readKey(node, "alternations", p.alternations);
  readKey(node, "lmIterations", p.lmIterations);
  readKey(node, "initialLambda", p.initialLambda);
  readKey(node, "maxMatchedKeyFrames", p.maxMatchedKeyFrames);
  readKey(node, "minKeyFrameOverlap", p.minKeyFrameOverlap);
  readKey(node, "minKeyFrameInliers", p.minKeyFrameInliers);
  readKey(node, "minFrameInliers", p.minFrameInliers);
  readKey(node, "maxIntermediateFrames", p.maxIntermediateFrames);
  readKey(node, "maxSolveHypotheses", p.maxSolveHypotheses);
  readKey(node, "guidedSearchRadiusPx", p.guidedSearchRadiusPx);
  readKey(node, "storedFeaturesPerKeyFrame", p.storedFeaturesPerKeyFrame);
  readKey(node, "maxStoredKeyFrames", p.maxStoredKeyFrames);
  readKey(node, "minIcpPoints", p.minIcpPoints);
  readKey(node, "maxCorrectionMm", p.maxCorrectionMm);
  readKey(node, "maxCorrectionDeg", p.maxCorrectionDeg);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
