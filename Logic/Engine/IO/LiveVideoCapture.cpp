#include "IO/LiveVideoCapture.h"

#include "Core/Error.h"

#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

#include <chrono>

namespace tissuemosaic {

struct LiveVideoCapture::Capture {
  cv::VideoCapture video;
};

VideoInputKind videoInputKind(const std::string& input) {
  if (input.find("appsink") != std::string::npos) return VideoInputKind::GStreamerPipeline;
  if (input.rfind("/dev/video", 0) == 0) return VideoInputKind::Device;
  return VideoInputKind::File;
}

LiveVideoCapture::LiveVideoCapture(const std::string& input, double firstFrameTimeoutS)
    : capture_(std::make_unique<Capture>()) {
  const VideoInputKind kind = videoInputKind(input);
  require(kind != VideoInputKind::File, "'" + input + "' is neither a V4L2 device nor a GStreamer pipeline");
  const int backend = kind == VideoInputKind::Device ? cv::CAP_V4L2 : cv::CAP_GSTREAMER;
  description_ = (kind == VideoInputKind::Device ? "capture device '" : "GStreamer pipeline '") + input + "'";
  require(cv::videoio_registry::hasBackend(static_cast<cv::VideoCaptureAPIs>(backend)),
          "cannot open " + description_ + ": this OpenCV has no " +
              (kind == VideoInputKind::Device ? "V4L2" : "GStreamer") + " backend (see cv::getBuildInformation())");
  bool opened = false;
  try {
    opened = capture_->video.open(input, backend);
  } catch (const cv::Exception& e) {
    throw Error("cannot open " + description_ + ": " + e.err);
  }
  require(opened, "cannot open " + description_ +
                      (kind == VideoInputKind::Device ? ": no such device, or it is busy"
                                                      : ": the pipeline does not start (it must end in appsink; "
                                                        "try it with gst-launch-1.0 and fakesink)"));
  thread_ = std::thread([this] { readLoop(); });
  std::unique_lock<std::mutex> lock(mutex_);
  const bool first = changed_.wait_for(lock, std::chrono::duration<double>(firstFrameTimeoutS),
                                       [this] { return !newest_.empty() || ended_; });
  if (!first || newest_.empty()) {
    lock.unlock();
    interrupt();
    thread_.join();
    throw Error("no frame came from " + description_ + " within " + cv::format("%g", firstFrameTimeoutS) + " s");
  }
  frameSize_ = newest_.size();
}

LiveVideoCapture::~LiveVideoCapture() {
  interrupt();
  if (thread_.joinable()) thread_.join();
}

void LiveVideoCapture::readLoop() {
  const auto start = std::chrono::steady_clock::now();
  cv::Mat frame;
  while (!stop_.load()) {
    // read() blocks until the source delivers: at the source's pace (a pipeline syncs its appsink to the clock).
    if (!capture_->video.read(frame) || frame.empty()) break;
    const auto now = std::chrono::steady_clock::now();
    ++arrived_;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!newestTaken_) ++dropped_;
    // Swap, not copy: the capture decodes into the buffer nextNewest() handed back last time.
    cv::swap(newest_, frame);
    newestTimeS_ = std::chrono::duration<double>(now - start).count();
    newestTaken_ = false;
    changed_.notify_all();
  }
  capture_->video.release();
  std::lock_guard<std::mutex> lock(mutex_);
  ended_ = true;
  changed_.notify_all();
}

bool LiveVideoCapture::nextNewest(cv::Mat& frame, double& timeS) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return !newestTaken_ || ended_ || stop_.load(); });
  if (stop_.load() || newestTaken_) return false;
  frame = newest_.clone();
  timeS = newestTimeS_;
  newestTaken_ = true;
  return true;
}

void LiveVideoCapture::interrupt() {
  stop_.store(true);
  std::lock_guard<std::mutex> lock(mutex_);
  changed_.notify_all();
}

}  // namespace tissuemosaic
