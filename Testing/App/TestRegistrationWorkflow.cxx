// Registration driven as a surgeon would, with mouse clicks and key presses (QTest) in the application window:
// open and scan the demo, switch to the Registration module, load a CT/MR surface through the file dialog (the
// synthetic scan's true surface moved by a known transform), pick four landmark pairs by clicking in the view,
// register, refine with ICP, read the results and export the transform through the save dialog. The known
// transform is the ground truth of every figure checked.
#include "LayoutInspection.h"
#include "qTissueMosaicMainWindow.h"
#include "qTissueMosaicReconstructionParametersWidget.h"
#include "qTissueMosaicReconstructionWidget.h"
#include "qTissueMosaicRegistrationView.h"
#include "qTissueMosaicRegistrationWidget.h"
#include "vtkTissueMosaicItkTransformFile.h"
#include "vtkTissueMosaicReconstructionLogic.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicRegistrationLogic.h"
#include "vtkTissueMosaicSurfaceDistance.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include "IO/TrajectoryTum.h"
#include "TestRegistrationScene.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <QApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStackedWidget>
#include <QTabBar>
#include <QTabWidget>
#include <QTest>
#include <QTimer>

#include <cmath>
#include <cstdio>

using namespace tissuemosaic;

namespace {

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

void click(QWidget* root, const char* buttonName) {
  auto* button = root->findChild<QPushButton*>(buttonName);
  ASSERT_NE(button, nullptr) << buttonName;
  ASSERT_TRUE(button->isEnabled()) << buttonName << " is disabled: " << button->toolTip().toStdString();
  QTest::mouseClick(button, Qt::LeftButton);
}

/// Answers the next file dialog as a user does: types the path into its file name field and presses Enter.
void answerNextFileDialog(const QString& path) {
  auto* poll = new QTimer;
  QObject::connect(poll, &QTimer::timeout, poll, [poll, path] {
    auto* dialog = qobject_cast<QFileDialog*>(QApplication::activeModalWidget());
    if (!dialog) return;
    poll->stop();
    poll->deleteLater();
    auto* name = dialog->findChild<QLineEdit*>("fileNameEdit");
    if (name) {
      name->clear();
      QTest::keyClicks(name, path);
      QTest::keyClick(name, Qt::Key_Return);
    }
    if (dialog->isVisible()) {  // a dialog that wanted more (a confirmation): take the typed file
      dialog->selectFile(path);
      QMetaObject::invokeMethod(dialog, "accept");
    }
  });
  poll->start(50);
}

Eigen::Vector3d mapped(const Eigen::Matrix4d& transform, const Eigen::Vector3d& point) {
  return transform.topLeftCorner<3, 3>() * point + transform.topRightCorner<3, 1>();
}

/// Largest distance between where two transforms put the model's points.
double largestDisplacementMm(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, const std::vector<Eigen::Vector3d>& points) {
  double largest = 0;
  for (const Eigen::Vector3d& point : points) largest = std::max(largest, (mapped(a, point) - mapped(b, point)).norm());
  return largest;
}

}  // namespace

