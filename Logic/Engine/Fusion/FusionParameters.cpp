#include "FusionParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Fusion/FusionParameterTable.h"

#include <opencv2/core/persistence.hpp>

#include <string>

namespace tissuemosaic {

namespace {

constexpr parameters::Group kFusion{"fusion"};

}  // namespace

void FusionParameters::validate() const {
  fusionParameterTable().requireInRange(*this);
  // The rule between fields.
  kFusion.requireRange("maxDepthMm", maxDepthMm, minDepthMm, 1e6);
}

void FusionParameters::write(cv::FileStorage& storage) const { fusionParameterTable().write(*this, storage); }

FusionParameters FusionParameters::read(const cv::FileNode& node) { return fusionParameterTable().readValidated(node); }

}  // namespace tissuemosaic
