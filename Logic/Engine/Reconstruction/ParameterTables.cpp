#include "Reconstruction/ParameterTables.h"

#include "Fusion/FusionParameterTable.h"
#include "Refinement/RefinementParameterTable.h"
#include "Stereo/StereoParameterTable.h"
#include "Tracking/FeatureParameterTable.h"
#include "Tracking/TrackingParameterTable.h"

namespace tissuemosaic {

std::vector<ParameterNodeDescription> describeParameterTables() {
  return {{stereoParameterTable().node(), stereoParameterTable().describe()},
          {featureParameterTable().node(), featureParameterTable().describe()},
          {trackingParameterTable().node(), trackingParameterTable().describe()},
          {refinementParameterTable().node(), refinementParameterTable().describe()},
          {fusionParameterTable().node(), fusionParameterTable().describe()}};
}

}  // namespace tissuemosaic
