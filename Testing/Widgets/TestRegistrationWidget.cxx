// The registration panel against ground truth: a synthetic scan of a smooth tissue-like surface (0.1 mm noise,
// 20% of the points 1.5-4 mm off the surface), moved by a known rigid transform; the CT model is the true surface
// meshed at 0.5 mm. Checks that what the panel shows (transform, numbers, table,
// colours, histogram) is the logic's result and that the result is the truth; that export writes files the
// logic's readers read back; and that a click in the 3D view puts the landmark on the clicked vertex.
#include "TestRegistrationScene.h"
#include "qTissueMosaicLandmarkTable.h"
#include "qTissueMosaicRegistrationView.h"
#include "qTissueMosaicRegistrationWidget.h"
#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicItkTransformFile.h"
#include "vtkTissueMosaicLandmarksFile.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicRegistrationLogic.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkMapper.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkScalarsToColors.h>

#include <QDir>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLocale>
#include <QPushButton>
#include <QTableWidget>
#include <QTest>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

using namespace tissuemosaic;
using namespace tissuemosaic::test;

namespace {

/// One folder per test: ctest runs the tests in parallel processes.
QString outputDir() {
  const QString dir = QString(TM_TEST_OUTPUT_DIR) + "/registration-widget/" +
                      ::testing::UnitTest::GetInstance()->current_test_info()->name();
  QDir().mkpath(dir);
  return dir;
}

/// The scene of the logic's registration tests: the model is the scan moved by inverse(truth), so that
/// truth = T_target_model maps it back onto the CT surface.
struct Scene {
  Eigen::Matrix4d truth = rigidTransform({0.2, 1, 0.3}, 10, {0, 0, 5}, {6, -4, 3});
  ScanSample sample = scanSample(3000, 25, 0.1, 11);
  std::vector<Eigen::Vector3d> modelPoints = transformedPoints(sample.pointsMm, truth.inverse());
  QString modelPath = outputDir() + "/model.ply";
  QString targetPath = outputDir() + "/ct.stl";
  /// Landmark positions picked on the CT surface.
  std::vector<Eigen::Vector3d> targetLandmarks;

  Scene() {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> vertices;
    for (const Eigen::Vector3d& point : modelPoints) {
      const vtkIdType id = points->InsertNextPoint(point.data());
      vertices->InsertNextCell(1, &id);
    }
    vtkNew<vtkPolyData> model;
    model->SetPoints(points);
    model->SetVerts(vertices);
    writeSurfaceModel(modelPath.toStdString(), model);
    writeSurfaceModel(targetPath.toStdString(), heightFieldMesh(25, 0.5));
    const double xy[6][2] = {{-15, -15}, {15, -15}, {15, 15}, {-15, 15}, {0, 8}, {-6, -2}};
    for (const auto& p : xy) targetLandmarks.emplace_back(p[0], p[1], height(p[0], p[1]));
  }
  Eigen::Vector3d modelOf(const Eigen::Vector3d& target) const {
    const Eigen::Matrix4d inverse = truth.inverse();
    return inverse.topLeftCorner<3, 3>() * target + inverse.topRightCorner<3, 1>();
  }
  /// RMS of the true distances: what the panel must report once the model sits where it belongs.
  double trueRmseMm() const {
    double sum = 0;
    for (double d : sample.trueDistanceMm) sum += d * d;
    return std::sqrt(sum / static_cast<double>(sample.trueDistanceMm.size()));
  }
};

/// Largest displacement between two transforms over the model points.
double maxDisplacementMm(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, const std::vector<Eigen::Vector3d>& points) {
  double largest = 0;
  const auto pa = transformedPoints(points, a), pb = transformedPoints(points, b);
  for (std::size_t i = 0; i < points.size(); ++i) largest = std::max(largest, (pa[i] - pb[i]).norm());
  return largest;
}

Eigen::Matrix4d parseShownTransform(const QString& text) {
  const QStringList words = text.split(QRegularExpression("\\s+"), Qt::SkipEmptyParts);
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Constant(std::nan(""));
  if (words.size() != 16) return matrix;
  for (int i = 0; i < 16; ++i) matrix(i / 4, i % 4) = words[i].toDouble();
  return matrix;
}

/// The panel and its scene view (which the application puts in its view area) on screen.
void showPanelAndView(qTissueMosaicRegistrationWidget& panel) {
  panel.resize(500, 900);
  panel.show();
  panel.sceneView()->resize(900, 700);
  panel.sceneView()->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&panel));
  ASSERT_TRUE(QTest::qWaitForWindowExposed(panel.sceneView()));
}

