// The reconstruction panels without OpenGL (Qt's offscreen platform): parameters round trip between the panel
// and the object (the panel's own, or a logic's), invalid values refused with the reason, presets and files,
// parameters fixed during a scan; the video panel's image conversion; the module panel's controls.
#include "qTissueMosaicReconstructionParametersWidget.h"
#include "qTissueMosaicReconstructionWidget.h"
#include "qTissueMosaicStereoParametersWidget.h"
#include "qTissueMosaicVideoPanel.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "Core/Device.h"
#include "Fusion/FusionParameterTable.h"
#include "Tracking/TrackingParameterTable.h"
#include "Core/StereoRig.h"
#include "IO/StereoFrameSource.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>

#include <vtkNew.h>

#include <QComboBox>
#include <QWheelEvent>
#include <QTest>
#include <QRegularExpression>
#include <QLabel>
#include <QApplication>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QPushButton>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QTableWidget>

#include <filesystem>
#include <fstream>
#include <limits>

using tissuemosaic::ReconstructionParameters;

namespace {

/// Values that differ from every default and are exact in the spin boxes' decimals.
ReconstructionParameters unusualParameters() {
  ReconstructionParameters p;
  p.stereo.minDisparityPx = -5;
  p.stereo.maxDisparityPx = 45;
  p.stereo.znccWindowPx = 9;
  p.stereo.refineAlpha = 0.25f;
  p.tracking.inlierThresholdPx = 3.5;
  p.tracking.candidateEta = 2.5;
  p.tracking.candidateRampIterations = 7;
  p.tracking.keyFramePoseThreshold = 4.5;
  p.tracking.keyFrameMinGapFrames = 6;
  p.tracking.keyFrameMinInliers = 40;
  p.refinement.icpWeightFactor = 0.2;
  p.refinement.icpTukeyMm = 3.0;
  p.refinement.maxMatchedKeyFrames = 3;
  p.fusion.truncationMm = 2.25;
  p.fusion.colourMinWeight = 0.2;
  p.fusion.newPointStepPx = 2;
  p.fusion.maxPoints = 5000000;
  return p;
}

void expectSame(const ReconstructionParameters& a, const ReconstructionParameters& b) {
  EXPECT_EQ(a.stereo.minDisparityPx, b.stereo.minDisparityPx);
  EXPECT_EQ(a.stereo.maxDisparityPx, b.stereo.maxDisparityPx);
  EXPECT_EQ(a.stereo.znccWindowPx, b.stereo.znccWindowPx);
  EXPECT_FLOAT_EQ(a.stereo.refineAlpha, b.stereo.refineAlpha);
  EXPECT_DOUBLE_EQ(a.tracking.inlierThresholdPx, b.tracking.inlierThresholdPx);
  EXPECT_DOUBLE_EQ(a.tracking.candidateEta, b.tracking.candidateEta);
  EXPECT_EQ(a.tracking.candidateRampIterations, b.tracking.candidateRampIterations);
  EXPECT_DOUBLE_EQ(a.tracking.keyFramePoseThreshold, b.tracking.keyFramePoseThreshold);
  EXPECT_EQ(a.tracking.keyFrameMinGapFrames, b.tracking.keyFrameMinGapFrames);
  EXPECT_EQ(a.tracking.keyFrameMinInliers, b.tracking.keyFrameMinInliers);
  EXPECT_DOUBLE_EQ(a.refinement.icpWeightFactor, b.refinement.icpWeightFactor);
  EXPECT_DOUBLE_EQ(a.refinement.icpTukeyMm, b.refinement.icpTukeyMm);
  EXPECT_EQ(a.refinement.maxMatchedKeyFrames, b.refinement.maxMatchedKeyFrames);
  EXPECT_DOUBLE_EQ(a.fusion.truncationMm, b.fusion.truncationMm);
  EXPECT_DOUBLE_EQ(a.fusion.colourMinWeight, b.fusion.colourMinWeight);
  EXPECT_EQ(a.fusion.newPointStepPx, b.fusion.newPointStepPx);
  EXPECT_EQ(a.fusion.maxPoints, b.fusion.maxPoints);
}

QDoubleSpinBox* realBox(QWidget& panel, const char* key) {
  return panel.findChild<QDoubleSpinBox*>(QString(key) + "SpinBox");
}
QSpinBox* intBox(QWidget& panel, const char* key) { return panel.findChild<QSpinBox*>(QString(key) + "SpinBox"); }

/// A source with no frames: a scan on it ends at once but exists until reset.
class EmptySource : public tissuemosaic::StereoFrameSource {
public:
  bool next(tissuemosaic::StereoFrame&) override { return false; }
  int frameCount() const override { return 0; }
  cv::Size frameSize() const override { return {64, 48}; }
  std::string description() const override { return "empty"; }
};

/// `count` frames of one pair.
class RepeatedPairSource : public tissuemosaic::StereoFrameSource {
public:
  RepeatedPairSource(cv::Mat left, cv::Mat right, int count) : left_(left), right_(right), count_(count) {}
  bool next(tissuemosaic::StereoFrame& frame) override {
    if (next_ >= count_) return false;
    frame.index = next_;
    frame.timeS = next_ / 30.0;
    frame.left = left_;
    frame.right = right_;
    ++next_;
    return true;
  }
  int frameCount() const override { return count_; }
  cv::Size frameSize() const override { return left_.size(); }
  std::string description() const override { return "one pair, repeated"; }

private:
  cv::Mat left_, right_;
  int count_, next_ = 0;
};

tissuemosaic::RectifiedGeometry emptyGeometry() {
  tissuemosaic::RectifiedGeometry geometry;
  geometry.imageSize = cv::Size(64, 48);
  geometry.focalPx = 60;
  geometry.cxLeftPx = 32;
  geometry.cyPx = 24;
  geometry.baselineMm = 5;
  return geometry;
}

}  // namespace

