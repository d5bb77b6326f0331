// tissuemosaic-view-benchmark: how the desktop application's 3D view copes with a large model. Builds a textured
// surface of N points (default 2 million, the size of the paper's models), hands it to the view the way the logic
// does (updateGrowingModel), and prints one JSON object: the OpenGL renderer, the time of the model update and of
// the first render (data upload), and the frame rate while the camera turns (what interaction feels like): VTK's
// drawing alone, and as shown, each frame also composed into the window by Qt ("_shown").
// Runs headless: a private Xvfb is started when there is no display.
#include "qTissueMosaicModelView.h"
#include "vtkTissueMosaicDisplay.h"
#include "vtkTissueMosaicGrowingModel.h"
#include "vtkTissueMosaicModelScene.h"
#include "vtkTissueMosaicSnapshot.h"

#include "Core/StereoRig.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkNew.h>
#include <vtkActor.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QSurfaceFormat>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char** argv) {
  long long points = 2000000;
  int frames = 30, width = 1280, height = 800;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string option = argv[i];
    if (option == "--points") points = std::atoll(argv[i + 1]);
    else if (option == "--frames") frames = std::atoi(argv[i + 1]);
    else if (option == "--size") std::sscanf(argv[i + 1], "%dx%d", &width, &height);
  }
  const tissuemosaic::XDisplayStatus display = tissuemosaic::ensureXDisplay();
  setenv("QT_QPA_PLATFORM", "xcb", 1);
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication application(argc, argv);

  // A gently curved, textured sheet of tissue colours, 100 x 100 mm, 80-100 mm in front of the scope.
  tissuemosaic::ColoredPointCloud cloud;
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(points))));
  cloud.pointsMm.reserve(points);
  cloud.colorsRgb.reserve(points);
  cloud.normals.reserve(points);
  for (long long i = 0; i < points; ++i) {
    const float x = -50.f + 100.f * (i % side) / side, y = -50.f + 100.f * (i / side) / side;
    cloud.pointsMm.emplace_back(x, y, 90.f + 0.002f * (x * x + y * y) + 2.f * std::sin(0.2f * x) * std::cos(0.15f * y));
    const float texture = 0.5f + 0.5f * std::sin(1.7f * x + 0.3f * y) * std::sin(1.3f * y);
    cloud.colorsRgb.emplace_back(uchar(170 + 60 * texture), uchar(70 + 50 * texture), uchar(60 + 40 * texture));
    cloud.normals.emplace_back(0.f, 0.f, -1.f);
  }

  qTissueMosaicModelView view;
  view.resize(width, height);
  view.show();
  QApplication::processEvents();
  vtkNew<vtkPolyData> model;
  view.setSceneData(model, nullptr, nullptr, nullptr);
  QElapsedTimer timer;
  timer.start();
  tissuemosaic::updateGrowingModel(model, cloud);
  const double updateMs = timer.nsecsElapsed() * 1e-6;
  timer.restart();
  view.render();  // uploads the points
  view.renderWindow()->WaitForCompletion();
  const double firstRenderMs = timer.nsecsElapsed() * 1e-6;
  const double fps = view.measureFrameRate(frames);
  const double interactiveFps = view.measureFrameRate(frames, true);
  // The same two as the user sees them: each frame composed into the window as well.
  const double shownFps = view.measureFrameRate(frames, false, true);
  const double shownInteractiveFps = view.measureFrameRate(frames, true, true);
  view.scene()->SetInteracting(true);
  const vtkIdType interactivePoints = view.scene()->GetDrawnModelPoints();
  view.scene()->SetInteracting(false);

  std::cout << "{\"renderer\": \"" << tissuemosaic::openGlRendererName() << "\", \"display\": \"" << display.description
            << "\", \"points\": " << model->GetNumberOfPoints() << ", \"view_px\": [" << width << ", " << height
            << "], \"model_update_ms\": " << updateMs << ", \"first_render_ms\": " << firstRenderMs
            << ", \"full_model_fps\": " << fps << ", \"interacting_fps\": " << interactiveFps
            << ", \"interacting_points\": " << interactivePoints << ", \"full_model_fps_shown\": " << shownFps
            << ", \"interacting_fps_shown\": " << shownInteractiveFps << "}" << std::endl;
  return 0;
}
