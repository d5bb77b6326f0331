#include "Tracking/StereoFeatures.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kFeature{"feature"};

}  // namespace

void FeatureParameters::validate() const {
  kFeature.requireRange("maxFeatures", maxFeatures, 10, 100000);
  kFeature.requireRange("scaleFactor", scaleFactor, 1.01, 2.0);
  kFeature.requireRange("levels", levels, 1, 16);
  kFeature.requireRange("fastThreshold", fastThreshold, 1, 255);
  kFeature.requireRange("weakTextureFeatures", weakTextureFeatures, 0, 100000);
  kFeature.requireRange("weakFastThreshold", weakFastThreshold, 1, 255);
  kFeature.requireRange("edgeThresholdPx", edgeThresholdPx, 3, 100);
  kFeature.requireRange("maxHammingDistance", maxHammingDistance, 1, 256);
  kFeature.requireRange("candidatesPerFeature", candidatesPerFeature, 0, 8);
  kFeature.requireRange("voteBinPx", voteBinPx, 0.5, 1000);
  kFeature.requireRange("maxRefinementShiftPx", maxRefinementShiftPx, 0.1, 100);
}

void FeatureParameters::write(cv::FileStorage& storage) const {
  storage << "features" << "{";
  storage << "maxFeatures" << maxFeatures << "scaleFactor" << scaleFactor << "levels" << levels;
  storage << "fastThreshold" << fastThreshold << "edgeThresholdPx" << edgeThresholdPx;
  storage << "weakTextureFeatures" << weakTextureFeatures << "weakFastThreshold" << weakFastThreshold;
  storage << "maxHammingDistance" << maxHammingDistance << "candidatesPerFeature" << candidatesPerFeature;
  storage << "voteBinPx" << voteBinPx << "subPixelRefinement" << static_cast<int>(subPixelRefinement);
  storage << "maxRefinementShiftPx" << maxRefinementShiftPx;
  storage << "}";
}

FeatureParameters FeatureParameters::read(const cv::FileNode& node) {
  FeatureParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'features' parameter node must be a map");
  const auto key = [&node](const char* name, auto& value) { kFeature.readKey(node, name, value); };
  key("maxFeatures", p.maxFeatures);
  key("scaleFactor", p.scaleFactor);
  key("levels", p.levels);
  key("fastThreshold", p.fastThreshold);
  key("weakTextureFeatures", p.weakTextureFeatures);
  key("weakFastThreshold", p.weakFastThreshold);
  key("edgeThresholdPx", p.edgeThresholdPx);
  key("maxHammingDistance", p.maxHammingDistance);
  key("candidatesPerFeature", p.candidatesPerFeature);
  key("voteBinPx", p.voteBinPx);
  int subPixel = p.subPixelRefinement ? 1 : 0;
  key("subPixelRefinement", subPixel);
  if (subPixel != 0 && subPixel != 1) throw Error("feature parameter subPixelRefinement must be 0 or 1");
  p.subPixelRefinement = subPixel == 1;
  key("maxRefinementShiftPx", p.maxRefinementShiftPx);
  p.validate();
  return p;
}

}  // namespace tissuemosaic
