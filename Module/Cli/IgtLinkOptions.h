#pragma once
/// @file IgtLinkOptions.h
/// @brief reconstruct's OpenIGTLink options (docs/OPENIGTLINK.md): the server that sends the scan to 3D Slicer
/// (--igtl-port, --igtl-wait-client, --igtl-send-video, --igtl-model-rate, --igtl-model-points) and the input from
/// a PLUS server (--igtl-input with --igtl-left/--igtl-right or --igtl-sbs). Builds without OpenIGTLink refuse them.
#include "Arguments.h"

#include "IO/StereoFrameSource.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <ostream>
#include <string>

namespace tissuemosaic {
struct ColoredPointCloud;
}

namespace tissuemosaic::cli {

/// The option names, for Arguments::allowOnly.
extern const char* const kIgtLinkOptionNames[];
extern const int kIgtLinkOptionCount;

/// The sending side of a reconstruct run; every call returns at once.
class IgtLinkSender {
public:
  virtual ~IgtLinkSender() = default;
  virtual void frameProcessed(int frameIndex, double timeS, bool tracked, const Eigen::Matrix4d& T_world_camera,
                              const std::string& trackingMessage, const cv::Mat& leftRectified) = 0;
  virtual bool modelDue() const = 0;
  virtual void modelUpdated(const ColoredPointCloud& model, double timeS) = 0;
  virtual void finished(const ColoredPointCloud& model, double timeS, const std::string& text) = 0;
  /// "OpenIGTLink: N clients, M messages sent, K models" for the summary.
  virtual std::string summary() const = 0;
};

/// nullptr without --igtl-port. With it: listens, then waits up to --igtl-wait-client seconds for a first client
/// (telling `log` what it does).
std::unique_ptr<IgtLinkSender> startIgtLinkSender(const Arguments& arguments, std::ostream& log);

/// True when --igtl-input is given.
bool hasIgtLinkInput(const Arguments& arguments);
std::unique_ptr<StereoFrameSource> openIgtLinkInput(const Arguments& arguments, VideoLayout layout);

}  // namespace tissuemosaic::cli
