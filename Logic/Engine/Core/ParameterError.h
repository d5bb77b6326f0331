#pragma once
/// @file ParameterError.h
/// @brief An Error about one value the caller gave the engine (the focal length of a rectified rig, the device, a
/// calibration's second file). The message says what is wrong in the engine's words and names no front end's option;
/// parameter() names the value as the engine's API does ("focalPx"), so that each front end can put its own spelling
/// of it before the message: the command line its option (`--focal-px: ...`, Module/Cli/OptionNames.cpp), Python its
/// argument (`focal_px: ...`).
#include "Core/Error.h"

#include <string>
#include <utility>

namespace tissuemosaic {

class ParameterError : public Error {
public:
  ParameterError(std::string parameter, const std::string& message)
      : Error(message), parameter_(std::move(parameter)) {}
  const std::string& parameter() const noexcept { return parameter_; }

private:
  std::string parameter_;
};

/// Throws ParameterError(parameter, message) when condition is false.
inline void requireParameter(bool condition, const char* parameter, const std::string& message) {
  if (!condition) throw ParameterError(parameter, message);
}

}  // namespace tissuemosaic
