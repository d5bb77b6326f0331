// The 3D view (qTissueMosaicModelView): its level of detail during a scan (what a live render draws before and after
// the view knows its own speed, and the full model once the scan ends), and how its renders share the event loop.
#include "qTissueMosaicModelView.h"
#include "vtkTissueMosaicModelScene.h"
#include "vtkTissueMosaicPointCloud.h"

#include "Core/StereoRig.h"

#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <vtkActor.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkRenderWindow.h>

namespace {

/// A flat, striped sheet of `columns` x `rows` points 100 mm in front of the world origin.
tissuemosaic::ColoredPointCloud sheet(int columns, int rows) {
  tissuemosaic::ColoredPointCloud cloud;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      cloud.pointsMm.emplace_back(-40.f + 80.f * c / (columns - 1), -30.f + 60.f * r / (rows - 1), 100.f);
      cloud.colorsRgb.emplace_back(static_cast<unsigned char>(c % 2 ? 220 : 60), 90, 70);
      cloud.normals.emplace_back(0.f, 0.f, -1.f);
    }
  }
  return cloud;
}

}  // namespace

TEST(ModelView, LiveRendersOfALargeModelStayReducedUntilTheScanEnds) {
  const vtkIdType points = 400 * 250;
  vtkSmartPointer<vtkPolyData> model = tissuemosaic::pointCloudToPolyData(sheet(400, 250));
  qTissueMosaicModelView view;
  view.resize(480, 360);
  view.show();
  view.setInteractiveFrameTimeMs(1e-3);  // far below any real frame: every live render is reduced
  view.setSceneData(model, nullptr, nullptr, nullptr);
  EXPECT_EQ(view.renderWindow()->GetMultiSamples(), 0) << "software OpenGL pays per sample";

  view.setLiveUpdates(true);
  view.render();
  // The first live render cannot know how fast this view draws: the smallest subsample, not the full model.
  const vtkIdType firstLive = view.scene()->GetDrawnModelPoints();
  EXPECT_GT(firstLive, 0);
  EXPECT_LE(firstLive, 20000);
  view.render();  // with the speed now measured, the budget of a 1 us frame is the floor: still reduced
  EXPECT_LE(view.scene()->GetDrawnModelPoints(), 20000);

  view.renderFullModel();  // pictures always show every point
  EXPECT_EQ(view.scene()->GetDrawnModelPoints(), points);
  view.render();
  EXPECT_LE(view.scene()->GetDrawnModelPoints(), 20000) << "back to the live level of detail";

  view.setLiveUpdates(false);
  view.render();
  EXPECT_EQ(view.scene()->GetDrawnModelPoints(), points) << "the scan ended: the full model";

  view.setInteractiveFrameTimeMs(0);  // 0: never reduce
  view.setLiveUpdates(true);
  view.render();
  EXPECT_EQ(view.scene()->GetDrawnModelPoints(), points);
}

// A render and the repaint of the window that shows it run in separate passes of the event loop (on software
// OpenGL each costs tens of milliseconds; back to back they made one stall twice as long).
TEST(ModelView, RenderLeavesTheWindowRepaintToALaterEventLoopPass) {
  vtkSmartPointer<vtkPolyData> model = tissuemosaic::pointCloudToPolyData(sheet(40, 30));
  qTissueMosaicModelView view;
  view.resize(320, 240);
  view.show();
  view.setSceneData(model, nullptr, nullptr, nullptr);
  QCoreApplication::processEvents();

  view.render();
  EXPECT_FALSE(view.vtkWidget()->updatesEnabled()) << "the repaint would run straight after the render";
  QElapsedTimer waited;
  waited.start();
  while (!view.vtkWidget()->updatesEnabled() && waited.elapsed() < 2000) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 10);
  }
  EXPECT_TRUE(view.vtkWidget()->updatesEnabled()) << "the repaint never came";

  view.renderFullModel();  // a picture follows at once: no deferral
  EXPECT_TRUE(view.vtkWidget()->updatesEnabled());
}
