#pragma once
/// @file FeatureParameterTable.h
/// @brief The fields of FeatureParameters, the ORB features and histogram voting (Core/ParameterTable.h): file key, limits, unit and doc of each, in the
/// parameter file's order. A new parameter is a member with its default plus one row.
#include "Core/ParameterTable.h"
#include "Tracking/StereoFeatures.h"

namespace tissuemosaic {

const parameters::Table<FeatureParameters>& featureParameterTable();

}  // namespace tissuemosaic
