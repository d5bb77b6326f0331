#pragma once
/// @file CalibrationDocument.h
/// @brief One calibration file as a tree of keys, whatever wrote it: OpenCV's FileStorage YAML ("%YAML:1.0") and
/// XML, plain YAML (ROS, Kalibr) and JSON (MATLAB's jsonencode). The layout readers look keys up here and turn
/// values into matrices; every error names the key.
#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include <string>

namespace tissuemosaic {

struct CalibrationDocument {
  std::string path;
  YAML::Node root;  ///< a map (load() refuses anything else)

  /// Reads `path`. Throws Error (without the "cannot read" prefix) for a missing file or one that is not valid
  /// YAML, JSON or OpenCV XML, or whose top level is not a map of keys.
  static CalibrationDocument load(const std::string& path);
  /// Adds the keys of `other` that this one lacks (the stereo_calib sample's intrinsics.yml + extrinsics.yml);
  /// Error when both hold the same key.
  void merge(const CalibrationDocument& other);
};

/// A map key as text: its scalar, or a flow rendering for the complex keys YAML allows (`? [a, b]`, which
/// as<std::string>() would throw for).
std::string keyText(const YAML::Node& key);
/// True when `node` is a map holding every key in `keys`.
bool hasKeys(const YAML::Node& node, std::initializer_list<const char*> keys);
/// The child `key` of `node`; Error "key 'KEY' is missing" (prefixed with `where`, e.g. "cam1: ").
YAML::Node requireKey(const YAML::Node& node, const std::string& key, const std::string& where = "");
/// A matrix of numbers (CV_64F) from an OpenCV matrix, a ROS {rows, cols, data} map, a flat list (one row) or a
/// list of rows. Error "key 'KEY' is not a matrix of numbers" otherwise.
cv::Mat readMatrix(const YAML::Node& node, const std::string& key);
/// requireKey + readMatrix, checked to hold rows x cols values (reshaped to rows x cols when the count fits).
cv::Mat readMatrix(const YAML::Node& parent, const std::string& key, int rows, int cols, const std::string& where = "");
double readNumber(const YAML::Node& node, const std::string& key);
std::string readText(const YAML::Node& node, const std::string& key);

}  // namespace tissuemosaic
