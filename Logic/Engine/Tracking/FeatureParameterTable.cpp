#include "Tracking/FeatureParameterTable.h"

namespace tissuemosaic {

const parameters::Table<FeatureParameters>& featureParameterTable() {
  using parameters::number;
  using P = FeatureParameters;
  static const parameters::Table<P> table("features", "feature", {
    number("maxFeatures", &P::maxFeatures, 10, 100000, "", "ORB features detected per frame at most."),
    number("scaleFactor", &P::scaleFactor, 1.01, 2.0, "", "ORB pyramid scale between levels."),
    number("levels", &P::levels, 1, 16, "", "ORB pyramid levels."),
    number("fastThreshold", &P::fastThreshold, 1, 255, "grey",
           "FAST corner threshold; low: tissue has weak texture."),
    number("edgeThresholdPx", &P::edgeThresholdPx, 3, 100, "px", "Border without features (>= the ORB patch radius)."),
    number("weakTextureFeatures", &P::weakTextureFeatures, 0, 100000, "",
           "Fewer features than this: the frame is searched again with weakFastThreshold."),
    number("weakFastThreshold", &P::weakFastThreshold, 1, 255, "grey", "The FAST threshold of weak-texture frames."),
    number("maxHammingDistance", &P::maxHammingDistance, 1, 256, "bits",
           "Descriptor matches farther than this (of 256 bits) are dropped."),
    number("candidatesPerFeature", &P::candidatesPerFeature, 0, 8, "",
           "Further descriptor matches offered to DynamicR1PPnP per feature (k - 1)."),
    number("voteBinPx", &P::voteBinPx, 0.5, 1000, "px", "Histogram-voting bin size."),
    number("subPixelRefinement", &P::subPixelRefinement, 0, 1, "", "1: matches are refined to sub-pixel positions."),
    number("maxRefinementShiftPx", &P::maxRefinementShiftPx, 0.1, 100, "px",
           "A refinement moving a match farther than this is ignored."),
  });
  return table;
}

}  // namespace tissuemosaic
