#include "RefinementParameters.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Refinement/RefinementParameterTable.h"

#include <opencv2/core/persistence.hpp>

namespace tissuemosaic {

void RefinementParameters::validate() const {
  refinementParameterTable().requireInRange(*this);
}

void RefinementParameters::write(cv::FileStorage& storage) const { refinementParameterTable().write(*this, storage); }

RefinementParameters RefinementParameters::read(const cv::FileNode& node) { return refinementParameterTable().readValidated(node); }

}  // namespace tissuemosaic
