// tissuemosaic-app: the desktop application. With --offscreen it runs on a headless server (a private Xvfb),
// e.g. `tissuemosaic-app --offscreen --demo --snapshot view.png` runs the demo scan and writes a screenshot.
#include "qTissueMosaicApplication.h"
#include "qTissueMosaicMainWindow.h"
#include "qTissueMosaicModelView.h"
#include "qTissueMosaicReconstructionParametersWidget.h"
#include "qTissueMosaicReconstructionWidget.h"
#include "qTissueMosaicStallProbe.h"
#include "vtkTissueMosaicDisplay.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include <QVTKOpenGLNativeWidget.h>

#include <QApplication>
#include <QSurfaceFormat>
#include <QTimer>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <string>

namespace {

const char* const help = R"(usage: tissuemosaic-app [options]

The TissueMosaic desktop application: open a stereo video (or the demo) and its calibration, reconstruct the
tissue surface live (growing textured model, camera frusta, video, disparity), export the model and the camera
path, register the model to a CT/MR surface.

options:
  --demo                 generate the bundled synthetic demo scan, open it and start reconstructing
  --demo-frames N        frames of the demo scan (default 60)
  --demo-size WxH        demo frame size (default 480x270)
  --device cpu|cuda|auto where the engine runs (default auto)
  --params FILE          reconstruction parameters (YAML, as the parameter panel saves them)
  --offscreen            headless: render into a private X server (Xvfb; started and stopped by the application,
                         nothing appears on any screen); falls back to $DISPLAY when Xvfb is not installed
  --snapshot FILE.png    write a screenshot of the application when the scan ends (or at --snapshot-frame),
                         then quit
  --snapshot-frame N     take the screenshot once N frames are processed (mid-scan) and stop the scan
  --export-model FILE    write the model (.ply or .vtp) when the scan ends
  --export-trajectory F  write the camera path (TUM) when the scan ends
  --quit-when-done       quit when the scan ends (implied by --offscreen and --snapshot)
  --report-stalls        print the longest event-loop stall (QTimer probe) measured while the scan ran
  --trace-slow-events MS write every event that takes longer than MS milliseconds to stderr (what a stall was)
  -h, --help             this text
)";

struct Options {
  bool demo = false, offscreen = false, quitWhenDone = false, reportStalls = false;
  int demoFrames = 60, demoWidth = 480, demoHeight = 270, snapshotFrame = -1, slowEventMs = 0;
  std::string device = "auto", params, snapshot, exportModel, exportTrajectory;
};

[[noreturn]] void usageError(const std::string& message) {
  std::cerr << "tissuemosaic-app: " << message << "\n(see tissuemosaic-app --help)\n";
  std::exit(2);
}

int positiveInteger(const std::string& option, const char* text) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (!end || *end || value <= 0 || value > 1000000) usageError(option + " needs a positive integer, not '" + text + "'");
  return static_cast<int>(value);
}

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    const auto value = [&]() -> const char* {
      if (i + 1 >= argc) usageError(word + " needs a value");
      return argv[++i];
    };
    if (word == "-h" || word == "--help") {
      std::cout << help;
      std::exit(0);
    } else if (word == "--demo") options.demo = true;
    else if (word == "--offscreen") options.offscreen = true;
    else if (word == "--quit-when-done") options.quitWhenDone = true;
    else if (word == "--report-stalls") options.reportStalls = true;
    else if (word == "--trace-slow-events") options.slowEventMs = positiveInteger(word, value());
    else if (word == "--demo-frames") options.demoFrames = positiveInteger(word, value());
    else if (word == "--demo-size") {
      const std::string size = value();
      const std::size_t x = size.find('x');
      if (x == std::string::npos) usageError("--demo-size must be WIDTHxHEIGHT, e.g. 480x270");
      options.demoWidth = positiveInteger(word, size.substr(0, x).c_str());
      options.demoHeight = positiveInteger(word, size.substr(x + 1).c_str());
    } else if (word == "--snapshot-frame") options.snapshotFrame = positiveInteger(word, value());
    else if (word == "--device") options.device = value();
    else if (word == "--params") options.params = value();
    else if (word == "--snapshot") options.snapshot = value();
    else if (word == "--export-model") options.exportModel = value();
    else if (word == "--export-trajectory") options.exportTrajectory = value();
    else usageError("unknown option '" + word + "'");
  }
  const std::map<std::string, int> devices = {{"auto", 0}, {"cpu", 1}, {"cuda", 2}};
  if (!devices.count(options.device)) usageError("--device must be cpu, cuda or auto");
  if (options.snapshotFrame > 0 && options.snapshot.empty()) usageError("--snapshot-frame needs --snapshot");
  if (options.offscreen || !options.snapshot.empty()) options.quitWhenDone = true;
  return options;
}

