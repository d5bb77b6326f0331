#pragma once
/// @file FusionParameterTable.h
/// @brief The fields of FusionParameters, the fusion and surface measurement (Core/ParameterTable.h): file key, limits, unit and doc of each, in the
/// parameter file's order. A new parameter is a member with its default plus one row.
#include "Core/ParameterTable.h"
#include "Fusion/FusionParameters.h"

namespace tissuemosaic {

const parameters::Table<FusionParameters>& fusionParameterTable();

}  // namespace tissuemosaic