TEST(ReconstructionParametersWidget, ShowsEveryFieldAndReadsEditsBack) {
  qTissueMosaicReconstructionParametersWidget panel;
  const ReconstructionParameters unusual = unusualParameters();
  ASSERT_TRUE(panel.setParameters(unusual)) << panel.errorText().toStdString();
  // Object -> panel: the controls show the values (the stereo ones in the embedded stereo panel).
  EXPECT_EQ(realBox(panel, "inlierThresholdPx")->value(), 3.5);
  EXPECT_EQ(realBox(panel, "keyFramePoseThreshold")->value(), 4.5);
  EXPECT_EQ(intBox(panel, "keyFrameMinGapFrames")->value(), 6);
  EXPECT_EQ(realBox(panel, "truncationMm")->value(), 2.25);
  EXPECT_EQ(intBox(panel, "maxPoints")->value(), 5000000);
  EXPECT_EQ(intBox(panel, "znccWindowPx")->value(), 9);
  EXPECT_EQ(realBox(panel, "refineAlpha")->value(), 0.25);
  expectSame(panel.parameters(), unusual);

  // Panel -> object: an edit in each group reaches the object, and each emits parametersChanged.
  QSignalSpy changed(&panel, &qTissueMosaicReconstructionParametersWidget::parametersChanged);
  realBox(panel, "inlierThresholdPx")->setValue(6.5);
  intBox(panel, "keyFrameMinInliers")->setValue(75);
  realBox(panel, "icpWeightFactor")->setValue(0.15);
  intBox(panel, "newPointStepPx")->setValue(3);
  intBox(panel, "maxDisparityPx")->setValue(60);
  realBox(panel, "refineEta")->setValue(0.02);
  EXPECT_EQ(changed.count(), 6);
  const ReconstructionParameters edited = panel.parameters();
  EXPECT_DOUBLE_EQ(edited.tracking.inlierThresholdPx, 6.5);
  EXPECT_EQ(edited.tracking.keyFrameMinInliers, 75);
  EXPECT_DOUBLE_EQ(edited.refinement.icpWeightFactor, 0.15);
  EXPECT_EQ(edited.fusion.newPointStepPx, 3);
  EXPECT_EQ(edited.stereo.maxDisparityPx, 60);
  EXPECT_FLOAT_EQ(edited.stereo.refineEta, 0.02f);
  EXPECT_TRUE(panel.errorText().isEmpty());
  // Every control explains itself.
  for (QAbstractSpinBox* box : panel.findChildren<QAbstractSpinBox*>()) {
    EXPECT_FALSE(box->toolTip().isEmpty()) << box->objectName().toStdString();
  }
}

