#pragma once
/// @file OptionNames.h
/// @brief The command line's spelling of the engine's parameters: an engine error about one value
/// (Core/ParameterError.h) says what is wrong without naming an option; the command line puts its option first.
#include "Core/ParameterError.h"

#include <string>

namespace tissuemosaic::cli {

/// The option that gives `parameter` (e.g. "--focal-px" for "focalPx"), or "" for one the command line does not know.
std::string optionFor(const std::string& parameter);
/// The error's message with its option first ("--focal-px: the focal length must be a positive number of pixels").
std::string withOptionName(const ParameterError& error);

}  // namespace tissuemosaic::cli
