#pragma once
/// @file ParameterTables.h
/// @brief Every parameter table of the reconstruction in words (Core/ParameterTable.h), node by node in the parameter
/// files' order: what `tissuemosaic params` lists.
#include "Core/ParameterTable.h"

#include <string>
#include <vector>

namespace tissuemosaic {

struct ParameterNodeDescription {
  std::string node;  ///< "stereo", "features", ...
  std::vector<parameters::FieldDescription> fields;
};

/// The nodes made from tables: stereo, features, tracking, refinement, fusion.
std::vector<ParameterNodeDescription> describeParameterTables();

}  // namespace tissuemosaic