TEST(ReconstructionParametersWidget, RefusesInvalidValuesWithTheReason) {
  qTissueMosaicReconstructionParametersWidget panel;
  const ReconstructionParameters before = panel.parameters();
  QSignalSpy changed(&panel, &qTissueMosaicReconstructionParametersWidget::parametersChanged);

  // A spin box holds exactly the table's range (issue 53: its limits exist once), so a value beyond it cannot be
  // typed: H stops at the table's 0.01, eta at 1, the new-point step at 1.
  const auto& threshold = tissuemosaic::trackingParameterTable().field("inlierThresholdPx");
  EXPECT_EQ(realBox(panel, "inlierThresholdPx")->minimum(), threshold.minimum);
  EXPECT_EQ(realBox(panel, "inlierThresholdPx")->maximum(), threshold.maximum);
  EXPECT_EQ(realBox(panel, "inlierThresholdPx")->toolTip().toStdString(), threshold.doc);
  realBox(panel, "inlierThresholdPx")->setValue(0.0);
  EXPECT_DOUBLE_EQ(panel.parameters().tracking.inlierThresholdPx, threshold.minimum);
  realBox(panel, "inlierThresholdPx")->setValue(4.0);
  EXPECT_EQ(changed.count(), 2);
  EXPECT_TRUE(panel.errorText().isEmpty());
  realBox(panel, "candidateEta")->setValue(0.5);
  EXPECT_DOUBLE_EQ(panel.parameters().tracking.candidateEta,
                   tissuemosaic::trackingParameterTable().field("candidateEta").minimum);
  realBox(panel, "candidateEta")->setValue(2.0);
  intBox(panel, "newPointStepPx")->setValue(0);
  EXPECT_EQ(panel.parameters().fusion.newPointStepPx, tissuemosaic::fusionParameterTable().field("newPointStepPx").minimum);
  intBox(panel, "newPointStepPx")->setValue(1);
  EXPECT_TRUE(panel.errorText().isEmpty());

  // The stereo panel refuses its own invalid combinations (min > max) with its message.
  intBox(panel, "minDisparityPx")->setValue(90);
  EXPECT_FALSE(panel.errorText().isEmpty());
  EXPECT_EQ(panel.parameters().stereo.minDisparityPx, before.stereo.minDisparityPx);

  ReconstructionParameters invalid;
  invalid.fusion.truncationMm = -1;
  EXPECT_FALSE(panel.setParameters(invalid));
  EXPECT_TRUE(panel.errorText().contains("truncationMm")) << panel.errorText().toStdString();
}

TEST(ReconstructionParametersWidget, EditsTheLogicsParametersAndDevice) {
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  qTissueMosaicReconstructionParametersWidget panel;
  ReconstructionParameters parameters = unusualParameters();
  ASSERT_TRUE(logic->SetParameters(parameters));
  panel.setReconstructionLogic(logic);
  EXPECT_EQ(realBox(panel, "inlierThresholdPx")->value(), 3.5);  // shows the logic's object
  realBox(panel, "keyFramePoseThreshold")->setValue(8.0);
  EXPECT_DOUBLE_EQ(logic->GetParameters().tracking.keyFramePoseThreshold, 8.0);
  intBox(panel, "znccWindowPx")->setValue(7);
  EXPECT_EQ(logic->GetParameters().stereo.znccWindowPx, 7);

  auto* device = panel.findChild<QComboBox*>("deviceComboBox");
  ASSERT_NE(device, nullptr);
  panel.setDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
  EXPECT_EQ(logic->GetDeviceChoice(), vtkTissueMosaicReconstructionLogic::DeviceCpu);
  EXPECT_EQ(device->currentData().toInt(), vtkTissueMosaicReconstructionLogic::DeviceCpu);
  auto* model = qobject_cast<QStandardItemModel*>(device->model());
  EXPECT_EQ(model->item(2)->isEnabled(), tissuemosaic::cudaAvailable()) << "CUDA offered only where it works";

  // During a scan the logic keeps its parameters: the panel shows why and keeps the logic's value.
  ASSERT_TRUE(logic->SetFrameSourceFactory([] { return std::make_unique<EmptySource>(); }));
  logic->SetRectifiedGeometry(emptyGeometry());
  logic->SetDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
  ASSERT_TRUE(logic->Start()) << logic->GetLastErrorText();
  realBox(panel, "keyFramePoseThreshold")->setValue(9.0);
  EXPECT_DOUBLE_EQ(logic->GetParameters().tracking.keyFramePoseThreshold, 8.0);
  EXPECT_TRUE(panel.errorText().contains("reset")) << panel.errorText().toStdString();
  logic->Reset();
  realBox(panel, "keyFramePoseThreshold")->setValue(9.5);
  EXPECT_DOUBLE_EQ(logic->GetParameters().tracking.keyFramePoseThreshold, 9.5);
}

