// tissuemosaic-app: the desktop application. With --offscreen it runs on a headless server (a private Xvfb),
// e.g. `tissuemosaic-app --offscreen --demo --snapshot view.png` runs the demo scan and writes a screenshot.
#include "qTissueMosaicApplication.h"
#include "qTissueMosaicCommandLine.h"
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
#include <malloc.h>
#include <functional>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <string>

namespace {

[[noreturn]] void usageError(const QString& message) {
  std::cerr << "tissuemosaic-app: " << message.toStdString() << "\n(see tissuemosaic-app --help)\n";
  std::exit(2);
}

qTissueMosaicCommandLine parse(int argc, char** argv) {
  QStringList arguments;
  for (int i = 0; i < argc; ++i) arguments << QString::fromLocal8Bit(argv[i]);
  qTissueMosaicCommandLine options;
  QString error;
  if (!options.parse(arguments, error)) usageError(error);
  if (options.help) {
    std::cout << qTissueMosaicCommandLine::helpText().toStdString();  // no display needed for the help
    std::exit(0);
  }
  return options;
}

/// An X display before Qt connects to one: Qt's xcb platform and VTK's OpenGL both need it.
bool prepareDisplay(const qTissueMosaicCommandLine& options) {
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

/// Calls `then` once the window is on screen and its 3D view has set up OpenGL (polls every 20 ms).
void whenFirstDrawn(qTissueMosaicMainWindow& window, const std::function<void()>& then) {
  auto* poll = new QTimer(&window);
  QObject::connect(poll, &QTimer::timeout, &window, [&window, poll, then] {
    if (!window.isVisible() || !window.modelView()->vtkWidget()->isValid()) return;
    poll->deleteLater();
    poll->stop();
    QTimer::singleShot(100, &window, then);  // the composition that follows the first paint
  });
  poll->start(20);
}

}  // namespace

int main(int argc, char** argv) {
  // Memory that a large allocation gets fresh from the system is paid for in page faults on first touch, on the
  // thread that touches it: on a virtual machine 20-70 us each, so that a new 4 MB buffer of a video frame or of
  // the renderer cost the GUI thread milliseconds, several times per frame. Freed memory stays in the process
  // for reuse instead (up to glibc's largest threshold, 32 MB; larger arrays are made on the engine's worker).
  // Measured on the 1280x1024 synthetic scan: the GUI thread's longest busy spell 52 -> 21 ms.
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 1024 * 1024 * 1024);
  const qTissueMosaicCommandLine options = parse(argc, argv);
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
  if (options.params && !logic->ReadParametersFile(*options.params)) {
    std::cerr << "tissuemosaic-app: " << logic->GetLastErrorText() << "\n";
    return 2;
  }
  panel->parametersPanel()->setDeviceChoice(options.device.name == "cpu" ? 1 : options.device.name == "cuda" ? 2 : 0);
  panel->parametersPanel()->updateGUIFromParameters();
  // A batch run has no one to answer "quit without exporting?".
  window.setConfirmUnsavedModel(!options.quitWhenDone);
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
                << stalls.ticks() << " probe ticks (5 ms timer) during the scan; the GUI thread was busy "
                << stalls.longestStallBusyMs() << " ms of it, and at most " << stalls.longestBusyMs()
                << " ms between two ticks" << std::endl;
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
        std::cerr << "tissuemosaic-app: " << panel->lastMessage().toStdString() << "\n";
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
  if (options.hasInput() || !options.geometry.calib.empty()) {
    // As Slicer opens the files it is given: the input (and its geometry) in the panel, then --start. Once the
    // window has been drawn: its first paint sets up OpenGL (a second or so on software OpenGL), which is no part
    // of a scan's event-loop stalls.
    whenFirstDrawn(window, [&] {
      QString error;
      if (!options.openInput(panel, error)) {
        std::cerr << "tissuemosaic-app: " << error.toStdString() << "\n";
        exitCode = 2;
        if (options.quitWhenDone) application.exit(2);
        return;
      }
      if (options.start && !panel->start()) {
        std::cerr << "tissuemosaic-app: " << panel->lastMessage().toStdString() << "\n";
        exitCode = 1;
        if (options.quitWhenDone) application.exit(1);
      }
    });
  }
  const int result = application.exec();
  return result != 0 ? result : exitCode;
}
