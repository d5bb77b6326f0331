#include "TrackingParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

template <class T>
void requireRange(const char* name, T value, T low, T high) {
  parameters::requireRange("tracking", name, value, low, high);
}

template <class T>
void readKey(const cv::FileNode& node, const char* name, T& value) {
  parameters::readKey("tracking", node, name, value);
}

}  // namespace

void TrackingParameters::validate() const {
  requireRange("inlierThresholdPx", inlierThresholdPx, 0.01, 100.0);
  requireRange("candidateEta", candidateEta, 1.0, 10.0);
  requireRange("candidateRampIterations", candidateRampIterations, 1, 100);
  requireRange("maxRansacIterations", maxRansacIterations, 1, 100000);
  requireRange("ransacConfidence", ransacConfidence, 0.5, 0.999999);
  requireRange("maxInnerIterations", maxInnerIterations, 2, 1000);
  requireRange("minInliers", minInliers, 4, 100000);
  requireRange("keyFrameMinInliers", keyFrameMinInliers, 4, 100000);
  requireRange("keyFrameMinGapFrames", keyFrameMinGapFrames, 0, 100000);
  requireRange("keyFramePoseThreshold", keyFramePoseThreshold, 0.0, 1e6);
  requireRange("dynamicResidualPx", dynamicResidualPx, 0.0, 100.0);
  requireRange("dynamicDisparityPx", dynamicDisparityPx, 0.0, 1000.0);
  requireRange("dynamicScoreDecay", dynamicScoreDecay, 0.0, 1.0);
  requireRange("dynamicExcludeScore", dynamicExcludeScore, 0.0, 1.0);
  requireRange("relocalisationMinInliers", relocalisationMinInliers, 4, 100000);
  requireRange("relocalisationCandidates", relocalisationCandidates, 0, 1000);
}

void TrackingParameters::write(cv::FileStorage& storage) const {
  storage << "tracking" << "{";
  storage << "inlierThresholdPx" << inlierThresholdPx << "candidateEta" << candidateEta;
  storage << "candidateRampIterations" << candidateRampIterations << "maxRansacIterations" << maxRansacIterations;
  storage << "ransacConfidence" << ransacConfidence << "maxInnerIterations" << maxInnerIterations;
  storage << "minInliers" << minInliers << "keyFrameMinInliers" << keyFrameMinInliers;
  storage << "keyFrameMinGapFrames" << keyFrameMinGapFrames << "keyFramePoseThreshold" << keyFramePoseThreshold;
  storage << "dynamicResidualPx" << dynamicResidualPx << "dynamicDisparityPx" << dynamicDisparityPx;
  storage << "dynamicScoreDecay" << dynamicScoreDecay;
  storage << "dynamicExcludeScore" << dynamicExcludeScore << "relocalisationMinInliers" << relocalisationMinInliers;
  storage << "relocalisationCandidates" << relocalisationCandidates;
  storage << "}";
}

TrackingParameters TrackingParameters::read(const cv::FileNode& node) {
  TrackingParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'tracking' parameter node must be a map");
  readKey(node, "inlierThresholdPx", p.inlierThresholdPx);
  readKey(node, "candidateEta", p.candidateEta);
  readKey(node, "candidateRampIterations", p.candidateRampIterations);
  readKey(node, "maxRansacIterations", p.maxRansacIterations);
  readKey(node, "ransacConfidence", p.ransacConfidence);
  readKey(node, "maxInnerIterations", p.maxInnerIterations);
  readKey(node, "minInliers", p.minInliers);
  readKey(node, "keyFrameMinInliers", p.keyFrameMinInliers);
  readKey(node, "keyFrameMinGapFrames", p.keyFrameMinGapFrames);
  readKey(node, "keyFramePoseThreshold", p.keyFramePoseThreshold);
  readKey(node, "dynamicResidualPx", p.dynamicResidualPx);
  readKey(node, "dynamicDisparityPx", p.dynamicDisparityPx);
  readKey(node, "dynamicScoreDecay", p.dynamicScoreDecay);
  readKey(node, "dynamicExcludeScore", p.dynamicExcludeScore);
  readKey(node, "relocalisationMinInliers", p.relocalisationMinInliers);
  readKey(node, "relocalisationCandidates", p.relocalisationCandidates);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