void loadScene(qTissueMosaicRegistrationWidget& panel, const Scene& scene) {
  ASSERT_TRUE(panel.loadModelFile(scene.modelPath)) << panel.errorText().toStdString();
  ASSERT_TRUE(panel.loadTargetFile(scene.targetPath)) << panel.errorText().toStdString();
}

}  // namespace

TEST(RegistrationWidget, ExactLandmarksGiveTheTruthAndThePanelShowsTheLogicsNumbers) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  loadScene(panel, scene);
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();
  EXPECT_EQ(logic->GetModel()->GetNumberOfPoints(), 3000);
  std::vector<Eigen::Vector3d> modelLandmarks;
  for (const Eigen::Vector3d& target : scene.targetLandmarks) {
    modelLandmarks.push_back(scene.modelOf(target));
    EXPECT_GE(panel.addLandmarkPair(modelLandmarks.back(), target), 0);
  }
  ASSERT_EQ(panel.landmarkTable()->rowCount(), 6);
  EXPECT_EQ(panel.shownNumber("rmse"), "-");  // nothing registered yet

  ASSERT_TRUE(panel.registerLandmarks()) << panel.errorText().toStdString();
  const Eigen::Matrix4d direct = registerLandmarks(modelLandmarks, scene.targetLandmarks, false).targetFromModel;
  EXPECT_LT((logic->GetTargetFromModel() - direct).norm(), 1e-12);
  EXPECT_LT((logic->GetTargetFromModel() - scene.truth).norm(), 1e-9);
  const Eigen::Matrix4d shown = parseShownTransform(panel.shownTransform());
  EXPECT_LT((shown - logic->GetTargetFromModel()).cwiseAbs().maxCoeff(), 0.6e-5) << panel.shownTransform().toStdString();

  const DistanceStatistics& statistics = logic->GetDistanceStatistics();
  EXPECT_EQ(panel.shownNumber("rmse"), QString::number(statistics.rmseMm, 'f', 3));
  EXPECT_EQ(panel.shownNumber("mean"), QString::number(statistics.meanMm, 'f', 3));
  EXPECT_EQ(panel.shownNumber("p95"), QString::number(statistics.p95Mm, 'f', 3));
  EXPECT_EQ(panel.shownNumber("points"), "3000");
  EXPECT_EQ(panel.shownNumber("landmarkRmse"), "0.000");
  EXPECT_EQ(panel.shownNumber("icpIterations"), "-");
  // The truth: every sample's distance is its offset along the normal (0.5 mm mesh: < 0.005 mm chord error).
  std::printf("exact landmarks: RMSE shown %s mm, true %.4f mm\n", qPrintable(panel.shownNumber("rmse")),
              scene.trueRmseMm());
  EXPECT_NEAR(statistics.rmseMm, scene.trueRmseMm(), 0.01);
  for (int row = 0; row < 6; ++row) {
    EXPECT_EQ(panel.landmarkTable()->item(row, qTissueMosaicLandmarkTable::ResidualColumn)->text(), "0.00");
  }
}

