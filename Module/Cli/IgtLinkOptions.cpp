#include "IgtLinkOptions.h"

#include "Core/Error.h"
#include "Core/StereoRig.h"

#include <iostream>

#if defined(TM_WITH_IGTLINK)
#include "IgtLinkPublisher.h"
#include "IgtLinkVideoSource.h"
#endif

namespace tissuemosaic::cli {

namespace {

const char* const kNoIgtLink =
    "this build has no OpenIGTLink: install libopenigtlink-dev (Resources/scripts/setup.sh) and configure again";

#if defined(TM_WITH_IGTLINK)
class PublisherSender : public IgtLinkSender {
public:
  PublisherSender(int port, const igtlink::IgtLinkServer::Options& server,
                  const igtlink::IgtLinkPublisherOptions& options)
      : server_(port, server), publisher_(server_, options), maxClients_(server.maxClients) {}
  igtlink::IgtLinkServer& server() { return server_; }
  void frameProcessed(int frameIndex, double timeS, bool tracked, const Eigen::Matrix4d& T_world_camera,
                      const std::string& trackingMessage, const cv::Mat& leftRectified) override {
    publisher_.frameProcessed(frameIndex, timeS, tracked, T_world_camera, trackingMessage, leftRectified);
  }
  bool modelDue() const override { return publisher_.modelDue(); }
  void modelUpdated(const ColoredPointCloud& model, double timeS) override { publisher_.modelUpdated(model, timeS); }
  void finished(const ColoredPointCloud& model, double timeS, const std::string& text) override {
    publisher_.finished(server_.clientCount() > 0 ? std::optional<ColoredPointCloud>(model) : std::nullopt, timeS,
                        text);
  }
  std::string summary() const override {
    const igtlink::IgtLinkServerCounters c = server_.counters();
    return "OpenIGTLink on " + server_.boundAddress() + " port " + std::to_string(server_.port()) + ": " +
           std::to_string(c.connections) + " client(s), " + std::to_string(c.messagesSent) + " messages sent (" +
           std::to_string(publisher_.modelsSent()) + " models), " + std::to_string(c.messagesDropped) +
           " dropped for slow clients, " + std::to_string(c.refused) + " connection(s) refused (more than " +
           std::to_string(maxClients_) + " clients)";
  }

private:
  igtlink::IgtLinkServer server_;  // declared first: the publisher stops before the server
  igtlink::IgtLinkPublisher publisher_;
  int maxClients_;
};
#endif

}  // namespace

void addIgtLinkServerOptions(CLI::App& command, IgtLinkServerOptions& options) {
  CLI::Option* port = command.add_option(
      "--igtl-port", options.port,
      "OpenIGTLink server for 3D Slicer: TRANSFORM LeftCameraToModel per tracked frame, POLYDATA TissueModel after "
      "key frames, STATUS TissueMosaic (Slicer's default port is 18944; 0: any free port)");
  port->check(CLI::Range(0, 65535))->type_name("P");
  CLI::Option* bind = command.add_option(
      "--igtl-bind", options.bindAddress,
      "the address the OpenIGTLink server listens on: 127.0.0.1 lets in only this computer's programs; a network "
      "interface's address, or 0.0.0.0 for all of them, lets in that network (docs/OPENIGTLINK.md)");
  bind->type_name("ADDRESS")->capture_default_str();
  CLI::Option* maxClients = command.add_option("--igtl-max-clients", options.maxClients,
                                               "OpenIGTLink clients connected at once; further connections are "
                                               "closed at once and counted");
  maxClients->check(CLI::PositiveNumber)->type_name("N")->capture_default_str();
  CLI::Option* wait = command.add_option("--igtl-wait-client", options.waitClientS,
                                         "hold processing up to S seconds for a first OpenIGTLink client");
  wait->check(CLI::NonNegativeNumber)->type_name("S");
  CLI::Option* video = command.add_flag("--igtl-send-video", options.sendVideo,
                                        "also send IMAGE LeftVideo, the rectified left frame");
  CLI::Option* rate = command.add_option("--igtl-model-rate", options.modelRateHz,
                                         "POLYDATA messages per second at most");
  rate->check(positiveNumber("per second"))->type_name("HZ")->capture_default_str();
  CLI::Option* points = command.add_option("--igtl-model-points", options.modelPoints,
                                           "points per POLYDATA at most (spread over the model)");
  points->check(CLI::PositiveNumber)->type_name("N")->capture_default_str();
  for (CLI::Option* option : {bind, maxClients, wait, video, rate, points}) option->needs(port);
  for (CLI::Option* option : {port, bind, maxClients, wait, video, rate, points}) option->group(heading::output);
}

std::unique_ptr<IgtLinkSender> startIgtLinkSender(const IgtLinkServerOptions& options, std::ostream& log) {
  if (!options.port) return nullptr;
#if defined(TM_WITH_IGTLINK)
  igtlink::IgtLinkPublisherOptions publisher;
  publisher.sendVideo = options.sendVideo;
  publisher.maxModelRateHz = options.modelRateHz;
  publisher.modelPointBudget = static_cast<std::size_t>(options.modelPoints);
  igtlink::IgtLinkServer::Options server;
  server.bindAddress = options.bindAddress;
  server.maxClients = options.maxClients;
  auto sender = std::make_unique<PublisherSender>(*options.port, server, publisher);
  log << "OpenIGTLink server listening on " << sender->server().boundAddress() << " port " << sender->server().port()
      << " (at most " << options.maxClients << " clients)" << std::endl;
  if (options.waitClientS > 0) {
    log << "waiting up to " << options.waitClientS << " s for an OpenIGTLink client..." << std::endl;
    if (!sender->server().waitForClient(options.waitClientS)) {
      log << "no OpenIGTLink client came: reconstructing anyway" << std::endl;
    }
  }
  return sender;
#else
  (void)log;
  throw Error(std::string("--igtl-port: ") + kNoIgtLink);
#endif
}

std::unique_ptr<StereoFrameSource> openIgtLinkInput(const InputOptions& input, VideoLayout layout) {
#if defined(TM_WITH_IGTLINK)
  igtlink::IgtLinkVideoInput source;
  igtlink::IgtLinkVideoInput::parseAddress(input.igtlInput, source.host, source.port);
  if (!input.igtlSbs.empty()) {
    source.packedName = input.igtlSbs;
    source.layout = layout;
  } else if (!input.igtlLeft.empty()) {
    source.leftName = input.igtlLeft;
    source.rightName = input.igtlRight;
  } else {
    throw UsageError("--igtl-input needs either --igtl-left NAME --igtl-right NAME (two IMAGE streams) or "
                     "--igtl-sbs NAME");
  }
  source.warn = [](const std::string& warning) { std::cerr << "warning: " << warning << std::endl; };
  return igtlink::openIgtLinkVideo(source);
#else
  (void)input;
  (void)layout;
  throw Error(std::string("--igtl-input: ") + kNoIgtLink);
#endif
}

std::string igtLinkInputSummary(const StereoFrameSource& source) {
#if defined(TM_WITH_IGTLINK)
  const auto* counters = dynamic_cast<const igtlink::IgtLinkInputCounters*>(&source);
  if (!counters) return "";
  const long long malformed = counters->malformedMessages();
  return "OpenIGTLink input: " + std::to_string(malformed) + " malformed message(s) skipped" +
         (malformed > 0 ? " (the last: " + counters->lastMalformed() + ")" : "") + ", " +
         std::to_string(counters->framesFailingCrc()) + " failed their CRC";
#else
  (void)source;
  return "";
#endif
}

}  // namespace tissuemosaic::cli
