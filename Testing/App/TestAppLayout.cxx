// The window as a user sees it at the smallest supported screen (1280x800) and at full HD: every visible widget of
// both module tabs is checked for text cut off, overlapping siblings, content cut or scrolled sideways and tables
// that do not show whole (LayoutInspection.h). Widget tests that only call methods passed while the registration
// tab was unusable; this one looks at the layout itself.
#include "LayoutInspection.h"
#include "qTissueMosaicMainWindow.h"
#include "qTissueMosaicReconstructionWidget.h"
#include "qTissueMosaicRegistrationWidget.h"

#include "TestRegistrationScene.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <QApplication>
#include <QDir>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QScrollArea>
#include <QStackedWidget>
#include <QTabWidget>
#include <QTest>

using namespace tissuemosaic::test;

namespace {

/// The registration panel mid-task: both models, six landmark pairs, a landmark registration (numbers, transform,
/// histogram), a long message.
void fillRegistration(qTissueMosaicRegistrationWidget* panel, const QString& dir) {
  const ScanSample sample = scanSample(2000, 25, 0.1, 7);
  const Eigen::Matrix4d truth = rigidTransform({0.2, 1, 0.3}, 10, {0, 0, 5}, {6, -4, 3});
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> vertices;
  for (const Eigen::Vector3d& point : sample.pointsMm) {
    const Eigen::Vector3d moved = truth.inverse().topLeftCorner<3, 3>() * point + truth.inverse().topRightCorner<3, 1>();
    const vtkIdType id = points->InsertNextPoint(moved.data());
    vertices->InsertNextCell(1, &id);
  }
  vtkNew<vtkPolyData> model;
  model->SetPoints(points);
  model->SetVerts(vertices);
  tissuemosaic::writeSurfaceModel((dir + "/model.ply").toStdString(), model);
  tissuemosaic::writeSurfaceModel((dir + "/ct.stl").toStdString(), heightFieldMesh(25, 1.0));
  ASSERT_TRUE(panel->loadModelFile(dir + "/model.ply")) << panel->errorText().toStdString();
  ASSERT_TRUE(panel->loadTargetFile(dir + "/ct.stl")) << panel->errorText().toStdString();
  const double xy[6][2] = {{-15, -15}, {15, -15}, {15, 15}, {-15, 15}, {0, 8}, {-6, -2}};
  for (const auto& p : xy) {
    const Eigen::Vector3d target(p[0], p[1], height(p[0], p[1]));
    const Eigen::Vector3d modelPoint = truth.inverse().topLeftCorner<3, 3>() * target + truth.inverse().topRightCorner<3, 1>();
    ASSERT_GE(panel->addLandmarkPair(modelPoint + Eigen::Vector3d(-123.456, 0.5, 0), target), 0);  // wide numbers
  }
  ASSERT_TRUE(panel->registerLandmarks()) << panel->errorText().toStdString();
  panel->exportTransform("/nonexistent-folder/with-a-long-name/t.tfm");  // a long error message, shown in place
}

void expectWholeLayout(qTissueMosaicMainWindow& window, const QSize& size) {
  window.resize(size);
  QApplication::processEvents();
  ASSERT_EQ(window.size(), size) << "the window cannot shrink to the screen";
  for (int tab = 0; tab < window.moduleTabs()->count(); ++tab) {
    window.moduleTabs()->setCurrentIndex(tab);
    for (int i = 0; i < 5; ++i) QApplication::processEvents();  // layouts settle over a few passes
    const QStringList problems = layoutProblems(&window);
    EXPECT_TRUE(problems.isEmpty()) << size.width() << "x" << size.height() << ", tab \""
                                    << window.moduleTabs()->tabText(tab).toStdString() << "\":\n"
                                    << problems.join("\n").toStdString();
    // The module's view fills the view area: the registration scene while Registration is active, the
    // reconstruction's model and video otherwise (the OpenIGTLink tab streams that scan).
    const bool registration = window.moduleTabs()->tabText(tab) == "Registration";
    EXPECT_EQ(window.viewArea()->currentIndex(), registration ? 1 : 0);
  }
}

}  // namespace

TEST(ApplicationLayout, EveryControlWholeFrom1280x800To1920x1080) {
  const QString dir = QString(TM_TEST_OUTPUT_DIR) + "/layout";
  QDir().mkpath(dir);
  qTissueMosaicMainWindow window;
  window.setConfirmUnsavedModel(false);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  // Long texts where they appear in use.
  window.reconstructionPanel()->showMessage(
      "The screenshot was not saved: the folder /a/rather/long/path/that/does/not/exist does not exist.", true);
  fillRegistration(window.registrationPanel(), dir);
  for (const QSize& size : {QSize(1280, 800), QSize(1600, 1000), QSize(1920, 1080)}) expectWholeLayout(window, size);
}

TEST(ApplicationLayout, TheInspectionFindsCutTextAndOverlaps) {
  // The checks themselves must fail on a broken layout: a label squeezed below its text, overlapping siblings.
  QWidget parent;
  parent.resize(300, 100);
  auto* layout = new QHBoxLayout(&parent);
  auto* label = new QLabel("a label whose text is much wider than the space it gets");
  label->setMaximumWidth(60);
  layout->addWidget(label);
  auto* button = new QPushButton("Refine with ICP");
  layout->addWidget(button);
  parent.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&parent));
  button->setFixedWidth(40);
  QApplication::processEvents();
  QStringList problems = layoutProblems(&parent);
  EXPECT_EQ(problems.filter("QLabel").size(), 1) << problems.join("\n").toStdString();
  EXPECT_EQ(problems.filter("QPushButton").size(), 1) << problems.join("\n").toStdString();
  layout->setEnabled(false);  // the layout no longer places them: move one over the other
  button->setGeometry(label->geometry().translated(10, 0));
  problems = layoutProblems(&parent);
  EXPECT_FALSE(problems.filter("overlap").isEmpty()) << problems.join("\n").toStdString();
}
