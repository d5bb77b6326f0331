#pragma once
/// @file Error.h
/// @brief The engine reports every failure as tissuemosaic::Error with a message a user can act on.
#include <stdexcept>
#include <string>

namespace tissuemosaic {

class Error : public std::runtime_error {
public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Throws Error(message) when condition is false.
inline void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace tissuemosaic
