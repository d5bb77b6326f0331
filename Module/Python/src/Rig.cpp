#include "Rig.h"

#include "Core/Error.h"

namespace tissuemosaic::python {

Rig::Rig(StereoGeometrySpec spec, std::string description, std::optional<cv::Size> imageSize)
    : spec_(std::move(spec)), description_(std::move(description)), pinholeImageSize_(imageSize) {
  if (pinholeImageSize_) resolve(*pinholeImageSize_, "the rig's image_size");  // values checked at once
}

std::optional<cv::Size> Rig::imageSize() const {
  if (spec_.calibration && !spec_.calibration->calibration.imageSize.empty()) return spec_.calibration->calibration.imageSize;
  return pinholeImageSize_;
}

std::shared_ptr<const StereoGeometry> Rig::resolve(const cv::Size& frameSize,
                                                   const std::string& framesDescription) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto key = std::make_pair(frameSize.width, frameSize.height);
  if (const auto found = resolved_.find(key); found != resolved_.end()) return found->second;
  auto geometry = std::make_shared<const StereoGeometry>(resolveStereoGeometry(spec_, frameSize, framesDescription));
  resolved_.emplace(key, geometry);
  return geometry;
}

std::shared_ptr<const StereoGeometry> Rig::resolveFor(const std::optional<cv::Size>& size) const {
  const std::optional<cv::Size> known = size ? size : imageSize();
  require(known.has_value(), "the rig does not know its image size: give image_size=(width, height)");
  return resolve(*known, size ? "image_size" : "the rig's image size");
}

}  // namespace tissuemosaic::python
