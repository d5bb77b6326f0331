#include "qTissueMosaicCommandLine.h"

#include "qTissueMosaicReconstructionWidget.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "Core/RectifiedGeometryFromPinhole.h"

#include <QCommandLineOption>
#include <QCommandLineParser>

#include <cmath>
#include <map>

namespace {

/// Every option once: name, value name ("" for a switch), description. The parser and the help come from it.
struct OptionSpec {
  const char* name;
  const char* valueName;
  const char* description;
};

// The input and geometry block is `tissuemosaic reconstruct`'s: same names, same meanings.
const OptionSpec kOptions[] = {
    {"left-frames", "DIR", "left frames (PNG/JPEG/..., paired with --right-frames in file-name order)"},
    {"right-frames", "DIR", "right frames"},
    {"left-video", "L", "left video file (with --right-video, read in lock step)"},
    {"right-video", "R", "right video file"},
    {"video", "SBS", "one side-by-side video (left eye in the left half)"},
    {"calib", "rig.yml", "stereo calibration, recognised by its keys (docs/CALIBRATION.md: OpenCV, stereo_calib / "
              "SCARED / SurgT, Kalibr, MATLAB); without an image size the frames give it: frames are rectified"},
    {"rectified", "", "with --calib: the frames are already rectified as StereoRectifier makes them from it"},
    {"focal-px", "F", "frames already rectified with this focal length (px), with --baseline-mm"},
    {"baseline-mm", "B", "the rectified rig's baseline (mm), with --focal-px"},
    {"cx-px", "X", "rectified principal point x (px; default: the image centre)"},
    {"cy-px", "Y", "rectified principal point y (px; default: the image centre)"},
    {"doffs-px", "D", "disparity offset cx_right - cx_left (px; default 0)"},
    {"fps", "F", "frame rate of frame folders (default 30)"},
    {"start", "", "start reconstructing the input at once"},
    {"demo", "", "generate the bundled synthetic demo scan, open it and start reconstructing"},
    {"demo-frames", "N", "frames of the demo scan (default 60)"},
    {"demo-size", "WxH", "demo frame size (default 480x270)"},
    {"device", "cpu|cuda|auto", "where the engine runs (default auto)"},
    {"params", "FILE", "reconstruction parameters (YAML, as the parameter panel saves them)"},
    {"offscreen", "",
     "headless: render into a private X server (Xvfb; started and stopped by the application, nothing appears on "
     "any screen); falls back to $DISPLAY when Xvfb is not installed"},
    {"snapshot", "FILE.png", "write a screenshot of the application when the scan ends (or at --snapshot-frame), then quit"},
    {"snapshot-frame", "N", "take the screenshot once N frames are processed (mid-scan) and stop the scan"},
    {"export-model", "FILE", "write the model (.ply or .vtp) when the scan ends"},
    {"export-trajectory", "FILE", "write the camera path (TUM) when the scan ends"},
    {"quit-when-done", "", "quit when the scan ends (implied by --offscreen and --snapshot)"},
    {"report-stalls", "", "print the longest event-loop stall (QTimer probe) measured while the scan ran"},
    {"trace-slow-events", "MS", "write every event that takes longer than MS milliseconds to stderr (what a stall was)"},
};

void addOptions(QCommandLineParser& parser) {
  for (const OptionSpec& spec : kOptions) {
    QCommandLineOption option(spec.name, spec.description);
    if (*spec.valueName) option.setValueName(spec.valueName);
    parser.addOption(option);
  }
  parser.addHelpOption();
}

bool positiveInteger(const QString& option, const QString& text, int& value, QString& error) {
  bool ok = false;
  const long long number = text.toLongLong(&ok);
  if (!ok || number <= 0 || number > 1000000) {
    error = QString("%1 needs a positive integer, not '%2'").arg(option, text);
    return false;
  }
  value = static_cast<int>(number);
  return true;
}

bool number(const QString& option, const QString& text, double& value, QString& error) {
  bool ok = false;
  value = text.toDouble(&ok);
  if (!ok || !std::isfinite(value)) {
    error = QString("%1 needs a number, not '%2'").arg(option, text);
    return false;
  }
  return true;
}

}  // namespace