TEST(RegistrationWidget, IcpRefinesNoisyLandmarksToTheTruth) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  loadScene(panel, scene);
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();
  // Picking errors of about 1 mm on the CT side.
  const double error[6][3] = {{0.8, -0.5, 0.3}, {-0.7, 0.6, -0.4}, {0.5, 0.9, 0.2},
                              {-0.9, -0.3, 0.5}, {0.4, -0.8, -0.6}, {-0.3, 0.7, 0.8}};
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d target = scene.targetLandmarks[i] + Eigen::Vector3d(error[i][0], error[i][1], error[i][2]);
    panel.addLandmarkPair(scene.modelOf(scene.targetLandmarks[i]), target);
  }
  ASSERT_TRUE(panel.registerLandmarks());
  const double landmarkRotation = rotationAngleDeg(logic->GetTargetFromModel() * scene.truth.inverse());
  const double landmarkDisplacement = maxDisplacementMm(logic->GetTargetFromModel(), scene.truth, scene.modelPoints);
  EXPECT_GT(landmarkDisplacement, 0.3);  // ICP has something to correct

  panel.setIcpMaxIterations(60);
  ASSERT_TRUE(panel.refineIcp()) << panel.errorText().toStdString();
  ASSERT_TRUE(logic->GetIcpResult().has_value());
  const IcpResult& icp = *logic->GetIcpResult();
  const double icpRotation = rotationAngleDeg(logic->GetTargetFromModel() * scene.truth.inverse());
  const double icpDisplacement = maxDisplacementMm(logic->GetTargetFromModel(), scene.truth, scene.modelPoints);
  std::printf("landmarks (1 mm picking error): %.3f deg, max displacement %.3f mm; ICP: %d iterations, %.4f deg, "
              "%.4f mm; RMSE shown %s mm (true %.4f)\n",
              landmarkRotation, landmarkDisplacement, icp.iterations, icpRotation, icpDisplacement,
              qPrintable(panel.shownNumber("rmse")), scene.trueRmseMm());
  EXPECT_TRUE(icp.converged);
  EXPECT_LT(icpRotation, 0.1);
  EXPECT_LT(icpDisplacement, 0.15);
  EXPECT_EQ(panel.shownNumber("icpIterations"), QString("%1 (converged)").arg(icp.iterations));
  EXPECT_EQ(panel.shownNumber("icpInlierRmse"), QString::number(icp.inlierRmseMm, 'f', 3));
  EXPECT_EQ(panel.shownNumber("rmse"), QString::number(logic->GetDistanceStatistics().rmseMm, 'f', 3));
  EXPECT_NEAR(logic->GetDistanceStatistics().rmseMm, scene.trueRmseMm(), 0.01);
  const Eigen::Matrix4d shown = parseShownTransform(panel.shownTransform());
  EXPECT_LT((shown - logic->GetTargetFromModel()).cwiseAbs().maxCoeff(), 0.6e-5);
}

TEST(RegistrationWidget, DeleteAndEditUpdateTheTableAndTheLogic) {
  qTissueMosaicRegistrationWidget panel;
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();
  QTableWidget* table = panel.landmarkTable();
  for (int i = 0; i < 4; ++i) panel.addLandmarkPair(Eigen::Vector3d(i, 0, 0), Eigen::Vector3d(0, i, 0));
  ASSERT_EQ(table->rowCount(), 4);
  ASSERT_TRUE(panel.removeLandmarkPair(1));
  ASSERT_EQ(table->rowCount(), 3);
  EXPECT_EQ(logic->GetNumberOfLandmarkPairs(), 3);
  EXPECT_EQ(table->item(0, 0)->text(), "L1");
  EXPECT_EQ(table->item(1, 0)->text(), "L3");
  EXPECT_EQ(table->item(1, qTissueMosaicLandmarkTable::ModelColumn)->text(), "2.00, 0.00, 0.00");

  // The Delete button removes the selected rows.
  table->selectRow(0);
  QPushButton* deleteButton = nullptr;
  for (QPushButton* button : panel.findChildren<QPushButton*>()) {
    if (button->text() == "Delete") deleteButton = button;
  }
  ASSERT_NE(deleteButton, nullptr);
  deleteButton->click();
  ASSERT_EQ(table->rowCount(), 2);
  EXPECT_EQ(table->item(0, 0)->text(), "L3");
  EXPECT_EQ(logic->GetLandmarkPair(0).label, "L3");

  // Editing a position or a label changes the logic; a bad value is refused and the old one shown again.
  table->item(0, qTissueMosaicLandmarkTable::TargetColumn)->setText("1.5, -2, 30");
  QCoreApplication::processEvents();
  EXPECT_TRUE(logic->GetLandmarkPair(0).targetLps->isApprox(Eigen::Vector3d(1.5, -2, 30)));
  EXPECT_EQ(table->item(0, qTissueMosaicLandmarkTable::TargetColumn)->text(), "1.50, -2.00, 30.00");
  table->item(0, qTissueMosaicLandmarkTable::ModelColumn)->setText("1, two, 3");
  QCoreApplication::processEvents();
  EXPECT_FALSE(panel.errorText().isEmpty());
  EXPECT_TRUE(logic->GetLandmarkPair(0).modelLps->isApprox(Eigen::Vector3d(2, 0, 0)));
  EXPECT_EQ(table->item(0, qTissueMosaicLandmarkTable::ModelColumn)->text(), "2.00, 0.00, 0.00");
  table->item(1, qTissueMosaicLandmarkTable::LabelColumn)->setText("L3");  // taken by row 0
  QCoreApplication::processEvents();
  EXPECT_EQ(logic->GetLandmarkPair(1).label, "L4");
  EXPECT_NE(panel.errorText().indexOf("already used"), -1) << panel.errorText().toStdString();
  table->item(1, qTissueMosaicLandmarkTable::LabelColumn)->setText("tip");
  QCoreApplication::processEvents();
  EXPECT_EQ(logic->GetLandmarkPair(1).label, "tip");
  EXPECT_TRUE(panel.errorText().isEmpty());

  // Too few pairs: the logic's message is shown, nothing changes.
  EXPECT_FALSE(panel.registerLandmarks());
  EXPECT_NE(panel.errorText().indexOf("at least 3"), -1) << panel.errorText().toStdString();
  EXPECT_TRUE(logic->GetTargetFromModel().isIdentity());
}

