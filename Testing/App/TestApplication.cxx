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
#include <QElapsedTimer>
#include <QImage>
#include <QSignalSpy>
#include <QTabWidget>

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

  // Slicer-like layout: modules on the left (both), views on the right.
  EXPECT_EQ(window.moduleTabs()->count(), 2);
  EXPECT_EQ(window.moduleTabs()->tabText(0), "Reconstruction");
  EXPECT_EQ(window.moduleTabs()->tabText(1), "Registration");

  qTissueMosaicReconstructionWidget* panel = window.reconstructionPanel();
  vtkTissueMosaicReconstructionLogic* logic = panel->reconstructionLogic();
  // Open: the demo is generated on a worker thread and opened (rectified frames + rig.yml).
  QSignalSpy opened(&window, &qTissueMosaicMainWindow::demoOpened);
  window.openDemo();
  ASSERT_TRUE(runUntil([&] { return opened.count() > 0; }, 120)) << "demo generation timed out";
  ASSERT_TRUE(opened.first().at(0).toBool()) << panel->lastMessage().toStdString();
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
  using Logic = vtkTissueMosaicReconstructionLogic;
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
  EXPECT_EQ(window.videoPanel()->leftImage().size(), QSize(320, 180));
  EXPECT_FALSE(window.videoPanel()->disparityImage().isNull());
  const QString statusText = window.statusText();
  EXPECT_TRUE(statusText.contains(QString("%1 key frames").arg(status.keyFrames))) << statusText.toStdString();
  EXPECT_TRUE(statusText.contains("k points")) << statusText.toStdString();

  // Export.
  ASSERT_TRUE(panel->exportModel(QString::fromStdString(out + "/model.ply"))) << panel->lastMessage().toStdString();
  ASSERT_TRUE(panel->exportTrajectory(QString::fromStdString(out + "/trajectory.txt")))
      << panel->lastMessage().toStdString();
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
}
