#pragma once
/// @file RefinementParameterTable.h
/// @brief The fields of RefinementParameters, the key-frame refinement (Core/ParameterTable.h): file key, limits, unit and doc of each, in the
/// parameter file's order. A new parameter is a member with its default plus one row.
#include "Core/ParameterTable.h"
#include "Refinement/RefinementParameters.h"

namespace tissuemosaic {

const parameters::Table<RefinementParameters>& refinementParameterTable();

}  // namespace tissuemosaic
