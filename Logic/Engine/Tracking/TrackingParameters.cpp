#include "TrackingParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Tracking/TrackingParameterTable.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

void TrackingParameters::validate() const {
  trackingParameterTable().requireInRange(*this);
}

void TrackingParameters::write(cv::FileStorage& storage) const { trackingParameterTable().write(*this, storage); }

TrackingParameters TrackingParameters::read(const cv::FileNode& node) { return trackingParameterTable().readValidated(node); }

}  // namespace tissuemosaic
