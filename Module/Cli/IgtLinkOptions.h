#pragma once
/// @file IgtLinkOptions.h
/// @brief The OpenIGTLink options (docs/OPENIGTLINK.md): reconstruct's server that sends the scan to 3D Slicer
/// (--igtl-port, --igtl-bind, --igtl-max-clients, --igtl-wait-client, --igtl-send-video, --igtl-model-rate,
/// --igtl-model-points), and the input from
/// a PLUS server that the input group declares (--igtl-input with --igtl-left/--igtl-right or --igtl-sbs). Builds
/// without OpenIGTLink refuse them with the reason.
#include "CommonOptions.h"

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

struct IgtLinkServerOptions {
  std::optional<int> port;
  std::string bindAddress = "127.0.0.1";  ///< loopback: only this computer's programs connect
  int maxClients = 8;
  double waitClientS = 0;
  bool sendVideo = false;
  double modelRateHz = 2.0;
  int modelPoints = 500000;
};
/// Declares the server options (help heading "Output": they are where the scan goes).
void addIgtLinkServerOptions(CLI::App& command, IgtLinkServerOptions& options);

/// The sending side of a reconstruct run; every call returns at once.
class IgtLinkSender {
public:
  virtual ~IgtLinkSender() = default;
  virtual void frameProcessed(int frameIndex, double timeS, bool tracked, const Eigen::Matrix4d& T_world_camera,
                              const std::string& trackingMessage, const cv::Mat& leftRectified) = 0;
  virtual bool modelDue() const = 0;
  virtual void modelUpdated(const ColoredPointCloud& model, double timeS) = 0;
  virtual void finished(const ColoredPointCloud& model, double timeS, const std::string& text) = 0;
  /// "OpenIGTLink on ADDRESS port P: N client(s), M messages sent (K models), D dropped for slow clients, R
  /// connection(s) refused (more than C clients)".
  virtual std::string summary() const = 0;
};

/// nullptr without --igtl-port. With it: listens, then waits up to --igtl-wait-client seconds for a first client
/// (telling `log` what it does).
std::unique_ptr<IgtLinkSender> startIgtLinkSender(const IgtLinkServerOptions& options, std::ostream& log);

/// The input from --igtl-input (openInput calls it). The first malformed messages it skips are told on stderr.
std::unique_ptr<StereoFrameSource> openIgtLinkInput(const InputOptions& input, VideoLayout layout);
/// For an --igtl-input source: "OpenIGTLink input: N malformed message(s) skipped (the last: ...), M failed their
/// CRC"; "" for any other source.
std::string igtLinkInputSummary(const StereoFrameSource& source);

}  // namespace tissuemosaic::cli