QString qTissueMosaicCommandLine::helpText() {
  QCommandLineParser parser;
  parser.setApplicationDescription(
      "The TissueMosaic desktop application: open a stereo video (or the demo) and its calibration, reconstruct the\n"
      "tissue surface live (growing textured model, camera frusta, video, disparity), export the model and the\n"
      "camera path, register the model to a CT/MR surface.\n\n"
      "Input and geometry as `tissuemosaic reconstruct`: --left-frames/--right-frames, --left-video/--right-video\n"
      "or --video, with --calib rig.yml [--rectified] or --focal-px F --baseline-mm B for rectified frames.");
  addOptions(parser);
  QString text = parser.helpText();
  text.replace("Usage: ", "usage: ");
  return text;
}

bool qTissueMosaicCommandLine::parse(const QStringList& arguments, QString& error) {
  QCommandLineParser parser;
  parser.setSingleDashWordOptionMode(QCommandLineParser::ParseAsLongOptions);
  addOptions(parser);
  if (!parser.parse(arguments)) {
    error = parser.errorText();
    return false;
  }
  if (!parser.positionalArguments().isEmpty()) {
    error = QString("unexpected argument '%1' (options start with --)").arg(parser.positionalArguments().first());
    return false;
  }
  this->help = parser.isSet("help");
  if (this->help) return true;
  const auto text = [&](const char* name, QString& value) {
    if (parser.isSet(name)) value = parser.value(name);
  };
  text("left-frames", this->leftFrames);
  text("right-frames", this->rightFrames);
  text("left-video", this->leftVideo);
  text("right-video", this->rightVideo);
  text("video", this->video);
  text("calib", this->calibration);
  text("device", this->device);
  text("params", this->params);
  text("snapshot", this->snapshot);
  text("export-model", this->exportModel);
  text("export-trajectory", this->exportTrajectory);
  this->rectified = parser.isSet("rectified");
  this->start = parser.isSet("start");
  this->demo = parser.isSet("demo");
  this->offscreen = parser.isSet("offscreen");
  this->quitWhenDone = parser.isSet("quit-when-done");
  this->reportStalls = parser.isSet("report-stalls");

  const std::map<const char*, double*> numbers = {{"focal-px", &this->focalPx}, {"baseline-mm", &this->baselineMm},
                                                  {"cx-px", &this->cxPx},       {"cy-px", &this->cyPx},
                                                  {"doffs-px", &this->doffsPx}, {"fps", &this->fps}};
  for (const auto& [name, value] : numbers) {
    if (parser.isSet(name) && !number(QString("--") + name, parser.value(name), *value, error)) return false;
  }
  const std::map<const char*, int*> integers = {{"demo-frames", &this->demoFrames},
                                                {"snapshot-frame", &this->snapshotFrame},
                                                {"trace-slow-events", &this->slowEventMs}};
  for (const auto& [name, value] : integers) {
    if (parser.isSet(name) && !positiveInteger(QString("--") + name, parser.value(name), *value, error)) return false;
  }
  if (parser.isSet("demo-size")) {
    const QStringList size = parser.value("demo-size").split('x');
    if (size.size() != 2) {
      error = "--demo-size must be WIDTHxHEIGHT, e.g. 480x270";
      return false;
    }
    if (!positiveInteger("--demo-size", size[0], this->demoWidth, error) ||
        !positiveInteger("--demo-size", size[1], this->demoHeight, error)) {
      return false;
    }
  }

  // The checks and words of `tissuemosaic reconstruct`.
  const bool folders = !this->leftFrames.isEmpty() || !this->rightFrames.isEmpty();
  const bool videos = !this->leftVideo.isEmpty() || !this->rightVideo.isEmpty();
  const bool sideBySide = !this->video.isEmpty();
  if (folders + videos + sideBySide > 1) {
    error = "give exactly one input: --left-frames/--right-frames, --left-video/--right-video or --video";
    return false;
  }
  const std::pair<const QString*, const char*> partners[] = {{&this->leftFrames, "left-frames"},
                                                             {&this->rightFrames, "right-frames"},
                                                             {&this->leftVideo, "left-video"},
                                                             {&this->rightVideo, "right-video"}};
  for (const auto& [value, name] : partners) {
    const bool needed = QString(name).endsWith("frames") ? folders : videos;
    if (needed && value->isEmpty()) {
      error = QString("missing required option --%1").arg(name);
      return false;
    }
  }
  if (!(this->fps > 0)) {
    error = "--fps must be positive";
    return false;
  }
  const bool pinhole = parser.isSet("focal-px") || parser.isSet("baseline-mm");
  if (this->rectified && this->calibration.isEmpty()) {
    error = "--rectified needs --calib: it says the frames were rectified with that calibration";
    return false;
  }
  if (!this->calibration.isEmpty() && pinhole) {
    error = "give either --calib or --focal-px/--baseline-mm, not both";
    return false;
  }
  if (pinhole && (!(this->focalPx > 0) || !(this->baselineMm > 0))) {
    error = !(this->focalPx > 0) ? "--focal-px must be a positive number of pixels"
                                 : "--baseline-mm must be a positive number of mm";
    return false;
  }
  if (this->hasInput() && this->calibration.isEmpty() && !pinhole) {
    error = "give the geometry: --calib rig.yml, or --focal-px and --baseline-mm for rectified frames";
    return false;
  }
  if (pinhole && !this->hasInput()) {
    error = "--focal-px/--baseline-mm describe an input's frames: give the input too";
    return false;
  }
  if (this->demo && this->hasInput()) {
    error = "give either --demo or an input, not both";
    return false;
  }
  if (this->start && !this->hasInput() && !this->demo) {
    error = "--start needs an input: --left-frames/--right-frames, --left-video/--right-video or --video";
    return false;
  }
  if (this->device != "auto" && this->device != "cpu" && this->device != "cuda") {
    error = "--device must be cpu, cuda or auto";
    return false;
  }
  if (this->snapshotFrame > 0 && this->snapshot.isEmpty()) {
    error = "--snapshot-frame needs --snapshot";
    return false;
  }
  if (this->offscreen || !this->snapshot.isEmpty()) this->quitWhenDone = true;
  if (this->quitWhenDone && this->hasInput() && !this->start) {
    error = "--offscreen, --snapshot and --quit-when-done end with the scan: add --start to begin it";
    return false;
  }
  return true;
}

