#pragma once
/// @file LiveVideoCapture.h
/// @brief A live video input (a V4L2 capture device or a GStreamer pipeline) read on its own thread at the source's
/// pace. Only the newest frame is kept: a consumer slower than the source gets the newest frame each time and the
/// frames it never saw are counted as dropped, so latency and memory stay bounded however slow the consumer is.
#include <opencv2/core.hpp>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace tissuemosaic {

/// What a video argument names: a file, a V4L2 device ("/dev/videoN") or a GStreamer pipeline (it holds "appsink").
enum class VideoInputKind { File, Device, GStreamerPipeline };
VideoInputKind videoInputKind(const std::string& input);

class LiveVideoCapture {
public:
  /// Opens the device or pipeline and waits up to firstFrameTimeoutS for its first frame (which gives the size).
  /// Throws Error when it cannot be opened, OpenCV lacks the backend, or no frame comes.
  explicit LiveVideoCapture(const std::string& input, double firstFrameTimeoutS = 10.0);
  ~LiveVideoCapture();
  LiveVideoCapture(const LiveVideoCapture&) = delete;
  LiveVideoCapture& operator=(const LiveVideoCapture&) = delete;

  /// Waits for a frame newer than the last one returned and returns the newest. timeS: seconds since the first
  /// frame, taken when the frame arrived. False when the stream ended or interrupt() was called.
  bool nextNewest(cv::Mat& frame, double& timeS);
  /// Makes a waiting (and every later) nextNewest() return false. Thread-safe; not async-signal-safe.
  void interrupt();
  /// Frames that arrived but were replaced by a newer one before nextNewest() took them.
  long long droppedFrames() const { return dropped_.load(); }
  long long arrivedFrames() const { return arrived_.load(); }
  cv::Size frameSize() const { return frameSize_; }
  const std::string& description() const { return description_; }

private:
  void readLoop();

  std::string description_;
  cv::Size frameSize_;
  struct Capture;
  std::unique_ptr<Capture> capture_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  cv::Mat newest_;
  double newestTimeS_ = 0;
  bool newestTaken_ = true;  ///< the slot holds nothing nextNewest() has not returned yet
  bool ended_ = false;
  std::atomic<bool> stop_{false};
  std::atomic<long long> dropped_{0}, arrived_{0};
};

}  // namespace tissuemosaic
