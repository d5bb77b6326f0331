// The desktop application driven end to end, in-process, on a short synthetic scan: open the demo, run it,
// check the views and the status bar, export the model and the trajectory, take a screenshot; and the event
// loop must keep running throughout (longest stall measured with a QTimer probe).
#include "qTissueMosaicMainWindow.h"
#include "qTissueMosaicModelView.h"
#include "qTissueMosaicReconstructionParametersWidget.h"
#include "qTissueMosaicReconstructionWidget.h"
#include "qTissueMosaicStallProbe.h"
#include "qTissueMosaicVideoPanel.h"
#include "vtkTissueMosaicModelScene.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "IO/PointCloudPly.h"
#include "IO/TrajectoryTum.h"

#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkMapper.h>
#include <vtkPolyData.h>

#include <QApplication>
#include <QTimer>
#include <QTest>
#include <QStatusBar>
#include <QMessageBox>
#include <QLabel>
#include <QAction>
#include <QAbstractButton>
#include <QElapsedTimer>
#include <QImage>
#include <QSignalSpy>
#include <QTabWidget>

#include <cstdio>
#include <filesystem>
#include <set>

namespace {

/// Runs the event loop until done() or timeoutS; true when done.
template <class Done>
bool runUntil(Done done, double timeoutS) {
  QElapsedTimer timer;
  timer.start();
  while (!done()) {
    if (timer.elapsed() > timeoutS * 1000) return false;
    QApplication::processEvents(QEventLoop::AllEvents, 20);
  }
  return true;
}

/// Answers the next message box by clicking the button with this text.
void answerNextMessageBox(const QString& buttonText) {
  auto* poll = new QTimer;
  QObject::connect(poll, &QTimer::timeout, poll, [poll, buttonText] {
    auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
    if (!box) return;
    poll->stop();
    poll->deleteLater();
    for (QAbstractButton* button : box->buttons()) {
      if (button->text().remove('&') == buttonText) QTest::mouseClick(button, Qt::LeftButton);
    }
  });
  poll->start(20);
}

/// Distinct colours in a region of an image (a flat background has one or two).
int distinctColours(const QImage& image, const QRect& region) {
  std::set<QRgb> colours;
  for (int y = region.top(); y <= region.bottom(); y += 3) {
    for (int x = region.left(); x <= region.right(); x += 3) colours.insert(image.pixel(x, y));
  }
  return static_cast<int>(colours.size());
}

}  // namespace