TEST(RegistrationWidget, ModelColouredByDistanceWithScalarBarAndHistogram) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  showPanelAndView(panel);
  loadScene(panel, scene);
  for (const Eigen::Vector3d& target : scene.targetLandmarks) panel.addLandmarkPair(scene.modelOf(target), target);
  ASSERT_TRUE(panel.registerLandmarks());
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();
  const DistanceStatistics& statistics = logic->GetDistanceStatistics();

  ASSERT_TRUE(panel.colourByDistance());
  vtkActor* actor = panel.sceneView()->distanceActor();
  EXPECT_TRUE(actor->GetVisibility());
  EXPECT_TRUE(panel.sceneView()->scalarBar()->GetVisibility());
  // What the mapper draws: every registered point as a vertex, with the logic's distances.
  vtkMapper* mapper = actor->GetMapper();
  mapper->Update();
  auto* shownModel = vtkPolyData::SafeDownCast(mapper->GetInput());
  ASSERT_NE(shownModel, nullptr);
  EXPECT_EQ(shownModel->GetNumberOfVerts() + shownModel->GetNumberOfPolys(), 3000);
  EXPECT_STREQ(mapper->GetArrayName(), kDistanceArrayName);
  vtkDataArray* distances = shownModel->GetPointData()->GetArray(kDistanceArrayName);
  ASSERT_NE(distances, nullptr);
  ASSERT_EQ(distances->GetNumberOfTuples(), 3000);
  for (vtkIdType i = 0; i < 3000; i += 97) {
    double shown[3], registered[3];
    shownModel->GetPoint(i, shown);
    logic->GetRegisteredModel()->GetPoint(i, registered);
    EXPECT_EQ(Eigen::Vector3d(shown[0], shown[1], shown[2]), Eigen::Vector3d(registered[0], registered[1], registered[2]));
    EXPECT_FLOAT_EQ(distances->GetTuple1(i), logic->GetDistancesMm()[i]);
  }
  double largestDifference = 0;
  for (vtkIdType i = 0; i < 3000; ++i) {
    largestDifference = std::max(largestDifference, std::abs(distances->GetTuple1(i) - scene.sample.trueDistanceMm[i]));
  }
  EXPECT_LT(largestDifference, 0.01);  // the map shows each point's true distance
  const double* range = panel.sceneView()->scalarBar()->GetLookupTable()->GetRange();
  EXPECT_EQ(range[0], 0.0);
  EXPECT_DOUBLE_EQ(range[1], statistics.p95Mm);
  EXPECT_EQ(actor->GetMapper()->GetLookupTable(), panel.sceneView()->scalarBar()->GetLookupTable());

  const QVector<double> percent = panel.histogramPercent();
  const DistanceHistogram& histogram = logic->GetDistanceHistogram();
  ASSERT_EQ(percent.size(), static_cast<int>(histogram.counts.size()));
  double total = 100.0 * histogram.overflow / 3000.0;
  for (int i = 0; i < percent.size(); ++i) {
    EXPECT_DOUBLE_EQ(percent[i], 100.0 * histogram.counts[i] / 3000.0);
    total += percent[i];
  }
  EXPECT_NEAR(total, 100.0, 1e-9);
  EXPECT_DOUBLE_EQ(panel.histogramBinWidthMm(), 0.1);

  panel.sceneView()->vtkWidget()->renderWindow()->Render();
  panel.setColourByDistance(false);
  EXPECT_FALSE(actor->GetVisibility());
  EXPECT_FALSE(panel.sceneView()->scalarBar()->GetVisibility());
  panel.sceneView()->vtkWidget()->renderWindow()->Render();
}

