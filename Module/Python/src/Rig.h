#pragma once
/// @file Rig.h
/// @brief The Python module's Rig: a stereo rig as given (a calibration file in any layout the command line reads, or
/// the rectified pinhole values), resolved for frames of one size by the engine (IO/StereoGeometry.h).
#include "IO/StereoGeometry.h"

#include <opencv2/core.hpp>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace tissuemosaic::python {

class Rig {
public:
  explicit Rig(StereoGeometrySpec spec, std::string description, std::optional<cv::Size> imageSize = std::nullopt);

  /// What the spec means for frames of `frameSize` (cached per size; thread-safe). Throws Error as
  /// resolveStereoGeometry does (`framesDescription` names the frames).
  std::shared_ptr<const StereoGeometry> resolve(const cv::Size& frameSize, const std::string& framesDescription) const;
  /// The image size the rig knows (the calibration's, or Rig.rectified's image_size); nullopt when the frames give it.
  std::optional<cv::Size> imageSize() const;
  /// resolve() for the size given, else the rig's own; Error when neither is known.
  std::shared_ptr<const StereoGeometry> resolveFor(const std::optional<cv::Size>& size) const;

  const StereoGeometrySpec& spec() const { return spec_; }
  const std::string& description() const { return description_; }

private:
  StereoGeometrySpec spec_;
  std::string description_;
  std::optional<cv::Size> pinholeImageSize_;
  mutable std::mutex mutex_;
  mutable std::map<std::pair<int, int>, std::shared_ptr<const StereoGeometry>> resolved_;
};

}  // namespace tissuemosaic::python
