#pragma once
/// @file ErrorText.h
/// @brief The message of the tissuemosaic::Error an action throws, for tests that check the words a user reads.
#include "Core/Error.h"

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

}  // namespace tissuemosaic