TEST(RegistrationWidget, ExportWritesFilesThatReadBack) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  loadScene(panel, scene);
  for (const Eigen::Vector3d& target : scene.targetLandmarks) panel.addLandmarkPair(scene.modelOf(target), target);
  const QString dir = outputDir();
  EXPECT_FALSE(panel.exportRegisteredModel(dir + "/early.vtp"));  // nothing registered yet
  EXPECT_FALSE(panel.errorText().isEmpty());
  ASSERT_TRUE(panel.registerLandmarks());
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();

  ASSERT_TRUE(panel.exportTransform(dir + "/t.tfm")) << panel.errorText().toStdString();
  EXPECT_LT((readModelToTargetTransform((dir + "/t.tfm").toStdString()) - logic->GetTargetFromModel()).norm(), 1e-12);

  ASSERT_TRUE(panel.exportRegisteredModel(dir + "/registered.vtp"));
  const SurfaceModelFile registered = readSurfaceModel((dir + "/registered.vtp").toStdString());
  ASSERT_EQ(registered.polyDataLps->GetNumberOfPoints(), 3000);
  vtkDataArray* distances = registered.polyDataLps->GetPointData()->GetArray(kDistanceArrayName);
  ASSERT_NE(distances, nullptr);
  double largest = 0;
  for (vtkIdType i = 0; i < 3000; ++i) {
    double p[3];
    registered.polyDataLps->GetPoint(i, p);
    largest = std::max(largest, (Eigen::Vector3d(p[0], p[1], p[2]) - scene.sample.pointsMm[i]).norm());
    EXPECT_NEAR(distances->GetTuple1(i), logic->GetDistancesMm()[i], 1e-5);
  }
  EXPECT_LT(largest, 1e-4);  // registered positions are the scan's true ones (float file precision)

  ASSERT_TRUE(panel.exportLandmarks(dir + "/pairs.mrk.json"));
  const LandmarkPairs pairs = readLandmarkPairs((dir + "/pairs.mrk.json").toStdString());
  ASSERT_EQ(pairs.targetLps.size(), 6u);
  EXPECT_TRUE(pairs.pairedByLabel);
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT((pairs.targetLps[i] - scene.targetLandmarks[i]).norm(), 1e-9);
    EXPECT_LT((pairs.modelLps[i] - *logic->GetLandmarkPair(i).modelLps).norm(), 1e-9);
  }
  // Loading them back into a new panel gives the same registration.
  qTissueMosaicRegistrationWidget second;
  loadScene(second, scene);
  ASSERT_TRUE(second.loadLandmarksFile(dir + "/pairs.mrk.json"));
  EXPECT_EQ(second.landmarkTable()->rowCount(), 6);
  ASSERT_TRUE(second.registerLandmarks());
  EXPECT_LT((second.registrationLogic()->GetTargetFromModel() - logic->GetTargetFromModel()).norm(), 1e-9);

  QFile::remove(dir + "/d.png");
  ASSERT_TRUE(panel.exportDistanceReport(dir + "/d.csv", dir + "/d.png"));
  std::ifstream csv((dir + "/d.csv").toStdString());
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "index,x_mm,y_mm,z_mm,distance_mm,signed_distance_mm");
  int rows = 0;
  while (std::getline(csv, line)) rows += !line.empty();
  EXPECT_EQ(rows, 3000);
  const cv::Mat png = cv::imread((dir + "/d.png").toStdString());
  EXPECT_FALSE(png.empty());
}