TEST(ReconstructionParametersWidget, PresetsAndFilesRoundTrip) {
  qTissueMosaicReconstructionParametersWidget panel;
  EXPECT_TRUE(panel.presetNames().contains("paper defaults"));
  EXPECT_TRUE(panel.presetNames().contains("fast"));
  auto* presets = panel.findChild<QComboBox*>("reconstructionPresetComboBox");
  ASSERT_TRUE(panel.applyPreset("fast"));
  EXPECT_EQ(panel.parameters().stereo.znccWindowPx, 7);  // Resources/Presets/fast.yml
  EXPECT_EQ(presets->currentText(), "fast");
  realBox(panel, "inlierThresholdPx")->setValue(7.0);
  EXPECT_EQ(presets->currentText(), "(custom)");
  EXPECT_FALSE(panel.applyPreset("no such preset"));

  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  const QString path = QString(TM_TEST_OUTPUT_DIR) + "/reconstruction-panel.yml";
  ASSERT_TRUE(panel.setParameters(unusualParameters()));
  ASSERT_TRUE(panel.saveParametersFile(path)) << panel.errorText().toStdString();
  qTissueMosaicReconstructionParametersWidget other;
  ASSERT_TRUE(other.loadParametersFile(path)) << other.errorText().toStdString();
  expectSame(other.parameters(), unusualParameters());
  EXPECT_FALSE(other.loadParametersFile(path + ".missing"));
  EXPECT_TRUE(other.errorText().startsWith("Not loaded")) << other.errorText().toStdString();
}

TEST(ReconstructionParametersWidget, OnePresetRowShowsTheStereoPanelsIsHidden) {
  // The reconstruction panel offers presets and files for everything; the stereo panel inside it hides its own
  // row, which a stand-alone stereo panel shows. Both list "(custom)" first, then "paper defaults".
  qTissueMosaicReconstructionParametersWidget panel;
  panel.show();
  for (const char* name : {"reconstructionPresetLabel", "reconstructionPresetComboBox", "reconstructionLoadButton",
                           "reconstructionSaveButton"}) {
    auto* control = panel.findChild<QWidget*>(name);
    ASSERT_NE(control, nullptr) << name;
    EXPECT_TRUE(control->isVisible()) << name;
  }
  for (const char* name : {"presetLabel", "presetComboBox", "loadButton", "saveButton"}) {
    auto* control = panel.stereoPanel()->findChild<QWidget*>(name);
    ASSERT_NE(control, nullptr) << name;
    EXPECT_FALSE(control->isVisible()) << name;
  }
  qTissueMosaicStereoParametersWidget standAlone;
  standAlone.show();
  EXPECT_TRUE(standAlone.findChild<QWidget*>("presetComboBox")->isVisible());
  for (auto* comboBox : {panel.findChild<QComboBox*>("reconstructionPresetComboBox"),
                         standAlone.findChild<QComboBox*>("presetComboBox")}) {
    ASSERT_GE(comboBox->count(), 3);
    EXPECT_EQ(comboBox->itemText(0), "(custom)");
    EXPECT_EQ(comboBox->itemText(1), "paper defaults");
  }
  EXPECT_EQ(panel.findChild<QComboBox*>("reconstructionPresetComboBox")->currentText(), "paper defaults")
      << "the defaults match the paper-defaults preset";
}

