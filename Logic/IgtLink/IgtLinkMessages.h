#pragma once
/// @file IgtLinkMessages.h
/// @brief The OpenIGTLink messages TissueMosaic sends (docs/OPENIGTLINK.md), packed once and shared by every client:
/// TRANSFORM LeftCameraToModel, POLYDATA TissueModel, STATUS TissueMosaic, IMAGE LeftVideo. Protocol version 2
/// messages with v1 headers (Debian's libopenigtlink 1.11), CRC-64 on every body, millimetres.
///
/// Frame: the model's world frame (the first left rectified camera, or --start-tum's pose: x right, y down, z
/// forward), as the trajectories and the model file use it. No RAS/LPS flip is applied.
#include "Core/StereoRig.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <memory>
#include <string>
#include <vector>

namespace tissuemosaic::igtlink {

/// Device names (OpenIGTLink 1.11 holds at most 20 characters; Slicer names its nodes after them).
inline constexpr const char* kCameraTransformName = "LeftCameraToModel";
inline constexpr const char* kModelName = "TissueModel";
inline constexpr const char* kStatusName = "TissueMosaic";
inline constexpr const char* kVideoName = "LeftVideo";
/// The POLYDATA point attribute with the model's colour: POINT_RGBA, 4 float components in [0, 1].
inline constexpr const char* kColourAttributeName = "Colors";

/// One packed message (header + body) and what it is.
struct PackedMessage {
  std::string deviceType;  ///< "TRANSFORM", "POLYDATA", ...
  std::string deviceName;
  std::shared_ptr<const std::vector<unsigned char>> bytes;
  std::size_t size() const { return bytes ? bytes->size() : 0; }
};

/// TRANSFORM: the 4x4 pose (rotation and translation in mm), time stamp timeS seconds.
PackedMessage packTransform(const std::string& name, const Eigen::Matrix4d& T, double timeS);

/// The points of `cloud` that a POLYDATA of at most maxPoints carries: all of them when they fit, else maxPoints
/// spread evenly over the model (every (size / maxPoints)-th, in model order).
std::vector<std::size_t> pointsWithinBudget(std::size_t modelPoints, std::size_t maxPoints);
/// POLYDATA: the chosen points (mm), one VERTICES cell per point, colour as the POINT_RGBA attribute
/// kColourAttributeName (alpha 1) when the cloud has colours.
PackedMessage packPointCloud(const std::string& name, const ColoredPointCloud& cloud, std::size_t maxPoints,
                             double timeS);

/// STATUS with its code (igtl::StatusMessage::STATUS_OK, ...), a short error name (<= 20 characters) and text.
PackedMessage packStatus(const std::string& name, int code, const std::string& errorName, const std::string& text,
                         double timeS);

/// IMAGE: an 8-bit BGR or grey frame as RGB (3 components) or grey, 1 mm spacing, rows along -A (upright in
/// Slicer's axial view).
PackedMessage packImage(const std::string& name, const cv::Mat& image, double timeS);

}  // namespace tissuemosaic::igtlink