TEST(RegistrationWidget, ClickPicksTheVertexUnderTheCursor) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  showPanelAndView(panel);
  loadScene(panel, scene);
  vtkRenderer* renderer = panel.sceneView()->renderer();
  renderer->GetActiveCamera()->Elevation(20);  // an oblique view, so depth matters
  renderer->ResetCamera();
  panel.sceneView()->vtkWidget()->renderWindow()->Render();
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();

  // Where a world point shows in the view, as Qt widget pixels (origin top left).
  const auto widgetPosition = [&](const Eigen::Vector3d& world) {
    renderer->SetWorldPoint(world.x(), world.y(), world.z(), 1.0);
    renderer->WorldToDisplay();
    const double* display = renderer->GetDisplayPoint();
    const double ratio = panel.sceneView()->vtkWidget()->devicePixelRatioF();
    return QPoint(static_cast<int>(std::lround(display[0] / ratio)),
                  panel.sceneView()->vtkWidget()->height() - 1 - static_cast<int>(std::lround(display[1] / ratio)));
  };
  QWidget* surface = panel.sceneView()->vtkWidget();

  // On the CT surface: a mesh vertex near the centre (x = 2, y = -3 lies on the 0.5 mm grid).
  const Eigen::Vector3d vertex(2, -3, height(2, -3));
  panel.setPickMode(qTissueMosaicRegistrationView::PickOnTarget);
  QTest::mouseClick(surface, Qt::LeftButton, Qt::NoModifier, widgetPosition(vertex));
  ASSERT_EQ(logic->GetNumberOfLandmarkPairs(), 1) << panel.errorText().toStdString();
  ASSERT_TRUE(logic->GetLandmarkPair(0).targetLps.has_value());
  const double targetError = (*logic->GetLandmarkPair(0).targetLps - vertex).norm();
  EXPECT_LT(targetError, 0.3);
  EXPECT_EQ(panel.landmarkTable()->rowCount(), 1);

  // On the model (a point cloud, drawn where the current transform, the identity, puts it): a scan point in the
  // middle of the surface, on the side facing the camera.
  int chosen = -1;
  for (int i = 0; i < 3000 && chosen < 0; ++i) {
    const Eigen::Vector3d& p = scene.modelPoints[i];
    if (std::hypot(p.x(), p.y()) < 6 && scene.sample.trueDistanceMm[i] < 0.05) chosen = i;
  }
  ASSERT_GE(chosen, 0);
  panel.setPickMode(qTissueMosaicRegistrationView::PickOnModel);
  // A drag rotates the camera and picks nothing.
  vtkNew<vtkCamera> saved;
  saved->DeepCopy(renderer->GetActiveCamera());
  const QPoint at = widgetPosition(scene.modelPoints[chosen]);
  QTest::mousePress(surface, Qt::LeftButton, Qt::NoModifier, at);
  QTest::mouseMove(surface, at + QPoint(40, 0));
  QTest::mouseRelease(surface, Qt::LeftButton, Qt::NoModifier, at + QPoint(40, 0));
  EXPECT_FALSE(logic->GetLandmarkPair(0).modelLps.has_value());
  renderer->GetActiveCamera()->DeepCopy(saved);
  panel.sceneView()->vtkWidget()->renderWindow()->Render();
  QTest::mouseClick(surface, Qt::LeftButton, Qt::NoModifier, widgetPosition(scene.modelPoints[chosen]));
  ASSERT_TRUE(logic->GetLandmarkPair(0).modelLps.has_value()) << panel.errorText().toStdString();
  const double modelError = (*logic->GetLandmarkPair(0).modelLps - scene.modelPoints[chosen]).norm();
  std::printf("picking: CT point %.3f mm from the clicked vertex, model point %.4f mm from the clicked scan point\n",
              targetError, modelError);
  EXPECT_LT(modelError, 1e-4);  // the picked point is the scan point itself (float file precision)
  EXPECT_EQ(panel.landmarkTable()->rowCount(), 1);  // it completed the pair
  EXPECT_FALSE(panel.landmarkTable()->item(0, qTissueMosaicLandmarkTable::ResidualColumn)->text().isEmpty());
}

TEST(RegistrationWidget, LoadErrorsAreShown) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  EXPECT_FALSE(panel.loadTargetFile(scene.modelPath));  // a point cloud is no surface
  EXPECT_NE(panel.errorText().indexOf("no polygons"), -1) << panel.errorText().toStdString();
  EXPECT_FALSE(panel.loadModelFile(outputDir() + "/missing.ply"));
  EXPECT_NE(panel.errorText().indexOf("does not exist"), -1) << panel.errorText().toStdString();
  EXPECT_FALSE(panel.refineIcp());
  EXPECT_FALSE(panel.errorText().isEmpty());
  ASSERT_TRUE(panel.loadModelFile(scene.modelPath));
  EXPECT_TRUE(panel.errorText().isEmpty());
}