bool qTissueMosaicCommandLine::hasInput() const {
  return !this->leftFrames.isEmpty() || !this->rightFrames.isEmpty() || !this->leftVideo.isEmpty() ||
         !this->rightVideo.isEmpty() || !this->video.isEmpty();
}

bool qTissueMosaicCommandLine::openInput(qTissueMosaicReconstructionWidget* panel, QString& error) const {
  bool ok = true;
  if (!this->leftFrames.isEmpty()) ok = panel->openFrameFolders(this->leftFrames, this->rightFrames, this->fps);
  else if (!this->leftVideo.isEmpty()) ok = panel->openVideoPair(this->leftVideo, this->rightVideo);
  else if (!this->video.isEmpty()) ok = panel->openSideBySideVideo(this->video);
  if (ok && !this->calibration.isEmpty()) {
    ok = panel->loadCalibration(this->calibration);
    panel->setInputRectified(this->rectified);
  }
  if (!ok) {
    error = panel->lastMessage();
    return false;
  }
  if (this->hasPinholeGeometry()) {
    // The geometry of rectified frames exactly as `tissuemosaic reconstruct` makes it from the same options.
    vtkTissueMosaicReconstructionLogic* logic = panel->reconstructionLogic();
    try {
      logic->SetRectifiedGeometry(tissuemosaic::rectifiedGeometryFromPinhole(
          logic->GetInputFrameSize(), this->focalPx, this->baselineMm, this->cxPx, this->cyPx, this->doffsPx));
    } catch (const std::exception& failure) {
      error = failure.what();
      return false;
    }
    panel->setInputRectified(true);  // shows the geometry's state
  }
  return true;
}
