#pragma once
/// @file StereoParameterTable.h
/// @brief The fields of StereoParameters (Core/ParameterTable.h): file key, limits, unit and doc of each, in the
/// parameter file's order. validate(), the "stereo" node's read and write, the stereo panel's spin boxes and the
/// command line's parameter list come from it: a new stereo parameter is a member with its default plus one row.
#include "Core/ParameterTable.h"
#include "Stereo/StereoParameters.h"

namespace tissuemosaic {

/// Most disparity candidates a range may hold (--disparities of the bench commands too).
constexpr int kMaxDisparityCount = 1024;

const parameters::Table<StereoParameters>& stereoParameterTable();

}  // namespace tissuemosaic
