#include "FusionParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

template <class T>
void requireRange(const char* name, T value, T low, T high) {
  parameters::requireRange("fusion", name, value, low, high);
}

template <class T>
void readKey(const cv::FileNode& node, const char* name, T& value) {
  parameters::readKey("fusion", node, name, value);
}

}  // namespace

void FusionParameters::validate() const {
  requireRange("truncationMm", truncationMm, 1e-3, 1000.0);
  requireRange("maxWeight", maxWeight, 1.0, 1e6);
  requireRange("maxNormalAngleDeg", maxNormalAngleDeg, 0.0, 180.0);
  requireRange("coverageRadiusPx", coverageRadiusPx, 0, 8);
  requireRange("colourFullWeightFraction", colourFullWeightFraction, 0.0, 1.0);
  requireRange("colourMinWeight", colourMinWeight, 1e-3, 1.0);
  requireRange("maxPoints", maxPoints, 1, 1 << 30);
  requireRange("newPointStepPx", newPointStepPx, 1, 64);
  requireRange("conflictMinWeight", conflictMinWeight, 0, 1000000);
  requireRange("minDepthMm", minDepthMm, 0.0, 1e6);
  requireRange("maxDepthMm", maxDepthMm, minDepthMm, 1e6);
  requireRange("normalRadiusPx", normalRadiusPx, 1, 32);
  requireRange("maxDepthJumpMm", maxDepthJumpMm, 1e-3, 1e6);
  requireRange("motionPenalty", motionPenalty, 0.0, 1e6);
  requireRange("motionMinThresholdMm", motionMinThresholdMm, 0.0, 1000.0);
  requireRange("motionNoiseFactor", motionNoiseFactor, 0.0, 1000.0);
  requireRange("occlusionMarginMm", occlusionMarginMm, 0.0, 1000.0);
  requireRange("movedTissueRadiusMm", movedTissueRadiusMm, 0.0, 1000.0);
  requireRange("motionMinAgreementShare", motionMinAgreementShare, 0.0, 1.0);
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
          << "movedTissueRadiusMm" << movedTissueRadiusMm;
  storage << "motionMinAgreementShare" << motionMinAgreementShare;
  storage << "}";
}

FusionParameters FusionParameters::read(const cv::FileNode& node) {
  FusionParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'fusion' parameter node must be a map");
  readKey(node, "truncationMm", p.truncationMm);
  readKey(node, "maxWeight", p.maxWeight);
  readKey(node, "maxNormalAngleDeg", p.maxNormalAngleDeg);
  readKey(node, "coverageRadiusPx", p.coverageRadiusPx);
  readKey(node, "colourFullWeightFraction", p.colourFullWeightFraction);
  readKey(node, "colourMinWeight", p.colourMinWeight);
  readKey(node, "maxPoints", p.maxPoints);
  readKey(node, "newPointStepPx", p.newPointStepPx);
  readKey(node, "conflictMinWeight", p.conflictMinWeight);
  readKey(node, "minDepthMm", p.minDepthMm);
  readKey(node, "maxDepthMm", p.maxDepthMm);
  readKey(node, "normalRadiusPx", p.normalRadiusPx);
  readKey(node, "maxDepthJumpMm", p.maxDepthJumpMm);
  readKey(node, "motionPenalty", p.motionPenalty);
  readKey(node, "motionMinThresholdMm", p.motionMinThresholdMm);
  readKey(node, "motionNoiseFactor", p.motionNoiseFactor);
  readKey(node, "occlusionMarginMm", p.occlusionMarginMm);
  readKey(node, "movedTissueRadiusMm", p.movedTissueRadiusMm);
  readKey(node, "motionMinAgreementShare", p.motionMinAgreementShare);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
