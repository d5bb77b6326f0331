#include "TrackingParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kTracking{"tracking"};

}  // namespace

void TrackingParameters::validate() const {
  kTracking.requireRange("inlierThresholdPx", inlierThresholdPx, 0.01, 100.0);
  kTracking.requireRange("candidateEta", candidateEta, 1.0, 10.0);
  kTracking.requireRange("candidateRampIterations", candidateRampIterations, 1, 100);
  kTracking.requireRange("maxRansacIterations", maxRansacIterations, 1, 100000);
  kTracking.requireRange("ransacConfidence", ransacConfidence, 0.5, 0.999999);
  kTracking.requireRange("maxInnerIterations", maxInnerIterations, 2, 1000);
  kTracking.requireRange("minInliers", minInliers, 4, 100000);
  kTracking.requireRange("keyFrameMinInliers", keyFrameMinInliers, 4, 100000);
  kTracking.requireRange("keyFrameMinGapFrames", keyFrameMinGapFrames, 0, 100000);
  kTracking.requireRange("keyFramePoseThreshold", keyFramePoseThreshold, 0.0, 1e6);
  kTracking.requireRange("dynamicResidualPx", dynamicResidualPx, 0.0, 100.0);
  kTracking.requireRange("dynamicDisparityPx", dynamicDisparityPx, 0.0, 1000.0);
  kTracking.requireRange("dynamicScoreDecay", dynamicScoreDecay, 0.0, 1.0);
  kTracking.requireRange("dynamicExcludeScore", dynamicExcludeScore, 0.0, 1.0);
  kTracking.requireRange("priorStepMm", priorStepMm, 0.0, 1000.0);
  kTracking.requireRange("priorStepDeg", priorStepDeg, 0.0, 180.0);
  kTracking.requireRange("relocalisationMinInliers", relocalisationMinInliers, 4, 100000);
  kTracking.requireRange("relocalisationCandidates", relocalisationCandidates, 0, 1000);
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
  storage << "dynamicExcludeScore" << dynamicExcludeScore  << "priorStepMm" << priorStepMm
          << "priorStepDeg" << priorStepDeg << "relocalisationMinInliers" << relocalisationMinInliers;
  storage << "relocalisationCandidates" << relocalisationCandidates;
  storage << "}";
}

TrackingParameters TrackingParameters::read(const cv::FileNode& node) {
  TrackingParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'tracking' parameter node must be a map");
  kTracking.readKey(node, "inlierThresholdPx", p.inlierThresholdPx);
  kTracking.readKey(node, "candidateEta", p.candidateEta);
  kTracking.readKey(node, "candidateRampIterations", p.candidateRampIterations);
  kTracking.readKey(node, "maxRansacIterations", p.maxRansacIterations);
  kTracking.readKey(node, "ransacConfidence", p.ransacConfidence);
  kTracking.readKey(node, "maxInnerIterations", p.maxInnerIterations);
  kTracking.readKey(node, "minInliers", p.minInliers);
  kTracking.readKey(node, "keyFrameMinInliers", p.keyFrameMinInliers);
  kTracking.readKey(node, "keyFrameMinGapFrames", p.keyFrameMinGapFrames);
  kTracking.readKey(node, "keyFramePoseThreshold", p.keyFramePoseThreshold);
  kTracking.readKey(node, "dynamicResidualPx", p.dynamicResidualPx);
  kTracking.readKey(node, "dynamicDisparityPx", p.dynamicDisparityPx);
  kTracking.readKey(node, "dynamicScoreDecay", p.dynamicScoreDecay);
  kTracking.readKey(node, "dynamicExcludeScore", p.dynamicExcludeScore);
  kTracking.readKey(node, "priorStepMm", p.priorStepMm);
  kTracking.readKey(node, "priorStepDeg", p.priorStepDeg);
  kTracking.readKey(node, "relocalisationMinInliers", p.relocalisationMinInliers);
  kTracking.readKey(node, "relocalisationCandidates", p.relocalisationCandidates);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
