#include "IgtLinkPublisher.h"

#include "Core/Error.h"

#include <igtlStatusMessage.h>

#include <cmath>

namespace tissuemosaic::igtlink {

void IgtLinkPublisherOptions::validate() const {
  require(maxModelRateHz > 0 && std::isfinite(maxModelRateHz), "the OpenIGTLink model rate must be positive");
  require(modelPointBudget > 0, "the OpenIGTLink model point budget must be positive");
}

IgtLinkPublisher::IgtLinkPublisher(IgtLinkServer& server, IgtLinkPublisherOptions options)
    : server_(server), options_(options) {
  options_.validate();
  packer_ = std::thread([this] { packLoop(); });
}

IgtLinkPublisher::~IgtLinkPublisher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    changed_.notify_all();
  }
  packer_.join();
}

void IgtLinkPublisher::frameProcessed(int frameIndex, double timeS, bool tracked, const Eigen::Matrix4d& T_world_camera,
                                      const std::string& trackingMessage, const cv::Mat& leftRectified) {
  if (tracked) {
    if (lost_) {
      server_.send(packStatus(kStatusName, igtl::StatusMessage::STATUS_OK, "Relocalised",
                              "tracking found again at frame " + std::to_string(frameIndex), timeS),
                   false);
    }
    server_.send(packTransform(kCameraTransformName, T_world_camera, timeS), false);
  } else if (!lost_) {
    server_.send(packStatus(kStatusName, igtl::StatusMessage::STATUS_NOT_FOUND, "Lost",
                            "tracking lost at frame " + std::to_string(frameIndex) + ": " + trackingMessage, timeS),
                 false);
  }
  lost_ = !tracked;
  if (options_.sendVideo && !leftRectified.empty() && server_.clientCount() > 0) {
    server_.send(packImage(kVideoName, leftRectified, timeS), true);
  }
}

bool IgtLinkPublisher::modelDue() const {
  if (server_.clientCount() == 0) return false;
  if (!anyModel_) return true;
  const double sinceS = std::chrono::duration<double>(std::chrono::steady_clock::now() - lastModel_).count();
  return sinceS >= 1.0 / options_.maxModelRateHz;
}

void IgtLinkPublisher::modelUpdated(ColoredPointCloud model, double timeS) {
  lastModel_ = std::chrono::steady_clock::now();
  anyModel_ = true;
  std::lock_guard<std::mutex> lock(mutex_);
  pendingModel_ = std::move(model);
  pendingTimeS_ = timeS;
  changed_.notify_all();
}

void IgtLinkPublisher::packLoop() {
  for (;;) {
    ColoredPointCloud model;
    double timeS = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      packing_ = false;
      changed_.notify_all();
      changed_.wait(lock, [this] { return stop_ || pendingModel_.has_value(); });
      if (!pendingModel_) return;  // stopped with nothing left to pack
      model = std::move(*pendingModel_);
      timeS = pendingTimeS_;
      pendingModel_.reset();
      packing_ = true;
    }
    server_.send(packPointCloud(kModelName, model, options_.modelPointBudget, timeS), true);
    ++modelsPacked_;
  }
}

void IgtLinkPublisher::finished(std::optional<ColoredPointCloud> finalModel, double timeS, const std::string& text,
                                double flushTimeoutS) {
  if (finalModel) {
    std::lock_guard<std::mutex> lock(mutex_);
    pendingModel_ = std::move(finalModel);
    pendingTimeS_ = timeS;
    changed_.notify_all();
  }
  {  // the final model is packed and queued before the status that ends the stream
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return !pendingModel_ && !packing_; });
  }
  // Heavy messages go out after the ordered ones: let the model leave before the status that ends the stream.
  server_.flush(flushTimeoutS);
  server_.send(packStatus(kStatusName, igtl::StatusMessage::STATUS_OK, "Finished", text, timeS), false);
  server_.flush(flushTimeoutS);
}

}  // namespace tissuemosaic::igtlink
