#include "Tracking/StereoFeatures.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Tracking/FeatureParameterTable.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

void FeatureParameters::validate() const {
  featureParameterTable().requireInRange(*this);
}

void FeatureParameters::write(cv::FileStorage& storage) const { featureParameterTable().write(*this, storage); }

FeatureParameters FeatureParameters::read(const cv::FileNode& node) { return featureParameterTable().readValidated(node); }

}  // namespace tissuemosaic