TEST(ReconstructionVideoPanel, ShowsFramesInRgbOrder) {
  cv::Mat bgr(30, 40, CV_8UC3, cv::Scalar(10, 20, 200));  // B G R: a red picture
  const QImage image = qTissueMosaicVideoPanel::toQImage(bgr);
  ASSERT_FALSE(image.isNull());
  EXPECT_EQ(image.size(), QSize(40, 30));
  EXPECT_EQ(image.pixelColor(5, 5), QColor(200, 20, 10));
  const cv::Mat grey(30, 40, CV_8UC1, cv::Scalar(77));
  EXPECT_EQ(qTissueMosaicVideoPanel::toQImage(grey).pixelColor(0, 0), QColor(77, 77, 77));
  EXPECT_TRUE(qTissueMosaicVideoPanel::toQImage(cv::Mat(4, 4, CV_32F)).isNull());

  qTissueMosaicVideoPanel panel;
  cv::Mat disparity(30, 40, CV_32F, cv::Scalar(20.0f));
  disparity.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  disparity.at<float>(29, 39) = 40.0f;
  panel.setFrames(bgr, grey, disparity);
  EXPECT_EQ(panel.leftImage().pixelColor(1, 1), QColor(200, 20, 10));
  EXPECT_EQ(panel.rightImage().size(), QSize(40, 30));
  EXPECT_EQ(panel.frameSize(), QSize(40, 30));
  EXPECT_EQ(panel.disparityImage().pixelColor(0, 0), QColor(0, 0, 0)) << "no estimate: black";
  panel.clear();
  EXPECT_TRUE(panel.leftImage().isNull());
}

TEST(ReconstructionVideoPanel, DisparityHasALegendInPixelsAndMillimetres) {
  // A scene from 50 mm (disparity 40 px) to 100 mm (20 px): f = 400 px, B = 5 mm.
  cv::Mat disparity(60, 80, CV_32F, cv::Scalar(20.0f));
  disparity(cv::Rect(0, 0, 40, 60)).setTo(40.0f);
  tissuemosaic::RectifiedGeometry geometry;
  geometry.focalPx = 400;
  geometry.baselineMm = 5;
  qTissueMosaicVideoPanel panel;
  panel.setFrames(cv::Mat(), cv::Mat(), disparity, &geometry, -20, 80);
  const QStringList legend = panel.disparityLegend();
  ASSERT_EQ(legend.size(), 5);
  EXPECT_EQ(legend.first(), "40 px = 50 mm");  // near, at the top, red
  EXPECT_EQ(legend.last(), "20 px = 100 mm");
  EXPECT_EQ(legend[2], "30 px = 67 mm");
  const QImage image = panel.disparityImage();
  EXPECT_GT(image.pixelColor(10, 10).red(), image.pixelColor(10, 10).blue()) << "near is red";
  EXPECT_GT(image.pixelColor(70, 10).blue(), image.pixelColor(70, 10).red()) << "far is blue";
  panel.setFrames(cv::Mat(), cv::Mat(), disparity);  // no geometry: pixels only
  EXPECT_EQ(panel.disparityLegend().first(), "40 px");
}