TEST(RegistrationWidget, FrameChoiceAppliesToTheNextLoad) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  ASSERT_TRUE(panel.loadTargetFile(scene.targetPath));  // our files carry SPACE=LPS
  double lps[3], ras[3];
  panel.registrationLogic()->GetTarget()->GetPoint(123, lps);
  panel.setTargetFrameChoice(static_cast<int>(ModelFrameChoice::RAS));  // the user says: RAS, whatever the file says
  ASSERT_TRUE(panel.loadTargetFile(scene.targetPath));
  panel.registrationLogic()->GetTarget()->GetPoint(123, ras);
  EXPECT_EQ(ras[0], -lps[0]);
  EXPECT_EQ(ras[1], -lps[1]);
  EXPECT_EQ(ras[2], lps[2]);
}

TEST(RegistrationWidget, LiveModelIsFollowedAsItGrows) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (int i = 0; i < 1000; ++i) points->InsertNextPoint(scene.modelPoints[i].data());
  vtkNew<vtkPolyData> live;  // as the reconstruction's growing model: points only, updated in place
  live->SetPoints(points);
  panel.setReconstructedModel(live);
  ASSERT_TRUE(panel.loadTargetFile(scene.targetPath));
  for (const Eigen::Vector3d& target : scene.targetLandmarks) panel.addLandmarkPair(scene.modelOf(target), target);
  ASSERT_TRUE(panel.registerLandmarks());
  EXPECT_EQ(panel.shownNumber("points"), "1000");

  EXPECT_TRUE(panel.usesCurrentScan());
  EXPECT_EQ(panel.shownModelText(), QString("Use the current scan (%1 points)").arg(QLocale().toString(1000)));
  EXPECT_TRUE(panel.resultsNotice().isEmpty());

  for (int i = 1000; i < 3000; ++i) points->InsertNextPoint(scene.modelPoints[i].data());
  points->Modified();
  live->Modified();
  panel.setReconstructedModel(live);  // the same model again: keeps the registration
  panel.liveModelChanged();           // as the application calls it when the scan grew
  EXPECT_LT((panel.registrationLogic()->GetTargetFromModel() - scene.truth).norm(), 1e-9);
  EXPECT_EQ(panel.shownModelText(), QString("Use the current scan (%1 points)").arg(QLocale().toString(3000)));
  // The numbers were made with 1000 points: the panel says they are out of date.
  EXPECT_TRUE(panel.resultsNotice().contains("Out of date")) << panel.resultsNotice().toStdString();
  ASSERT_TRUE(panel.updateDistances());
  EXPECT_TRUE(panel.resultsNotice().isEmpty());
  EXPECT_EQ(panel.shownNumber("points"), "3000");
  EXPECT_NEAR(panel.registrationLogic()->GetDistanceStatistics().rmseMm, scene.trueRmseMm(), 0.01);
}

TEST(RegistrationWidget, AResetScanDropsItsResultsAndItsModelLandmarks) {
  // After Reset and a new scan, nothing of the old model may remain: count, transform, numbers, colours, model
  // landmarks; and no transform of a model that no longer exists can be exported.
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const Eigen::Vector3d& point : scene.modelPoints) points->InsertNextPoint(point.data());
  vtkNew<vtkPolyData> live;
  live->SetPoints(points);
  panel.setReconstructedModel(live);
  panel.liveModelChanged();
  ASSERT_TRUE(panel.loadTargetFile(scene.targetPath));
  for (const Eigen::Vector3d& target : scene.targetLandmarks) panel.addLandmarkPair(scene.modelOf(target), target);
  ASSERT_TRUE(panel.registerLandmarks());
  ASSERT_NE(panel.shownNumber("rmse"), "-");

  points->SetNumberOfPoints(0);  // the reconstruction's Reset empties its model in place
  live->Modified();
  panel.liveModelChanged();
  vtkTissueMosaicRegistrationLogic* logic = panel.registrationLogic();
  EXPECT_EQ(panel.shownModelText(), "Use the current scan (no points yet)");
  EXPECT_EQ(panel.shownNumber("rmse"), "-");
  EXPECT_EQ(panel.shownNumber("landmarkRmse"), "-");
  EXPECT_TRUE(logic->GetTargetFromModel().isIdentity());
  EXPECT_FALSE(panel.sceneView()->distanceActor()->GetVisibility()) << "no colour map of a model that is gone";
  EXPECT_TRUE(panel.resultsNotice().contains("reset")) << panel.resultsNotice().toStdString();
  ASSERT_EQ(logic->GetNumberOfLandmarkPairs(), 6);  // the CT/MR points stay, for picking the model ones again
  EXPECT_EQ(logic->GetNumberOfCompleteLandmarkPairs(), 0);
  EXPECT_EQ(panel.landmarkTable()->item(0, qTissueMosaicLandmarkTable::ModelColumn)->text(), "");
  EXPECT_FALSE(panel.exportTransform(outputDir() + "/stale.tfm"));
  EXPECT_TRUE(panel.errorText().contains("Nothing registered")) << panel.errorText().toStdString();
  EXPECT_FALSE(QFile::exists(outputDir() + "/stale.tfm"));
}

