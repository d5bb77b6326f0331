#include "IgtLinkOptions.h"

#include "Core/Error.h"
#include "Core/StereoRig.h"

#if defined(TM_WITH_IGTLINK)
#include "IgtLinkPublisher.h"
#include "IgtLinkVideoSource.h"
#endif

#include <cmath>

namespace tissuemosaic::cli {

const char* const kIgtLinkOptionNames[] = {"igtl-port",         "igtl-wait-client", "igtl-send-video",
                                           "igtl-model-rate",   "igtl-model-points", "igtl-input",
                                           "igtl-left",         "igtl-right",        "igtl-sbs"};
const int kIgtLinkOptionCount = sizeof(kIgtLinkOptionNames) / sizeof(kIgtLinkOptionNames[0]);

bool hasIgtLinkInput(const Arguments& arguments) { return arguments.has("igtl-input"); }

namespace {

void checkSenderOptionsNeedPort(const Arguments& arguments) {
  for (const char* name : {"igtl-wait-client", "igtl-send-video", "igtl-model-rate", "igtl-model-points"})
    require(!arguments.has(name) || arguments.has("igtl-port"), std::string("--") + name + " needs --igtl-port");
}

void checkInputOptionsNeedInput(const Arguments& arguments) {
  for (const char* name : {"igtl-left", "igtl-right", "igtl-sbs"})
    require(!arguments.has(name) || arguments.has("igtl-input"), std::string("--") + name + " needs --igtl-input");
}

#if defined(TM_WITH_IGTLINK)

class PublisherSender : public IgtLinkSender {
public:
  PublisherSender(int port, const igtlink::IgtLinkPublisherOptions& options)
      : server_(port), publisher_(server_, options) {}
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
    return "OpenIGTLink on port " + std::to_string(server_.port()) + ": " + std::to_string(c.connections) +
           " client(s), " + std::to_string(c.messagesSent) + " messages sent (" +
           std::to_string(publisher_.modelsSent()) + " models), " + std::to_string(c.messagesDropped) +
           " dropped for slow clients";
  }

private:
  igtlink::IgtLinkServer server_;
  igtlink::IgtLinkPublisher publisher_;
};

#endif

}  // namespace

std::unique_ptr<IgtLinkSender> startIgtLinkSender(const Arguments& arguments, std::ostream& log) {
  checkSenderOptionsNeedPort(arguments);
  if (!arguments.has("igtl-port")) return nullptr;
  const int port = arguments.integer("igtl-port", 0);
  require(port >= 0 && port <= 65535, "--igtl-port must be in 0..65535 (Slicer's default is 18944; 0: any free port)");
  const double waitS = arguments.number("igtl-wait-client", 0);
  require(waitS >= 0 && std::isfinite(waitS), "--igtl-wait-client must be a number of seconds >= 0");
#if defined(TM_WITH_IGTLINK)
  igtlink::IgtLinkPublisherOptions options;
  options.sendVideo = arguments.has("igtl-send-video");
  options.maxModelRateHz = arguments.number("igtl-model-rate", options.maxModelRateHz);
  const int points = arguments.integer("igtl-model-points", static_cast<int>(options.modelPointBudget));
  require(points > 0, "--igtl-model-points must be positive");
  options.modelPointBudget = static_cast<std::size_t>(points);
  try {
    options.validate();
  } catch (const Error& e) {
    throw Error(std::string("--igtl-model-rate: ") + e.what());
  }
  auto sender = std::make_unique<PublisherSender>(port, options);
  log << "OpenIGTLink server listening on port " << sender->server().port() << std::endl;
  if (waitS > 0) {
    log << "waiting up to " << waitS << " s for an OpenIGTLink client..." << std::endl;
    if (!sender->server().waitForClient(waitS)) log << "no OpenIGTLink client came: reconstructing anyway" << std::endl;
  }
  return sender;
#else
  (void)log;
  throw Error("this build has no OpenIGTLink (--igtl-port): install libopenigtlink-dev (Resources/scripts/setup.sh) "
              "and configure again");
#endif
}

std::unique_ptr<StereoFrameSource> openIgtLinkInput(const Arguments& arguments, VideoLayout layout) {
  checkInputOptionsNeedInput(arguments);
#if defined(TM_WITH_IGTLINK)
  igtlink::IgtLinkVideoInput input;
  igtlink::IgtLinkVideoInput::parseAddress(arguments.required("igtl-input"), input.host, input.port);
  const bool pair = arguments.has("igtl-left") || arguments.has("igtl-right");
  require(pair != arguments.has("igtl-sbs"),
          "--igtl-input needs either --igtl-left NAME --igtl-right NAME (two IMAGE streams) or --igtl-sbs NAME");
  if (pair) {
    input.leftName = arguments.required("igtl-left");
    input.rightName = arguments.required("igtl-right");
  } else {
    input.packedName = arguments.required("igtl-sbs");
    input.layout = layout;
  }
  return igtlink::openIgtLinkVideo(input);
#else
  (void)layout;
  throw Error("this build has no OpenIGTLink (--igtl-input): install libopenigtlink-dev (Resources/scripts/setup.sh) "
              "and configure again");
#endif
}

}  // namespace tissuemosaic::cli