TEST(ReconstructionModulePanel, ControlsFollowTheScanState) {
  qTissueMosaicReconstructionWidget panel;
  auto* start = panel.findChild<QPushButton*>("startButton");
  auto* reset = panel.findChild<QPushButton*>("resetButton");
  auto* exportModel = panel.findChild<QPushButton*>("exportModelButton");
  ASSERT_TRUE(start && reset && exportModel);
  EXPECT_FALSE(start->isEnabled()) << "no input yet";
  EXPECT_FALSE(exportModel->isEnabled());
  EXPECT_EQ(panel.timingTable()->rowCount(), 8);  // the paper's 7 stages and the model agreement

  EXPECT_FALSE(panel.openFrameFolders("/nonexistent/left", "/nonexistent/right"));
  EXPECT_FALSE(panel.lastMessage().isEmpty());
  vtkTissueMosaicReconstructionLogic* logic = panel.reconstructionLogic();
  ASSERT_TRUE(logic->SetFrameSourceFactory([] { return std::make_unique<EmptySource>(); }));
  logic->SetRectifiedGeometry(emptyGeometry());
  logic->SetDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
  panel.updateFromLogic();
  QSignalSpy states(&panel, &qTissueMosaicReconstructionWidget::scanStateChanged);
  ASSERT_TRUE(panel.start()) << panel.lastMessage().toStdString();
  ASSERT_TRUE(logic->WaitForScanEnd(30));
  panel.updateFromLogic();
  EXPECT_GE(states.count(), 1);
  EXPECT_EQ(states.last().at(0).toInt(), vtkTissueMosaicReconstructionLogic::StateFinished);
  EXPECT_FALSE(start->isEnabled()) << "an ended scan needs a reset";
  EXPECT_TRUE(reset->isEnabled());
  EXPECT_FALSE(panel.parametersPanel()->isEnabled()) << "parameters are fixed until reset";
  reset->click();
  EXPECT_TRUE(start->isEnabled());
  EXPECT_TRUE(panel.parametersPanel()->isEnabled());
}

TEST(ReconstructionModulePanel, APairOutOfRectificationStandsOutInTheDisparityLine) {
  tissuemosaic::synthetic::SyntheticStereoOptions options;
  options.width = 320;
  options.height = 180;
  options.supersampling = 1;
  options.rightRowsBelowPx = 4;
  const tissuemosaic::synthetic::SyntheticStereoPair pair = tissuemosaic::synthetic::renderSyntheticStereoPair(options);
  qTissueMosaicReconstructionWidget panel;
  auto* range = panel.findChild<QLabel*>("disparityRangeLabel");
  ASSERT_NE(range, nullptr);
  vtkTissueMosaicReconstructionLogic* logic = panel.reconstructionLogic();
  ASSERT_TRUE(logic->SetFrameSourceFactory(
      [pair] { return std::make_unique<RepeatedPairSource>(pair.leftRectified, pair.rightRectified, 2); }));
  logic->SetRectifiedGeometry(pair.geometry);
  logic->SetDeviceChoice(vtkTissueMosaicReconstructionLogic::DeviceCpu);
  panel.updateFromLogic();
  EXPECT_TRUE(range->styleSheet().isEmpty());
  ASSERT_TRUE(panel.start()) << panel.lastMessage().toStdString();
  ASSERT_TRUE(logic->WaitForScanEnd(60));
  panel.updateFromLogic();
  EXPECT_TRUE(range->text().contains("not rectified: the right view's rows lay 4 px below the left's"))
      << range->text().toStdString();
  EXPECT_TRUE(range->styleSheet().contains("#e65100")) << range->styleSheet().toStdString();
  // A reset forgets the scan and its warning.
  auto* reset = panel.findChild<QPushButton*>("resetButton");
  ASSERT_NE(reset, nullptr);
  reset->click();
  panel.updateFromLogic();
  EXPECT_TRUE(range->styleSheet().isEmpty()) << range->text().toStdString();
}