TEST(RegistrationWorkflow, ScanPickRegisterRefineExportByMouseAndKeyboard) {
  QApplication::setAttribute(Qt::AA_DontUseNativeDialogs);
  const QString dir = QString(TM_TEST_OUTPUT_DIR) + "/registration-workflow";
  QDir(dir).removeRecursively();
  QDir().mkpath(dir);
  qTissueMosaicMainWindow window;
  window.setConfirmUnsavedModel(false);
  qTissueMosaicDemoInput::Options demo;
  demo.width = 320;
  demo.height = 180;
  demo.frames = 12;
  window.setDemoOptions(demo);
  window.resize(1280, 800);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  qTissueMosaicReconstructionWidget* scanPanel = window.reconstructionPanel();
  vtkTissueMosaicReconstructionLogic* scan = scanPanel->reconstructionLogic();

  // Scan the demo: Open demo, a narrower disparity range typed into its fields, Start.
  QSignalSpy opened(&window, &qTissueMosaicMainWindow::demoOpened);
  click(scanPanel, "openDemoButton");
  ASSERT_TRUE(runUntil([&] { return opened.count() > 0; }, 120)) << "demo generation timed out";
  ASSERT_TRUE(opened.first().at(0).toBool()) << scanPanel->lastMessage().toStdString();
  for (const auto& [name, value] : {std::pair{"maxDisparityPxSpinBox", 40}, std::pair{"minDisparityPxSpinBox", 0}}) {
    auto* field = scanPanel->findChild<QSpinBox*>(name);
    ASSERT_NE(field, nullptr);
    field->setFocus();
    field->selectAll();
    QTest::keyClicks(field, QString::number(value));
    QTest::keyClick(field, Qt::Key_Tab);
  }
  ASSERT_EQ(scan->GetParameters().stereo.maxDisparityPx, 40);
  scanPanel->parametersPanel()->setDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
  click(scanPanel, "startButton");
  using Scan = vtkTissueMosaicReconstructionLogic;
  // The state the app has taken with the outputs (the worker's can be ahead of the model shown).
  const auto takenState = [&] { return scan->GetStatus().state; };
  ASSERT_TRUE(runUntil([&] { return takenState() == Scan::StateFinished || takenState() == Scan::StateFailed; }, 180));
  ASSERT_EQ(takenState(), Scan::StateFinished) << scan->GetStatus().errorText;
  QApplication::processEvents();
  const vtkIdType modelPoints = scan->GetModel()->GetNumberOfPoints();
  ASSERT_GT(modelPoints, 10000);

  // The Registration module: its scene takes the view area, the live scan is the model.
  QTabBar* tabs = window.moduleTabs()->tabBar();
  QTest::mouseClick(tabs, Qt::LeftButton, Qt::NoModifier, tabs->tabRect(1).center());
  ASSERT_EQ(window.moduleTabs()->currentIndex(), 1);
  EXPECT_EQ(window.viewArea()->currentWidget(), window.registrationPanel()->sceneView());
  qTissueMosaicRegistrationWidget* panel = window.registrationPanel();
  vtkTissueMosaicRegistrationLogic* registration = panel->registrationLogic();
  EXPECT_TRUE(panel->usesCurrentScan());
  EXPECT_EQ(registration->GetModel(), scan->GetModel());
  EXPECT_TRUE(panel->shownModelText().contains(QLocale().toString(static_cast<qlonglong>(modelPoints))))
      << panel->shownModelText().toStdString();
  // The view is framed on the scan (which had no points when the module was made) and draws it in its colours.
  QApplication::processEvents();
  double focal[3], bounds[6];
  panel->sceneView()->renderer()->GetActiveCamera()->GetFocalPoint(focal);
  scan->GetModel()->GetBounds(bounds);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GE(focal[axis], bounds[2 * axis] - 1) << "axis " << axis;
    EXPECT_LE(focal[axis], bounds[2 * axis + 1] + 1) << "axis " << axis;
  }
  EXPECT_TRUE(panel->sceneView()->modelActor()->GetVisibility());
  EXPECT_FALSE(panel->sceneView()->modelActor()->GetProperty()->GetLighting()) << "lit points facing away are black";

  // The CT/MR surface: the scan's true surface, in the reconstruction's frame (the first camera's), moved by a
  // known transform (12 degrees, 15 mm), as a segmentation would put it in the CT's frame.
  const Trajectory truth = readTumTrajectory((window.demoDirectory() + "/groundtruth/trajectory.txt").toStdString());
  ASSERT_FALSE(truth.empty());
  const Eigen::Matrix4d knownTargetFromModel = test::rigidTransform({0.3, -0.5, 1}, 12, {0, 0, 80}, {15, -10, 5});
  const SurfaceModelFile surface = readSurfaceModel((window.demoDirectory() + "/groundtruth/surface.ply").toStdString());
  const Eigen::Matrix4d ctFromWorld = knownTargetFromModel * truth.front().T_world_camera.inverse();
  const QString ctPath = dir + "/ct-surface.vtk";
  writeSurfaceModel(ctPath.toStdString(), transformedPolyData(surface.polyDataLps, ctFromWorld));
  answerNextFileDialog(ctPath);
  click(panel, "loadTargetButton");
  ASSERT_NE(registration->GetTarget(), nullptr) << panel->errorText().toStdString();

  // Four landmark pairs, each a click on the model and a click on the CT/MR surface at the same anatomy.
  qTissueMosaicRegistrationView* view = panel->sceneView();
  view->render();
  vtkRenderer* renderer = view->renderer();
  QWidget* surfaceWidget = view->vtkWidget();
  const auto widgetPosition = [&](const Eigen::Vector3d& world) {
    renderer->SetWorldPoint(world.x(), world.y(), world.z(), 1.0);
    renderer->WorldToDisplay();
    const double* display = renderer->GetDisplayPoint();
    const double ratio = surfaceWidget->devicePixelRatioF();
    return QPoint(static_cast<int>(std::lround(display[0] / ratio)),
                  surfaceWidget->height() - 1 - static_cast<int>(std::lround(display[1] / ratio)));
  };
  // Four scan points around the model's middle, spread in x and y.
  const std::vector<Eigen::Vector3d> points = polyDataPoints(scan->GetModel());
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centre += p;
  centre /= static_cast<double>(points.size());
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) spread += (p - centre).cwiseAbs();
  spread /= static_cast<double>(points.size());
  const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  std::vector<Eigen::Vector3d> chosen;
  for (const auto& corner : corners) {
    const Eigen::Vector2d goal(centre.x() + corner[0] * spread.x(), centre.y() + corner[1] * spread.y());
    const Eigen::Vector3d* best = &points.front();
    for (const Eigen::Vector3d& p : points) {
      if ((p.head<2>() - goal).norm() < (best->head<2>() - goal).norm()) best = &p;
    }
    chosen.push_back(*best);
  }
  for (const Eigen::Vector3d& modelPoint : chosen) {
    click(panel, "pickModelButton");
    QTest::mouseClick(surfaceWidget, Qt::LeftButton, Qt::NoModifier, widgetPosition(modelPoint));
    click(panel, "pickTargetButton");
    QTest::mouseClick(surfaceWidget, Qt::LeftButton, Qt::NoModifier, widgetPosition(mapped(knownTargetFromModel, modelPoint)));
  }
  ASSERT_EQ(registration->GetNumberOfLandmarkPairs(), 4) << panel->lastMessage().toStdString();
  ASSERT_EQ(registration->GetNumberOfCompleteLandmarkPairs(), 4) << panel->lastMessage().toStdString();
  for (int i = 0; i < 4; ++i) {
    const auto& pair = registration->GetLandmarkPair(i);
    // The model landmark is the scan point clicked (or one next to it); the CT/MR one is where its ray meets the
    // surface, near the true position of that scan point (the scan's own error, about a millimetre).
    EXPECT_LT((*pair.modelLps - chosen[i]).norm(), 1.0) << "pair " << i;
    EXPECT_LT((*pair.targetLps - mapped(knownTargetFromModel, *pair.modelLps)).norm(), 3.0) << "pair " << i;
  }

  // The reference: the distances of the scan under the known transform (the reconstruction's own error) and the
  // pairs' residuals there (the picking error).
  const TargetSurface ct(registration->GetTarget());
  const DistanceStatistics atKnown =
      distanceStatistics(distancesToSurface(ct, transformedPoints(points, knownTargetFromModel)));
  double residualSquares = 0;
  for (int i = 0; i < 4; ++i) {
    const auto& pair = registration->GetLandmarkPair(i);
    residualSquares += (*pair.targetLps - mapped(knownTargetFromModel, *pair.modelLps)).squaredNorm();
  }
  const double landmarkRmseAtKnown = std::sqrt(residualSquares / 4);

  // Register: the landmark fit lands near the known transform, and the panel shows the logic's numbers.
  click(panel, "registerLandmarksButton");
  ASSERT_TRUE(registration->HasRegistration()) << panel->errorText().toStdString();
  const double landmarkError = largestDisplacementMm(registration->GetTargetFromModel(), knownTargetFromModel, points);
  const QString landmarkRmseShown = panel->shownNumber("landmarkRmse");
  EXPECT_EQ(landmarkRmseShown, QString::number(registration->GetCurrentLandmarkRmseMm(), 'f', 3));
  EXPECT_EQ(panel->shownNumber("rmse"), QString::number(registration->GetDistanceStatistics().rmseMm, 'f', 3));
  // The least-squares fit of the pairs leaves at most their residuals under the truth.
  EXPECT_LE(registration->GetCurrentLandmarkRmseMm(), landmarkRmseAtKnown + 1e-9);
  EXPECT_LT(landmarkError, 2.0);

  // Refine with ICP (on its worker, with progress; the test waits for its end).
  const Eigen::Matrix4d landmarkFit = registration->GetTargetFromModel();
  const double rmseAfterLandmarks = registration->GetDistanceStatistics().rmseMm;
  // At most 30 steps, typed into the field (the default 100 costs a minute on a busy 2-core machine).
  auto* iterations = panel->findChild<QSpinBox*>("icpIterationsSpinBox");
  ASSERT_NE(iterations, nullptr);
  iterations->setFocus();
  iterations->selectAll();
  QTest::keyClicks(iterations, "30");
  QTest::keyClick(iterations, Qt::Key_Tab);
  ASSERT_EQ(iterations->value(), 30);
  QSignalSpy refined(panel, &qTissueMosaicRegistrationWidget::icpFinished);
  QElapsedTimer icpClock;
  icpClock.start();
  click(panel, "refineIcpButton");
  EXPECT_TRUE(panel->isIcpRunning() || refined.count() > 0);
  // Generous: on a busy 2-core machine the ICP thread may get a fifth of a core.
  ASSERT_TRUE(runUntil([&] { return refined.count() > 0; }, 300))
      << panel->lastMessage().toStdString() << " (running: " << panel->isIcpRunning() << ")";
  ASSERT_TRUE(refined.first().at(0).toBool()) << panel->errorText().toStdString();
  const auto& icp = registration->GetIcpResult();
  ASSERT_TRUE(icp.has_value());
  EXPECT_EQ(panel->shownNumber("icpInlierRmse"), QString::number(icp->inlierRmseMm, 'f', 3));
  EXPECT_EQ(panel->shownNumber("rmse"), QString::number(registration->GetDistanceStatistics().rmseMm, 'f', 3));
  EXPECT_EQ(panel->shownNumber("points"), QString::number(modelPoints));
  const double rmseAfterIcp = registration->GetDistanceStatistics().rmseMm;
  const double icpError = largestDisplacementMm(registration->GetTargetFromModel(), knownTargetFromModel, points);
  const QString icpMessage = panel->lastMessage();
  std::printf("[ measured ] ICP took %.1f s (the window stayed live: the test's event loop ran meanwhile)\n",
              icpClock.elapsed() / 1000.0);
  std::printf("[ measured ] %lld model points; at the known transform: distance RMSE %.3f mm, landmark RMSE %.3f mm; "
              "landmarks (4 clicked pairs): landmark RMSE %s mm, distance RMSE %.3f mm, largest displacement from "
              "the known transform %.3f mm; ICP: %d steps, distance RMSE %.3f mm, largest displacement %.3f mm: \"%s\"\n",
              static_cast<long long>(modelPoints), atKnown.rmseMm, landmarkRmseAtKnown, qPrintable(landmarkRmseShown),
              rmseAfterLandmarks, landmarkError, icp->iterations, rmseAfterIcp, icpError, qPrintable(icpMessage));
  if (rmseAfterIcp > rmseAfterLandmarks * 1.05 + 0.01) {
    // ICP made the fit worse (it trims the farthest 20% of the correspondences and can slide along smooth tissue):
    // the panel says so with the figures, and Undo brings the landmark fit back.
    EXPECT_TRUE(icpMessage.contains("ICP made the fit worse")) << icpMessage.toStdString();
    EXPECT_TRUE(icpMessage.contains(QString::number(rmseAfterIcp, 'f', 3))) << icpMessage.toStdString();
    click(panel, "undoRegistrationButton");
    EXPECT_TRUE(registration->GetTargetFromModel() == landmarkFit);
    EXPECT_FALSE(registration->GetIcpResult().has_value());
    EXPECT_EQ(panel->shownNumber("rmse"), QString::number(rmseAfterLandmarks, 'f', 3));
    EXPECT_EQ(panel->shownNumber("icpIterations"), "-");
  } else {
    // A refinement that helps: at least as good a fit as the known transform's, near it, and no warning.
    EXPECT_FALSE(icpMessage.contains("worse")) << icpMessage.toStdString();
    EXPECT_LE(rmseAfterIcp, atKnown.rmseMm + 0.02);
    EXPECT_LT(icpError, 2.0);
  }

  // Export the transform through the save dialog: the file holds the registration (Slicer's direction).
  const QString tfm = dir + "/model-to-ct.tfm";
  answerNextFileDialog(tfm);
  click(panel, "exportTransformButton");
  ASSERT_TRUE(QFileInfo::exists(tfm)) << panel->lastMessage().toStdString();
  EXPECT_TRUE(panel->lastMessage().contains("written")) << panel->lastMessage().toStdString();
  const Eigen::Matrix4d exported = readModelToTargetTransform(tfm.toStdString());
  EXPECT_LT((exported - registration->GetTargetFromModel()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(largestDisplacementMm(exported, knownTargetFromModel, points), 2.0);

  // Mid-task, the window still shows every control whole.
  const QStringList problems = tissuemosaic::test::layoutProblems(&window);
  EXPECT_TRUE(problems.isEmpty()) << problems.join("\n").toStdString();
}
