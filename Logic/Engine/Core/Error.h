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
/// The same for a literal message: no std::string is built while the condition holds (checks inside loops over
/// thousands of items cost 30-50 ns each otherwise). A message built from parts is built before the call: in a loop,
/// write `if (!condition) throw Error(...)` instead.
inline void require(bool condition, const char* message) {
  if (!condition) throw Error(message);
}

}  // namespace tissuemosaic