TEST(ReconstructionModulePanel, ARefusedValueIsRedAtItsFieldAndStartSaysWhy) {
  // Min disparity 100 with max 80: refused at once, shown at the field in red with the reason in its group, and
  // Start is disabled with the reason beside it, so that no scan runs with other values than those on screen.
  qTissueMosaicReconstructionWidget panel;
  vtkTissueMosaicReconstructionLogic* logic = panel.reconstructionLogic();
  ASSERT_TRUE(logic->SetFrameSourceFactory([] { return std::make_unique<EmptySource>(); }));
  logic->SetRectifiedGeometry(emptyGeometry());
  panel.setInputRectified(true);
  auto* start = panel.findChild<QPushButton*>("startButton");
  ASSERT_TRUE(start->isEnabled()) << panel.startProblem().toStdString();
  QSpinBox* minimum = intBox(panel, "minDisparityPx");
  minimum->setValue(100);
  EXPECT_EQ(logic->GetParameters().stereo.minDisparityPx, -20) << "the object keeps its valid value";
  EXPECT_TRUE(minimum->styleSheet().contains("#ffd7d7")) << "red at the field";
  EXPECT_TRUE(minimum->toolTip().contains("maxDisparityPx")) << minimum->toolTip().toStdString();
  EXPECT_TRUE(intBox(panel, "maxDisparityPx")->styleSheet().isEmpty()) << "only the refused field";
  // The reason in the field's own group, right under it.
  QLabel* groupLine = nullptr;
  for (QLabel* label : minimum->parentWidget()->findChildren<QLabel*>(QRegularExpression("^groupMessage"))) {
    if (!label->isHidden()) groupLine = label;
  }
  ASSERT_NE(groupLine, nullptr) << "no message in the field's group";
  EXPECT_TRUE(groupLine->text().contains("maxDisparityPx")) << groupLine->text().toStdString();
  EXPECT_FALSE(start->isEnabled());
  EXPECT_TRUE(panel.startProblem().contains("not applied")) << panel.startProblem().toStdString();
  EXPECT_TRUE(start->toolTip().contains("Cannot start")) << start->toolTip().toStdString();
  intBox(panel, "maxDisparityPx")->setValue(120);  // now valid: both values go through, red and reason gone
  EXPECT_EQ(logic->GetParameters().stereo.minDisparityPx, 100);
  EXPECT_TRUE(minimum->styleSheet().isEmpty());
  EXPECT_TRUE(groupLine->isHidden());
  EXPECT_TRUE(start->isEnabled()) << panel.startProblem().toStdString();
}

TEST(ReconstructionModulePanel, ACalibrationOfAnotherFrameSizeIsNotCalledCalibrated) {
  // A new input keeps the previous input's calibration: the panel says it does not fit, and Start says why.
  qTissueMosaicReconstructionWidget panel;
  vtkTissueMosaicReconstructionLogic* logic = panel.reconstructionLogic();
  tissuemosaic::RectifiedGeometry other = emptyGeometry();
  other.imageSize = cv::Size(480, 270);
  logic->SetRectifiedGeometry(other);
  ASSERT_TRUE(logic->SetFrameSourceFactory([] { return std::make_unique<EmptySource>(); }));  // 64x48 frames
  panel.setInputRectified(true);
  const QString input = panel.findChild<QLabel*>("inputLabel")->text();
  EXPECT_FALSE(input.endsWith("; calibrated")) << input.toStdString();
  EXPECT_TRUE(input.contains("another frame size")) << input.toStdString();
  EXPECT_FALSE(panel.findChild<QPushButton*>("startButton")->isEnabled());
  EXPECT_TRUE(panel.startProblem().contains("480x270")) << panel.startProblem().toStdString();
  EXPECT_TRUE(panel.startProblem().contains("64x48")) << panel.startProblem().toStdString();
}

