#pragma once
/// @file TrackingParameterTable.h
/// @brief The fields of TrackingParameters, the camera tracking (DynamicR1PPnP, key frames, scene motion, relocalisation) (Core/ParameterTable.h): file key, limits, unit and doc of each, in the
/// parameter file's order. A new parameter is a member with its default plus one row.
#include "Core/ParameterTable.h"
#include "Tracking/TrackingParameters.h"

namespace tissuemosaic {

const parameters::Table<TrackingParameters>& trackingParameterTable();

}  // namespace tissuemosaic