TEST(Application, DemoScanEndToEnd) {
  const std::string out = std::string(TM_TEST_OUTPUT_DIR) + "/application";
  std::filesystem::create_directories(out);
  qTissueMosaicMainWindow window;
  qTissueMosaicDemoInput::Options demo;
  demo.width = 320;
  demo.height = 180;
  demo.frames = 12;
  window.setDemoOptions(demo);
  window.resize(1280, 800);
  window.show();
  ASSERT_TRUE(runUntil([&] { return window.isVisible(); }, 10));

  // Slicer-like layout: modules on the left (both, and the OpenIGTLink link where built), views on the right.
#if defined(TM_WITH_IGTLINK)
  EXPECT_EQ(window.moduleTabs()->count(), 3);
  EXPECT_EQ(window.moduleTabs()->tabText(2), "OpenIGTLink");
#else
  EXPECT_EQ(window.moduleTabs()->count(), 2);
#endif
  EXPECT_EQ(window.moduleTabs()->tabText(0), "Reconstruction");
  EXPECT_EQ(window.moduleTabs()->tabText(1), "Registration");

  qTissueMosaicReconstructionWidget* panel = window.reconstructionPanel();
  vtkTissueMosaicReconstructionLogic* logic = panel->reconstructionLogic();
  // Menu items act only when they can: nothing to export, start or pause yet.
  for (const char* name : {"exportModelAction", "exportTrajectoryAction", "startAction", "pauseAction", "stopAction"}) {
    EXPECT_FALSE(window.action(name)->isEnabled()) << name;
  }
  // Open: the demo is generated on a worker thread and opened (rectified frames + rig.yml).
  QSignalSpy opened(&window, &qTissueMosaicMainWindow::demoOpened);
  window.openDemo();
  ASSERT_TRUE(runUntil([&] { return opened.count() > 0; }, 120)) << "demo generation timed out";
  ASSERT_TRUE(opened.first().at(0).toBool()) << panel->lastMessage().toStdString();
  EXPECT_EQ(panel->lastMessage(), "Demo ready: press Start (F5)");
  EXPECT_TRUE(window.action("startAction")->isEnabled());
  EXPECT_EQ(logic->GetInputFrameCount(), 12);
  EXPECT_TRUE(logic->HasCalibration());
  EXPECT_TRUE(logic->GetInputRectified());

  // A narrower disparity range for speed (the demo's disparities are about 15-25 px at this size).
  tissuemosaic::ReconstructionParameters parameters = panel->parametersPanel()->parameters();
  parameters.stereo.setFixedDisparityRange(0, 40);
  parameters.tracking.keyFrameMinGapFrames = 4;
  parameters.tracking.keyFramePoseThreshold = 2.0;
  ASSERT_TRUE(panel->parametersPanel()->setParameters(parameters)) << panel->parametersPanel()->errorText().toStdString();
  panel->parametersPanel()->setDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);

  // Run, with the event loop watched the whole time.
  qTissueMosaicStallProbe probe;
  probe.start();
  ASSERT_TRUE(panel->start()) << panel->lastMessage().toStdString();
  // "Demo ready: press Start" must not stay while the demo runs.
  EXPECT_TRUE(panel->findChild<QLabel*>("inputMessage")->isHidden());
  EXPECT_TRUE(window.statusBar()->currentMessage().isEmpty()) << window.statusBar()->currentMessage().toStdString();
  using Logic = vtkTissueMosaicReconstructionLogic;
  // Paused: no frame rate as if frames still flowed.
  ASSERT_TRUE(runUntil([&] { return logic->GetStatus().framesProcessed >= 2; }, 120));
  panel->pause();
  ASSERT_TRUE(runUntil([&] { return logic->GetStatus().state == Logic::StatePaused; }, 30));
  panel->updateFromLogic();
  EXPECT_TRUE(window.statusText().contains("| paused |")) << window.statusText().toStdString();
  EXPECT_TRUE(window.action("startAction")->isEnabled()) << "Start resumes";
  EXPECT_FALSE(window.action("pauseAction")->isEnabled());
  ASSERT_TRUE(panel->start()) << panel->lastMessage().toStdString();
  ASSERT_TRUE(runUntil([&] { return logic->GetStatus().state == Logic::StateFinished ||
                                    logic->GetStatus().state == Logic::StateFailed; },
                       180))
      << "scan timed out";
  probe.stop();
  ASSERT_EQ(logic->GetStatus().state, Logic::StateFinished) << logic->GetStatus().errorText;
  std::cout << "[ measured ] longest event-loop stall " << probe.longestStallMs() << " ms (" << probe.ticks()
            << " ticks of a 5 ms timer) during a " << logic->GetStatus().elapsedS << " s scan\n";
  // A GUI that waited for the worker would stall for whole frames (here ~0.3-1 s each) or the whole scan; one that
  // rendered and composed the window in one pass, about twice the measured figure. Measured here: 67 ms
  // (docs/DESKTOP.md); the bound leaves room for a busy CI machine with 2 shared cores and software OpenGL (Mesa
  // llvmpipe) running another test beside this one.
  EXPECT_LT(probe.longestStallMs(), 500.0);
  // ... and the loop ran all along: on average at least one 5 ms tick per 50 ms.
  EXPECT_GT(probe.ticks(), logic->GetStatus().elapsedS * 1000 / 50) << "the event loop was starved";

  // Views and status show the result.
  const auto& status = logic->GetStatus();
  EXPECT_EQ(status.framesProcessed, 12);
  EXPECT_GE(status.keyFrames, 2);
  EXPECT_GT(status.modelPoints, 10000);
  QApplication::processEvents();
  vtkTissueMosaicModelScene* scene = window.modelView()->scene();
  window.modelView()->renderFullModel();  // a live scan may have drawn a subsample (level of detail)
  auto* drawn = vtkPolyData::SafeDownCast(scene->GetModelActor()->GetMapper()->GetInput());
  ASSERT_NE(drawn, nullptr);
  EXPECT_EQ(drawn, logic->GetModel()) << "the 3D view draws the logic's model";
  EXPECT_EQ(scene->GetDrawnModelPoints(), status.modelPoints);
  EXPECT_TRUE(scene->GetKeyFrameFrustaActor()->GetVisibility());
  EXPECT_EQ(window.videoPanel()->frameSize(), QSize(320, 180));
  EXPECT_FALSE(window.videoPanel()->disparityImage().isNull());
  const QString statusText = window.statusText();
  EXPECT_TRUE(statusText.contains(QString("%1 key frames").arg(status.keyFrames))) << statusText.toStdString();
  EXPECT_TRUE(statusText.contains("k points")) << statusText.toStdString();

  EXPECT_TRUE(window.statusText().contains("fps average")) << window.statusText().toStdString();
  for (const char* name : {"exportModelAction", "exportTrajectoryAction", "resetAction"}) {
    EXPECT_TRUE(window.action(name)->isEnabled()) << name;
  }
  EXPECT_FALSE(window.action("startAction")->isEnabled()) << "an ended scan is reset, not restarted";

  // Quitting with a model never exported asks first: Cancel keeps the window, Quit without exporting closes it.
  ASSERT_TRUE(panel->hasUnexportedModel());
  answerNextMessageBox("Cancel");
  EXPECT_FALSE(window.close());
  EXPECT_TRUE(window.isVisible());
  answerNextMessageBox("Quit without exporting");
  EXPECT_TRUE(window.close());
  EXPECT_FALSE(window.isVisible());
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));

  // Export.
  ASSERT_TRUE(panel->exportModel(QString::fromStdString(out + "/model.ply"))) << panel->lastMessage().toStdString();
  EXPECT_FALSE(panel->hasUnexportedModel()) << "exported: closing needs no question";
  ASSERT_TRUE(panel->exportTrajectory(QString::fromStdString(out + "/trajectory.txt")))
      << panel->lastMessage().toStdString();
  EXPECT_TRUE(panel->lastMessage().startsWith("Trajectory written")) << panel->lastMessage().toStdString();
  // A screenshot that cannot be written says why, in place of the earlier confirmation.
  EXPECT_FALSE(window.saveScreenshot("/nonexistent-folder/shot.png"));
  EXPECT_EQ(panel->lastMessage(),
            "The screenshot was not saved: the folder /nonexistent-folder does not exist.");
  EXPECT_EQ(static_cast<long long>(tissuemosaic::readPly(out + "/model.ply").size()), status.modelPoints);
  EXPECT_EQ(tissuemosaic::readTumTrajectory(out + "/trajectory.txt").size(), 12u);

  // Screenshot of the whole window, with the 3D view's OpenGL content in it.
  const QString screenshot = QString::fromStdString(out + "/window.png");
  ASSERT_TRUE(window.saveScreenshot(screenshot));
  const QImage picture(screenshot);
  ASSERT_FALSE(picture.isNull());
  EXPECT_EQ(picture.size(), window.size() * window.devicePixelRatioF());
  const QRect viewArea(window.modelView()->mapTo(&window, QPoint(0, 0)), window.modelView()->size());
  EXPECT_GT(distinctColours(picture, viewArea), 50) << "the 3D view is blank in the screenshot";

  // Reset drops the results.
  panel->reset();
  EXPECT_EQ(logic->GetModel()->GetNumberOfPoints(), 0);
  EXPECT_EQ(logic->GetScanState(), Logic::StateIdle);

  // Another input: the progress counts its frames, not the last scan's.
  const std::string other = out + "/four-frames";
  for (const char* side : {"left", "right"}) {
    std::filesystem::create_directories(other + "/" + side);
    for (int i = 0; i < 4; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "/%06d.png", i);
      std::filesystem::copy_file(window.demoDirectory().toStdString() + "/" + side + name, other + "/" + side + name,
                                 std::filesystem::copy_options::overwrite_existing);
    }
  }
  ASSERT_TRUE(panel->openFrameFolders(QString::fromStdString(other + "/left"), QString::fromStdString(other + "/right")));
  QApplication::processEvents();
  EXPECT_TRUE(window.statusText().endsWith("frame 0 / 4")) << window.statusText().toStdString();
}