TEST(ReconstructionParametersWidget, TheWheelChangesNoValueUnlessTheFieldHasFocus) {
  // Scrolling the panel with the wheel over a field must not change it (it had turned -20 into -76).
  qTissueMosaicReconstructionParametersWidget panel;
  panel.show();
  QApplication::setActiveWindow(&panel);
  ASSERT_TRUE(QTest::qWaitForWindowActive(&panel));
  QSpinBox* minimum = intBox(panel, "minDisparityPx");
  const auto wheel = [&](QWidget* target) {
    QWheelEvent event(QPointF(5, 5), minimum->mapToGlobal(QPoint(5, 5)), QPoint(), QPoint(0, 120), Qt::NoButton,
                      Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(target, &event);
    return event.isAccepted();
  };
  intBox(panel, "maxDisparityPx")->setFocus();  // the keyboard is elsewhere
  ASSERT_FALSE(minimum->hasFocus());
  EXPECT_FALSE(wheel(minimum)) << "an unfocused field passes the wheel on (to the scroll area)";
  EXPECT_EQ(minimum->value(), -20);
  EXPECT_EQ(panel.parameters().stereo.minDisparityPx, -20);
  EXPECT_EQ(minimum->focusPolicy(), Qt::StrongFocus);
  auto* preset = panel.findChild<QComboBox*>("reconstructionPresetComboBox");
  ASSERT_NE(preset, nullptr);
  const int presetIndex = preset->currentIndex();
  ASSERT_FALSE(preset->hasFocus());
  wheel(preset);
  EXPECT_EQ(preset->currentIndex(), presetIndex);
  minimum->setFocus();  // clicked or tabbed into: now the wheel edits it
  ASSERT_TRUE(minimum->hasFocus());
  wheel(minimum);
  EXPECT_EQ(minimum->value(), -19);
}

TEST(ReconstructionParametersWidget, ABrokenParameterFileIsExplainedBesideLoadInPlainWords) {
  const std::string path = std::string(TM_TEST_OUTPUT_DIR) + "/broken-parameters.yml";
  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  {
    std::ofstream file(path);
    file << "%YAML:1.0\nstereo:\n  minDisparityPx: [1, 2\n  maxDisparityPx: }\n";
  }
  qTissueMosaicReconstructionParametersWidget panel;
  panel.resize(500, 2000);
  panel.show();
  EXPECT_FALSE(panel.loadParametersFile(QString::fromStdString(path)));
  QLabel* error = panel.findChild<QLabel*>("reconstructionErrorLabel");
  ASSERT_NE(error, nullptr);
  EXPECT_TRUE(error->isVisible());
  EXPECT_TRUE(error->text().contains("broken-parameters.yml")) << error->text().toStdString();
  EXPECT_TRUE(error->text().contains("not a valid YAML/XML file")) << error->text().toStdString();
  for (const char* internal : {"persistence", ".cpp", "error: (", "OpenCV("}) {
    EXPECT_FALSE(error->text().contains(internal)) << internal << " in: " << error->text().toStdString();
  }
  // Where the action was: right under the row with Load..., above every parameter.
  auto* load = panel.findChild<QPushButton*>("reconstructionLoadButton");
  ASSERT_NE(load, nullptr);
  const int errorTop = error->mapTo(&panel, QPoint(0, 0)).y();
  const int loadBottom = load->mapTo(&panel, QPoint(0, load->height())).y();
  EXPECT_GE(errorTop, loadBottom);
  EXPECT_LT(errorTop - loadBottom, 60);
  EXPECT_LT(errorTop, intBox(panel, "minDisparityPx")->mapTo(&panel, QPoint(0, 0)).y());
}

TEST(ReconstructionModulePanel, ShowsTheDisparityRangeAndWhatAWorkingDistanceMeans) {
  qTissueMosaicReconstructionWidget panel;
  auto* range = panel.findChild<QLabel*>("disparityRangeLabel");
  ASSERT_NE(range, nullptr);
  EXPECT_TRUE(range->text().contains("auto: from the first frame")) << range->text().toStdString();

  // With the rig known (f B = 300 px mm), a working distance of 10..30 mm is 10..30 px: 8..31 px on the grid, both
  // in the scan's line and beside the working distance fields.
  vtkTissueMosaicReconstructionLogic* logic = panel.reconstructionLogic();
  ASSERT_TRUE(logic->SetFrameSourceFactory([] { return std::make_unique<EmptySource>(); }));
  logic->SetRectifiedGeometry(emptyGeometry());
  realBox(panel, "workingDistanceFarMm")->setValue(30);
  realBox(panel, "workingDistanceNearMm")->setValue(10);
  EXPECT_EQ(logic->GetParameters().stereo.disparityRangeMode, tissuemosaic::DisparityRangeMode::WorkingDistance);
  EXPECT_TRUE(range->text().contains("working distance 10..30 mm: 8..31 px")) << range->text().toStdString();
  const QString beside = panel.parametersPanel()->stereoPanel()->workingDistanceText();
  EXPECT_TRUE(beside.contains("10..30 mm is 8..31 px")) << beside.toStdString();
}
