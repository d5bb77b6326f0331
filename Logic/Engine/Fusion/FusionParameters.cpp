#include "FusionParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

#include <string>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kFusion{"fusion"};

}  // namespace

void FusionParameters::validate() const {
  kFusion.requireRange("truncationMm", truncationMm, 1e-3, 1000.0);
  kFusion.requireRange("maxWeight", maxWeight, 1.0, 1e6);
  kFusion.requireRange("maxNormalAngleDeg", maxNormalAngleDeg, 0.0, 180.0);
  kFusion.requireRange("coverageRadiusPx", coverageRadiusPx, 0, 8);
  kFusion.requireRange("colourFullWeightFraction", colourFullWeightFraction, 0.0, 1.0);
  kFusion.requireRange("colourMinWeight", colourMinWeight, 1e-3, 1.0);
  kFusion.requireRange("maxPoints", maxPoints, 1, 1 << 30);
  kFusion.requireRange("newPointStepPx", newPointStepPx, 1, 64);
  kFusion.requireRange("conflictMinWeight", conflictMinWeight, 0, 1000000);
  kFusion.requireRange("minDepthMm", minDepthMm, 0.0, 1e6);
  kFusion.requireRange("maxDepthMm", maxDepthMm, minDepthMm, 1e6);
  kFusion.requireRange("normalRadiusPx", normalRadiusPx, 1, 32);
  kFusion.requireRange("maxDepthJumpMm", maxDepthJumpMm, 1e-3, 1e6);
  kFusion.requireRange("motionPenalty", motionPenalty, 0.0, 1e6);
  kFusion.requireRange("motionMinThresholdMm", motionMinThresholdMm, 0.0, 1000.0);
  kFusion.requireRange("motionNoiseFactor", motionNoiseFactor, 0.0, 1000.0);
  kFusion.requireRange("occlusionMarginMm", occlusionMarginMm, 0.0, 1000.0);
  kFusion.requireRange("movedTissueRadiusMm", movedTissueRadiusMm, 0.0, 1000.0);
  kFusion.requireRange("markerRestFrames", markerRestFrames, 0, 1000000);  // counted in a float: exact to 2^24
  kFusion.requireRange("seenThroughFrames", seenThroughFrames, 0, 1000);
  kFusion.requireRange("motionMinAgreementShare", motionMinAgreementShare, 0.0, 1.0);
}

void FusionParameters::write(cv::FileStorage& storage) const {
  storage << "fusion" << "{";
  storage << "truncationMm" << truncationMm << "maxWeight" << maxWeight;
  storage << "maxNormalAngleDeg" << maxNormalAngleDeg << "coverageRadiusPx" << coverageRadiusPx;
  storage << "colourFullWeightFraction" << colourFullWeightFraction << "colourMinWeight" << colourMinWeight;
  storage << "maxPoints" << maxPoints << "newPointStepPx" << newPointStepPx << "conflictMinWeight" << conflictMinWeight;
  storage << "minDepthMm" << minDepthMm << "maxDepthMm" << maxDepthMm;
  storage << "normalRadiusPx" << normalRadiusPx << "maxDepthJumpMm" << maxDepthJumpMm;
  storage << "motionPenalty" << motionPenalty << "motionMinThresholdMm" << motionMinThresholdMm;
  storage << "motionNoiseFactor" << motionNoiseFactor << "occlusionMarginMm" << occlusionMarginMm
          << "movedTissueRadiusMm" << movedTissueRadiusMm << "markerRestFrames" << markerRestFrames
          << "seenThroughFrames" << seenThroughFrames;
  storage << "motionMinAgreementShare" << motionMinAgreementShare;
  storage << "deformation" << (deformation ? "on" : "off");
  storage << "}";
}

FusionParameters FusionParameters::read(const cv::FileNode& node) {
  FusionParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'fusion' parameter node must be a map");
  kFusion.readKey(node, "truncationMm", p.truncationMm);
  kFusion.readKey(node, "maxWeight", p.maxWeight);
  kFusion.readKey(node, "maxNormalAngleDeg", p.maxNormalAngleDeg);
  kFusion.readKey(node, "coverageRadiusPx", p.coverageRadiusPx);
  kFusion.readKey(node, "colourFullWeightFraction", p.colourFullWeightFraction);
  kFusion.readKey(node, "colourMinWeight", p.colourMinWeight);
  kFusion.readKey(node, "maxPoints", p.maxPoints);
  kFusion.readKey(node, "newPointStepPx", p.newPointStepPx);
  kFusion.readKey(node, "conflictMinWeight", p.conflictMinWeight);
  kFusion.readKey(node, "minDepthMm", p.minDepthMm);
  kFusion.readKey(node, "maxDepthMm", p.maxDepthMm);
  kFusion.readKey(node, "normalRadiusPx", p.normalRadiusPx);
  kFusion.readKey(node, "maxDepthJumpMm", p.maxDepthJumpMm);
  kFusion.readKey(node, "motionPenalty", p.motionPenalty);
  kFusion.readKey(node, "motionMinThresholdMm", p.motionMinThresholdMm);
  kFusion.readKey(node, "motionNoiseFactor", p.motionNoiseFactor);
  kFusion.readKey(node, "occlusionMarginMm", p.occlusionMarginMm);
  kFusion.readKey(node, "movedTissueRadiusMm", p.movedTissueRadiusMm);
  kFusion.readKey(node, "markerRestFrames", p.markerRestFrames);
  kFusion.readKey(node, "seenThroughFrames", p.seenThroughFrames);
  kFusion.readKey(node, "motionMinAgreementShare", p.motionMinAgreementShare);
  if (const cv::FileNode entry = node["deformation"]; !entry.empty()) {
    const std::string value = entry.isString() ? static_cast<std::string>(entry) : std::string();
    if (value != "on" && value != "off") throw Error("fusion parameter deformation must be \"on\" or \"off\"");
    p.deformation = value == "on";
  }
  p.validate();
  return p;
}

}  // namespace tissuemosaic
