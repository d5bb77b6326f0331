#include "qTissueMosaicCommandLine.h"

#include "qTissueMosaicReconstructionWidget.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "HelpFormat.h"
#include "UsageMessage.h"

#include "Core/RectifiedGeometryFromPinhole.h"

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

namespace cli = tissuemosaic::cli;

const char* const kApplicationHeading = "Application";

/// The options as text where the application checks them itself, for its own messages.
struct ApplicationText {
  std::string demoFrames, demoSize, snapshotFrame, slowEventMs;
};

/// One grammar: the tool's input, geometry, device and parameters groups, then the application's own.
std::unique_ptr<CLI::App> makeParser(qTissueMosaicCommandLine& options, ApplicationText& text) {
  auto app = std::make_unique<CLI::App>(
      "The TissueMosaic desktop application: open a stereo video (or the demo) and its calibration, reconstruct the\n"
      "tissue surface live (growing textured model, camera frusta, video, disparity), export the model and the\n"
      "camera path, register the model to a CT/MR surface. Input and geometry as `tissuemosaic reconstruct`.",
      "tissuemosaic-app");
  cli::useHouseHelpFormat(*app);
  cli::addInputOptions(*app, options.input);
  cli::addGeometryOptions(*app, options.geometry);
  const auto own = [&](CLI::Option* option) { option->group(kApplicationHeading); };
  own(app->add_flag("--start", options.start, "start reconstructing the input at once"));
  own(app->add_flag("--demo", options.demo, "generate the bundled synthetic demo scan, open it and start reconstructing"));
  own(app->add_option("--demo-frames", text.demoFrames, "frames of the demo scan (default 60)")->type_name("N"));
  own(app->add_option("--demo-size", text.demoSize, "demo frame size (default 480x270)")->type_name("WxH"));
  own(app->add_flag("--offscreen", options.offscreen,
                    "headless: render into a private X server (Xvfb; started and stopped by the application, nothing "
                    "appears on any screen); falls back to $DISPLAY when Xvfb is not installed"));
  own(app->add_option("--snapshot", options.snapshot,
                      "write a screenshot of the application when the scan ends (or at --snapshot-frame), then quit")
          ->type_name("FILE.png"));
  own(app->add_option("--snapshot-frame", text.snapshotFrame,
                      "take the screenshot once N frames are processed (mid-scan) and stop the scan")
          ->type_name("N"));
  own(app->add_option("--export-model", options.exportModel, "write the model (.ply or .vtp) when the scan ends")
          ->type_name("FILE"));
  own(app->add_option("--export-trajectory", options.exportTrajectory, "write the camera path (TUM) when the scan ends")
          ->type_name("FILE"));
  own(app->add_flag("--quit-when-done", options.quitWhenDone, "quit when the scan ends (implied by --offscreen and "
                                                              "--snapshot)"));
  own(app->add_flag("--report-stalls", options.reportStalls,
                    "print the longest event-loop stall (QTimer probe) measured while the scan ran"));
  own(app->add_option("--trace-slow-events", text.slowEventMs,
                      "write every event that takes longer than MS milliseconds to stderr (what a stall was)")
          ->type_name("MS"));
  cli::addDeviceOption(*app, options.device);
  cli::addParamsOption(*app, options.params, "stereo, features, tracking, refinement, fusion, agreement, pipeline");
  cli::moveHelpLast(*app);
  return app;
}

/// A positive integer (at most a million) from an option's text; UsageError in the application's words.
int positiveInteger(const char* option, const std::string& text) {
  std::size_t end = 0;
  long long number = 0;
  try {
    number = std::stoll(text, &end);
  } catch (const std::exception&) {
    end = 0;
  }
  if (end == 0 || end != text.size() || number <= 0 || number > 1000000) {
    throw cli::UsageError(std::string(option) + " needs a positive integer, not '" + text + "'");
  }
  return static_cast<int>(number);
}