TEST(RegistrationWidget, HistogramSaysHowManyPointsLieBeyondIt) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  loadScene(panel, scene);
  for (const Eigen::Vector3d& target : scene.targetLandmarks) panel.addLandmarkPair(scene.modelOf(target), target);
  ASSERT_TRUE(panel.registerLandmarks());
  EXPECT_TRUE(panel.histogramOverflowNote().isEmpty()) << "0.1 mm bins cover every distance of this scene";
  auto* bin = panel.findChild<QDoubleSpinBox*>("binWidthSpinBox");
  ASSERT_NE(bin, nullptr);
  bin->setValue(0.01);  // 100 bins up to 1 mm: the off-surface points (1.5-4 mm) lie beyond
  const DistanceHistogram& histogram = panel.registrationLogic()->GetDistanceHistogram();
  ASSERT_GT(histogram.overflow, 0u);
  const double percent = 100.0 * static_cast<double>(histogram.overflow) / 3000.0;
  EXPECT_EQ(panel.histogramOverflowNote(),
            QString("%1% of the points lie beyond %2 mm").arg(percent, 0, 'f', 1).arg(0.01 * histogram.counts.size(), 0, 'g', 3));
}

TEST(RegistrationWidget, AMissedPickAnExportAndAWrongFolderAreReportedInPlainWords) {
  const Scene scene;
  qTissueMosaicRegistrationWidget panel;
  showPanelAndView(panel);
  loadScene(panel, scene);
  // A click on the CT/MR model that hits nothing adds nothing, and says so (a later pick would pair wrongly).
  panel.setPickMode(qTissueMosaicRegistrationView::PickOnTarget);
  EXPECT_FALSE(panel.sceneView()->pickAt(2, 2));  // the corner of the view: background
  EXPECT_EQ(panel.registrationLogic()->GetNumberOfLandmarkPairs(), 0);
  EXPECT_TRUE(panel.errorText().contains("No CT/MR surface under the cursor")) << panel.errorText().toStdString();
  // Nothing registered yet: no identity transform written.
  EXPECT_FALSE(panel.exportTransform(outputDir() + "/identity.tfm"));
  EXPECT_FALSE(QFile::exists(outputDir() + "/identity.tfm"));
  for (const Eigen::Vector3d& target : scene.targetLandmarks) panel.addLandmarkPair(scene.modelOf(target), target);
  ASSERT_TRUE(panel.registerLandmarks());
  // Each export confirms where it wrote.
  ASSERT_TRUE(panel.exportTransform(outputDir() + "/t.tfm"));
  EXPECT_EQ(panel.lastMessage(), "Transform written to " + outputDir() + "/t.tfm");
  // A missing folder: plain words, never a library's object dump.
  EXPECT_FALSE(panel.exportRegisteredModel("/nonexistent-folder/registered.vtp"));
  const QString message = panel.errorText();
  EXPECT_TRUE(message.contains("the folder does not exist")) << message.toStdString();
  for (const char* internal : {"Debug:", "Modified Time", "Reference Count", "vtkXML", "0x"}) {
    EXPECT_FALSE(message.contains(internal)) << internal << " in: " << message.toStdString();
  }
}