/// An X display before Qt connects to one: Qt's xcb platform and VTK's OpenGL both need it.
bool prepareDisplay(const Options& options) {
  try {
    if (options.offscreen) {
      setenv("QT_QPA_PLATFORM", "xcb", 1);  // a GL-capable platform on the private server, whatever the caller set
      const tissuemosaic::XDisplayStatus display = tissuemosaic::ensureXDisplay(true);
      std::cout << "tissuemosaic-app: offscreen on " << display.description << std::endl;
      return true;
    }
    const char* platform = std::getenv("QT_QPA_PLATFORM");
    if (platform && std::strcmp(platform, "xcb") != 0) return true;  // the caller chose another platform
    const char* display = std::getenv("DISPLAY");
    if (tissuemosaic::canOpenXDisplay(display ? display : "")) return true;
    std::cerr << "tissuemosaic-app: no X display" << (display ? std::string(" (cannot open '") + display + "')" : "")
              << ". Run it with --offscreen on a headless machine (a private Xvfb is started), or set DISPLAY.\n";
  } catch (const std::exception& error) {
    std::cerr << "tissuemosaic-app: " << error.what() << "\n";
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  if (!prepareDisplay(options)) return 2;

  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  qTissueMosaicApplication application(argc, argv);
  application.setSlowEventThresholdMs(options.slowEventMs);
  application.setApplicationName("TissueMosaic");

  qTissueMosaicMainWindow window;
  qTissueMosaicReconstructionWidget* panel = window.reconstructionPanel();
  vtkTissueMosaicReconstructionLogic* logic = panel->reconstructionLogic();
  qTissueMosaicDemoInput::Options demo;
  demo.frames = options.demoFrames;
  demo.width = options.demoWidth;
  demo.height = options.demoHeight;
  window.setDemoOptions(demo);
  if (!options.params.empty() && !logic->ReadParametersFile(options.params)) {
    std::cerr << "tissuemosaic-app: " << logic->GetLastErrorText() << "\n";
    return 2;
  }
  panel->parametersPanel()->setDeviceChoice(options.device == "cpu" ? 1 : options.device == "cuda" ? 2 : 0);
  panel->parametersPanel()->updateGUIFromParameters();
  window.show();

  qTissueMosaicStallProbe stalls;
  if (options.slowEventMs > 0) {
    // On the slow-event log's clock, so that each stall can be matched with the events that made it.
    QObject::connect(&stalls, &qTissueMosaicStallProbe::stalled, &application, [&](double stallMs) {
      if (stallMs > options.slowEventMs) {
        std::fprintf(stderr, "tissuemosaic-app: stall of %.1f ms ending at %.1f ms\n", stallMs,
                     application.elapsedMs());
      }
    });
  }
  int exitCode = 0;
  bool finished = false;
  const auto finish = [&](bool scanEnded) {
    if (finished) return;
    finished = true;
    stalls.stop();
    panel->updateFromLogic();
    window.refreshViews();
    const auto& status = logic->GetStatus();
    if (status.state == vtkTissueMosaicReconstructionLogic::StateFailed) {
      std::cerr << "tissuemosaic-app: the scan failed: " << status.errorText << "\n";
      exitCode = 1;
    }
    std::cout << "tissuemosaic-app: " << status.framesProcessed << " frames, " << status.keyFrames << " key frames, "
              << status.modelPoints << " model points, " << status.lostFrames << " lost" << std::endl;
    if (options.reportStalls) {
      std::cout << "tissuemosaic-app: longest event-loop stall " << stalls.longestStallMs() << " ms over "
                << stalls.ticks() << " probe ticks (5 ms timer) during the scan" << std::endl;
    }
    if (!options.exportModel.empty() && !panel->exportModel(QString::fromStdString(options.exportModel))) {
      std::cerr << "tissuemosaic-app: " << panel->lastMessage().toStdString() << "\n";
      exitCode = 1;
    }
    if (!options.exportTrajectory.empty() &&
        !panel->exportTrajectory(QString::fromStdString(options.exportTrajectory))) {
      std::cerr << "tissuemosaic-app: " << panel->lastMessage().toStdString() << "\n";
      exitCode = 1;
    }
    if (!options.snapshot.empty()) {
      // Let the views paint the last results before the picture is taken.
      window.modelView()->renderFullModel();
      QApplication::processEvents();
      if (window.saveScreenshot(QString::fromStdString(options.snapshot))) {
        std::cout << "tissuemosaic-app: screenshot written to " << options.snapshot << std::endl;
      } else {
        std::cerr << "tissuemosaic-app: cannot write the screenshot " << options.snapshot
                  << " (does its folder exist?)\n";
        exitCode = 1;
      }
    }
    if (!scanEnded) panel->stop();
    if (options.quitWhenDone) QTimer::singleShot(0, &application, [&] { application.exit(exitCode); });
  };

  QObject::connect(panel, &qTissueMosaicReconstructionWidget::scanStateChanged, &window, [&](int state) {
    using Logic = vtkTissueMosaicReconstructionLogic;
    if (state == Logic::StateRunning && !stalls.isActive()) stalls.start();
    if (state == Logic::StateFinished || state == Logic::StateStopped || state == Logic::StateFailed) finish(true);
  });
  if (options.snapshotFrame > 0) {
    QObject::connect(panel, &qTissueMosaicReconstructionWidget::outputsUpdated, &window, [&] {
      if (logic->GetStatus().framesProcessed >= options.snapshotFrame) finish(false);
    });
  }
  QObject::connect(&window, &qTissueMosaicMainWindow::demoOpened, &window, [&](bool ok) {
    if (!ok) {
      std::cerr << "tissuemosaic-app: the demo could not be opened\n";
      exitCode = 1;
      if (options.quitWhenDone) application.exit(1);
      return;
    }
    if (!panel->start()) {
      std::cerr << "tissuemosaic-app: " << panel->lastMessage().toStdString() << "\n";
      exitCode = 1;
      if (options.quitWhenDone) application.exit(1);
    }
  });
  if (options.demo) QTimer::singleShot(0, &window, &qTissueMosaicMainWindow::openDemo);
  const int result = application.exec();
  return result != 0 ? result : exitCode;
}
