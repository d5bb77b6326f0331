#pragma once
/// @file ParameterChecks.h
/// @brief The checks and file reading shared by every parameter struct (StereoParameters, TrackingParameters, ...):
/// one wording for range errors and one rule for reading numbers from a cv::FileStorage node.
#include "Error.h"

#include <opencv2/core.hpp>

#include <sstream>
#include <string>
#include <type_traits>

namespace tissuemosaic::parameters {

/// Throws Error "<group> parameter <name> = <value> is out of range [low, high]" unless low <= value <= high
/// (NaN fails).
template <class T>
void requireRange(const char* group, const char* name, T value, T low, T high) {
  if (!(value >= low && value <= high)) {
    std::ostringstream message;
    message << group << " parameter " << name << " = " << value << " is out of range [" << low << ", " << high << "]";
    throw Error(message.str());
  }
}

/// Reads node[name] into value when present (a missing key keeps the default); a value of the wrong type is an Error.
template <class T>
void readKey(const char* group, const cv::FileNode& node, const char* name, T& value) {
  const cv::FileNode entry = node[name];
  if (entry.empty()) return;
  if (!entry.isInt() && !entry.isReal()) throw Error(std::string(group) + " parameter " + name + " must be a number");
  if constexpr (std::is_integral_v<T>) {
    if (!entry.isInt()) throw Error(std::string(group) + " parameter " + name + " must be an integer");
    value = static_cast<T>(static_cast<int>(entry));
  } else {
    value = static_cast<T>(static_cast<double>(entry));
  }
}

/// One parameter group (a key of the parameter files: "stereo", "tracking", ...): its checks and reads with the group's
/// name in every message. Bounds of another arithmetic type than the value compare in their common type.
struct Group {
  const char* name;

  template <class T, class Low, class High>
  void requireRange(const char* key, T value, Low low, High high) const {
    using Common = std::common_type_t<T, Low, High>;
    // An unsigned common type would turn a negative bound into a huge one.
    static_assert(std::is_signed_v<Common>, "range checks compare in a signed or floating-point type");
    parameters::requireRange<Common>(name, key, value, low, high);
  }
  template <class T>
  void readKey(const cv::FileNode& node, const char* key, T& value) const {
    parameters::readKey(name, node, key, value);
  }
};

}  // namespace tissuemosaic::parameters
