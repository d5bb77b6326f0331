#pragma once
/// @file ErrorText.h
/// @brief The message of the tissuemosaic::Error an action throws, for tests that check the words a user reads.
#include "Core/Error.h"
#include "Core/ParameterError.h"

#include <functional>
#include <string>

namespace tissuemosaic {

/// The Error's message, or "no error" when the action throws none.
inline std::string errorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  }
  return "no error";
}

/// The parameter a ParameterError names (Core/ParameterError.h): "" for another Error, "no error" when none is thrown.
inline std::string parameterOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const ParameterError& error) {
    return error.parameter();
  } catch (const Error&) {
    return "";
  }
  return "no error";
}

}  // namespace tissuemosaic
