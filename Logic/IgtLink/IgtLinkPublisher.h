#pragma once
/// @file IgtLinkPublisher.h
/// @brief What a reconstruction sends over OpenIGTLink and when (docs/OPENIGTLINK.md): one TRANSFORM
/// LeftCameraToModel per tracked frame, a POLYDATA TissueModel after key frames (at most maxModelRateHz, at most
/// modelPointBudget points, packed on its own thread, newest only), STATUS TissueMosaic when tracking is lost, found
/// again and when the scan finishes, and IMAGE LeftVideo per frame when asked. Every call returns at once: the
/// server only queues.
#include "IgtLinkServer.h"

#include <Eigen/Core>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

namespace tissuemosaic::igtlink {

struct IgtLinkPublisherOptions {
  double maxModelRateHz = 2.0;          ///< POLYDATA messages per second, at most
  std::size_t modelPointBudget = 500000;  ///< points per POLYDATA, at most (Slicer stays interactive)
  bool sendVideo = false;               ///< IMAGE LeftVideo: the rectified left frame of every processed frame

  /// Throws Error for a non-positive rate or budget.
  void validate() const;
};

class IgtLinkPublisher {
public:
  IgtLinkPublisher(IgtLinkServer& server, IgtLinkPublisherOptions options);
  ~IgtLinkPublisher();
  IgtLinkPublisher(const IgtLinkPublisher&) = delete;
  IgtLinkPublisher& operator=(const IgtLinkPublisher&) = delete;

  /// After each processed frame. tracked: T_world_camera (left rectified camera to model, mm) is valid;
  /// trackingMessage says why not. leftRectified: sent as IMAGE when sendVideo (may be empty otherwise).
  void frameProcessed(int frameIndex, double timeS, bool tracked, const Eigen::Matrix4d& T_world_camera,
                      const std::string& trackingMessage, const cv::Mat& leftRectified);
  /// True when a key frame's model would be sent now (a client is connected and the rate allows): the caller takes
  /// the model snapshot only then.
  bool modelDue() const;
  /// Hands the model over for packing (newest only: a model still waiting is replaced).
  void modelUpdated(ColoredPointCloud model, double timeS);
  /// The end of the scan: the final model (when given, regardless of the rate) and STATUS Finished, then waits up
  /// to flushTimeoutS for the clients to take everything.
  void finished(std::optional<ColoredPointCloud> finalModel, double timeS, const std::string& text,
                double flushTimeoutS = 10.0);

  long long modelsSent() const { return modelsPacked_; }

private:
  void packLoop();

  IgtLinkServer& server_;
  IgtLinkPublisherOptions options_;
  bool lost_ = false;
  std::chrono::steady_clock::time_point lastModel_;
  bool anyModel_ = false;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<ColoredPointCloud> pendingModel_;
  double pendingTimeS_ = 0;
  bool packing_ = false, stop_ = false;
  std::atomic<long long> modelsPacked_{0};
  std::thread packer_;
};

}  // namespace tissuemosaic::igtlink