/// What the application's own options say, and how they go with the input.
void checkApplicationOptions(qTissueMosaicCommandLine& options, const ApplicationText& text) {
  if (!text.demoFrames.empty()) options.demoFrames = positiveInteger("--demo-frames", text.demoFrames);
  if (!text.snapshotFrame.empty()) options.snapshotFrame = positiveInteger("--snapshot-frame", text.snapshotFrame);
  if (!text.slowEventMs.empty()) options.slowEventMs = positiveInteger("--trace-slow-events", text.slowEventMs);
  if (!text.demoSize.empty()) {
    const std::size_t x = text.demoSize.find('x');
    if (x == std::string::npos) throw cli::UsageError("--demo-size must be WIDTHxHEIGHT, e.g. 480x270");
    options.demoWidth = positiveInteger("--demo-size", text.demoSize.substr(0, x));
    options.demoHeight = positiveInteger("--demo-size", text.demoSize.substr(x + 1));
  }
  const cli::InputOptions& input = options.input;
  if (!input.igtlInput.empty() || !input.scared.empty() || !input.hamlyn.empty() || !input.stereomis.empty() ||
      input.videoLayout != "sbs" || !options.geometry.calibExtrinsics.empty() || !options.geometry.calibRight.empty()) {
    throw cli::UsageError("the application opens frame folders, two videos or one side-by-side video with one "
                          "calibration file: run OpenIGTLink, data-set layouts, other video layouts and two-file "
                          "calibrations with `tissuemosaic reconstruct`");
  }
  if (options.hasInput()) {
    cli::requireOneInput(input);
    cli::requireGeometry(options.geometry);
  } else if (options.hasPinholeGeometry()) {
    throw cli::UsageError("--focal-px/--baseline-mm describe an input's frames: give the input too");
  }
  if (options.demo && options.hasInput()) throw cli::UsageError("give either --demo or an input, not both");
  if (options.start && !options.hasInput() && !options.demo) {
    throw cli::UsageError("--start needs an input: --left-frames/--right-frames, --left-video/--right-video or --video");
  }
  if (options.device.name != "auto" && options.device.name != "cpu" && options.device.name != "cuda") {
    throw cli::UsageError("--device must be cpu, cuda or auto");
  }
  if (options.snapshotFrame > 0 && options.snapshot.empty()) throw cli::UsageError("--snapshot-frame needs --snapshot");
  if (options.offscreen || !options.snapshot.empty()) options.quitWhenDone = true;
  if (options.quitWhenDone && options.hasInput() && !options.start) {
    throw cli::UsageError("--offscreen, --snapshot and --quit-when-done end with the scan: add --start to begin it");
  }
}

}  // namespace

QString qTissueMosaicCommandLine::helpText() {
  qTissueMosaicCommandLine options;
  ApplicationText text;
  QString help = QString::fromStdString(makeParser(options, text)->help());
  help.replace("Usage: ", "usage: ");
  return help;
}

bool qTissueMosaicCommandLine::parse(const QStringList& arguments, QString& error) {
  ApplicationText text;
  const std::unique_ptr<CLI::App> parser = makeParser(*this, text);
  std::vector<std::string> words;
  for (int i = arguments.size() - 1; i >= 1; --i) words.push_back(arguments[i].toStdString());  // CLI11: reversed
  try {
    parser->parse(words);
    checkApplicationOptions(*this, text);
  } catch (const CLI::CallForHelp&) {
    this->help = true;
  } catch (const CLI::ParseError& failure) {
    error = QString::fromStdString(cli::usageMessage(failure, *parser));
    return false;
  }
  return true;
}

bool qTissueMosaicCommandLine::openInput(qTissueMosaicReconstructionWidget* panel, QString& error) const {
  const auto qt = [](const std::string& text) { return QString::fromStdString(text); };
  bool ok = true;
  if (!this->input.leftFrames.empty()) {
    ok = panel->openFrameFolders(qt(this->input.leftFrames), qt(this->input.rightFrames), this->input.fps);
  } else if (!this->input.leftVideo.empty()) {
    ok = panel->openVideoPair(qt(this->input.leftVideo), qt(this->input.rightVideo));
  } else if (!this->input.video.empty()) {
    ok = panel->openSideBySideVideo(qt(this->input.video));
  }
  if (ok && !this->geometry.calib.empty()) {
    ok = panel->loadCalibration(qt(this->geometry.calib));
    panel->setInputRectified(this->geometry.rectified);
  }
  if (!ok) {
    error = panel->lastMessage();
    return false;
  }
  if (this->hasPinholeGeometry()) {
    // The geometry of rectified frames exactly as `tissuemosaic reconstruct` makes it from the same options.
    vtkTissueMosaicReconstructionLogic* logic = panel->reconstructionLogic();
    const double centre = std::numeric_limits<double>::quiet_NaN();  // the image centre
    try {
      logic->SetRectifiedGeometry(tissuemosaic::rectifiedGeometryFromPinhole(
          logic->GetInputFrameSize(), this->geometry.focalPx.value_or(0), this->geometry.baselineMm.value_or(0),
          this->geometry.cxPx.value_or(centre), this->geometry.cyPx.value_or(centre),
          this->geometry.doffsPx.value_or(0)));
    } catch (const std::exception& failure) {
      error = failure.what();
      return false;
    }
    panel->setInputRectified(true);  // shows the geometry's state
  }
  return true;
}
