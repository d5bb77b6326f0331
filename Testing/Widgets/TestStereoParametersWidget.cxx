// qTissueMosaicStereoParametersWidget: panel <-> parameters round trips, invalid edits refused with a visible
// message, presets, and editing a logic's parameters.
#include "qTissueMosaicStereoParametersWidget.h"
#include "StereoParametersTestFields.h"
#include "vtkTissueMosaicStereoLogic.h"

#include <gtest/gtest.h>

#include <vtkNew.h>

#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTimer>

#include <filesystem>

using tissuemosaic::StereoParameters;
using tissuemosaic::test::numericStereoFields;
using tissuemosaic::test::expectSameParameters;
using tissuemosaic::test::unusualParameters;

namespace {

QSpinBox* intBox(QWidget& widget, const char* key) {
  return widget.findChild<QSpinBox*>(QString(key) + "SpinBox");
}
QDoubleSpinBox* realBox(QWidget& widget, const char* key) {
  return widget.findChild<QDoubleSpinBox*>(QString(key) + "SpinBox");
}

}  // namespace

TEST(StereoParametersWidget, ObjectToPanelShowsEveryField) {
  qTissueMosaicStereoParametersWidget widget;
  // Every numeric row of the stereo table has its spin box, with the table's limits and doc (the method and the
  // range's mode have their combo boxes).
  ASSERT_TRUE(widget.setParameters(unusualParameters())) << widget.errorText().toStdString();
  const StereoParameters expected = unusualParameters();
  for (const auto* field : numericStereoFields()) {
    QAbstractSpinBox* box = nullptr;
    if (field->integer()) {
      QSpinBox* spinBox = intBox(widget, field->key);
      ASSERT_NE(spinBox, nullptr) << field->key;
      EXPECT_EQ(spinBox->value(), field->get(expected)) << field->key;
      EXPECT_EQ(spinBox->minimum(), field->minimum) << field->key;
      EXPECT_EQ(spinBox->maximum(), field->maximum) << field->key;
      box = spinBox;
    } else {
      QDoubleSpinBox* spinBox = realBox(widget, field->key);
      ASSERT_NE(spinBox, nullptr) << field->key;
      EXPECT_FLOAT_EQ(static_cast<float>(spinBox->value()), static_cast<float>(field->get(expected))) << field->key;
      EXPECT_EQ(spinBox->minimum(), field->minimum) << field->key;
      EXPECT_EQ(spinBox->maximum(), field->maximum) << field->key;
      box = spinBox;
    }
    EXPECT_EQ(box->toolTip().toStdString(), field->doc) << field->key;
  }
}

TEST(StereoParametersWidget, PanelToObjectRoundTrip) {
  qTissueMosaicStereoParametersWidget widget;
  QSignalSpy changed(&widget, &qTissueMosaicStereoParametersWidget::parametersChanged);
  const StereoParameters target = unusualParameters();
  // Edit as a user would, one spin box at a time, in the table's order; every intermediate state is valid.
  for (const auto* field : numericStereoFields()) {
    if (field->integer()) intBox(widget, field->key)->setValue(static_cast<int>(field->get(target)));
    else realBox(widget, field->key)->setValue(field->get(target));
  }
  expectSameParameters(widget.parameters(), target);
  EXPECT_EQ(changed.count(), static_cast<int>(numericStereoFields().size()));
  EXPECT_TRUE(widget.errorText().isEmpty());

  // And back: what the panel holds shows again after a GUI refresh.
  widget.updateGUIFromParameters();
  ASSERT_TRUE(widget.updateParametersFromGUI());
  expectSameParameters(widget.parameters(), target);
}

TEST(StereoParametersWidget, InvalidCombinationIsRefusedWithAVisibleMessage) {
  qTissueMosaicStereoParametersWidget widget;
  widget.show();
  QLabel* errorLabel = widget.findChild<QLabel*>("errorLabel");
  ASSERT_NE(errorLabel, nullptr);
  EXPECT_FALSE(errorLabel->isVisible());

  QSignalSpy changed(&widget, &qTissueMosaicStereoParametersWidget::parametersChanged);
  intBox(widget, "minDisparityPx")->setValue(90);  // above the max of 80
  EXPECT_EQ(widget.parameters().minDisparityPx, -20) << "the invalid value must not reach the object";
  EXPECT_EQ(changed.count(), 0);
  EXPECT_TRUE(errorLabel->isVisible());
  EXPECT_TRUE(errorLabel->text().contains("maxDisparityPx")) << errorLabel->text().toStdString();

  intBox(widget, "maxDisparityPx")->setValue(120);  // now valid again: both values go through
  EXPECT_EQ(widget.parameters().minDisparityPx, 90);
  EXPECT_EQ(widget.parameters().maxDisparityPx, 120);
  EXPECT_FALSE(errorLabel->isVisible());

  intBox(widget, "znccWindowPx")->setValue(10);  // even window
  EXPECT_EQ(widget.parameters().znccWindowPx, 11);
  EXPECT_TRUE(errorLabel->isVisible());
  EXPECT_TRUE(errorLabel->text().contains("odd")) << errorLabel->text().toStdString();

  StereoParameters inverted;
  inverted.minDisparityPx = 10;
  inverted.maxDisparityPx = 5;
  EXPECT_FALSE(widget.setParameters(inverted));
  EXPECT_EQ(widget.parameters().maxDisparityPx, 120);

  // Show the panel briefly, as a user would see it, then quit on a timer.
  QTimer::singleShot(50, qApp, &QApplication::quit);
  qApp->exec();
}

TEST(StereoParametersWidget, PresetsApplyTheirFiles) {
  qTissueMosaicStereoParametersWidget widget;
  const QStringList names = widget.presetNames();
  ASSERT_TRUE(names.contains("paper defaults")) << names.join(", ").toStdString();
  ASSERT_TRUE(names.contains("fast")) << names.join(", ").toStdString();
  EXPECT_EQ(names.first(), "paper defaults");

  StereoParameters fast;
  std::string errorText;
  ASSERT_TRUE(vtkTissueMosaicStereoLogic::ReadStereoParametersFile(TM_PRESETS_DIR "/fast.yml", fast, errorText))
      << errorText;
  ASSERT_TRUE(widget.applyPreset("fast"));
  expectSameParameters(widget.parameters(), fast);
  EXPECT_EQ(intBox(widget, "znccWindowPx")->value(), fast.znccWindowPx);
  auto* presetBox = widget.findChild<QComboBox*>("presetComboBox");
  ASSERT_NE(presetBox, nullptr);
  EXPECT_EQ(presetBox->currentText(), "fast");

  intBox(widget, "refineSearchPx")->setValue(fast.refineSearchPx + 1);  // an edit leaves the preset
  EXPECT_EQ(presetBox->currentText(), "(custom)");

  ASSERT_TRUE(widget.applyPreset("paper defaults"));
  expectSameParameters(widget.parameters(), StereoParameters{});
  EXPECT_FALSE(widget.applyPreset("no such preset"));
}

TEST(StereoParametersWidget, MethodChoiceSwitchesTheGroupsAndIsPartOfPresets) {
  qTissueMosaicStereoParametersWidget widget;
  auto* method = widget.findChild<QComboBox*>("methodComboBox");
  auto* presetBox = widget.findChild<QComboBox*>("presetComboBox");
  ASSERT_NE(method, nullptr);
  ASSERT_NE(presetBox, nullptr);
  ASSERT_EQ(method->count(), 2);
  QSpinBox* zncc = intBox(widget, "znccWindowPx");
  QSpinBox* census = intBox(widget, "censusWidthPx");
  QSpinBox* range = intBox(widget, "minDisparityPx");
  EXPECT_EQ(method->currentIndex(), 0);
  EXPECT_TRUE(zncc->isEnabled());
  EXPECT_FALSE(census->isEnabled());
  EXPECT_EQ(presetBox->currentText(), "paper defaults");

  QSignalSpy changed(&widget, &qTissueMosaicStereoParametersWidget::parametersChanged);
  method->setCurrentIndex(1);
  EXPECT_EQ(widget.parameters().method, tissuemosaic::StereoMethod::AdCensus);
  EXPECT_EQ(changed.count(), 1);
  EXPECT_FALSE(zncc->isEnabled()) << "the paper's groups do nothing under AD-Census";
  EXPECT_TRUE(census->isEnabled());
  EXPECT_TRUE(range->isEnabled()) << "both methods use the disparity range";
  // AD-Census with every other value at its default is the "ad census" preset, not "paper defaults".
  EXPECT_EQ(presetBox->currentText(), "ad census");

  ASSERT_TRUE(widget.applyPreset("paper defaults"));
  EXPECT_EQ(method->currentIndex(), 0);
  EXPECT_TRUE(zncc->isEnabled());
  EXPECT_FALSE(census->isEnabled());

  // The method travels through parameter files like every other field.
  StereoParameters adCensus = unusualParameters();
  adCensus.method = tissuemosaic::StereoMethod::AdCensus;
  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  const std::string path = TM_TEST_OUTPUT_DIR "/widget-ad-census.yml";
  std::string errorText;
  ASSERT_TRUE(vtkTissueMosaicStereoLogic::WriteStereoParametersFile(path, adCensus, errorText)) << errorText;
  ASSERT_TRUE(widget.loadParametersFile(QString::fromStdString(path))) << widget.errorText().toStdString();
  EXPECT_EQ(method->currentIndex(), 1);
  expectSameParameters(widget.parameters(), adCensus);
  EXPECT_EQ(presetBox->currentText(), "(custom)");
}

TEST(StereoParametersWidget, EditsTheLogicsParametersAndFiles) {
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  ASSERT_TRUE(logic->SetStereoParameters(unusualParameters()));
  qTissueMosaicStereoParametersWidget widget;
  widget.setStereoLogic(logic);
  EXPECT_EQ(intBox(widget, "maxDisparityPx")->value(), 57);

  intBox(widget, "maxDisparityPx")->setValue(64);
  EXPECT_EQ(logic->GetStereoParameters().maxDisparityPx, 64);
  intBox(widget, "maxDisparityPx")->setValue(-10);  // below the min of -7: refused
  EXPECT_EQ(logic->GetStereoParameters().maxDisparityPx, 64);

  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  const QString path = TM_TEST_OUTPUT_DIR "/widget-parameters.yml";
  intBox(widget, "maxDisparityPx")->setValue(64);
  ASSERT_TRUE(widget.saveParametersFile(path)) << widget.errorText().toStdString();
  ASSERT_TRUE(widget.applyPreset("paper defaults"));
  EXPECT_EQ(logic->GetStereoParameters().maxDisparityPx, 80);
  ASSERT_TRUE(widget.loadParametersFile(path)) << widget.errorText().toStdString();
  StereoParameters expected = unusualParameters();
  expected.maxDisparityPx = 64;
  expected.disparityRangeMode = tissuemosaic::DisparityRangeMode::Fixed;  // typing a max disparity fixes the range
  expectSameParameters(logic->GetStereoParameters(), expected);
  EXPECT_FALSE(widget.loadParametersFile(TM_TEST_OUTPUT_DIR "/missing.yml"));
  EXPECT_FALSE(widget.errorText().isEmpty());
}

TEST(StereoParametersWidget, WorkingDistanceFieldsShowTheirDisparitiesAndChooseTheRange) {
  qTissueMosaicStereoParametersWidget widget;
  auto* mode = widget.findChild<QComboBox*>("disparityRangeModeComboBox");
  auto* label = widget.findChild<QLabel*>("workingDistanceDisparitiesLabel");
  ASSERT_NE(mode, nullptr);
  ASSERT_NE(label, nullptr);
  // The default is automatic, and no rig is known yet: no disparities to show.
  EXPECT_EQ(widget.parameters().disparityRangeMode, tissuemosaic::DisparityRangeMode::Automatic);
  EXPECT_EQ(mode->currentIndex(), 0);
  EXPECT_TRUE(label->text().contains("once the calibration is known")) << label->text().toStdString();

  // A rig of f B = 5000 px mm: 50..100 mm are disparities 50..100 px (48..103 px on the kernels' grid).
  tissuemosaic::RectifiedGeometry rig;
  rig.imageSize = cv::Size(640, 360);
  rig.focalPx = 1000;
  rig.baselineMm = 5;
  widget.setRigGeometry(&rig);
  realBox(widget, "workingDistanceNearMm")->setValue(50);
  realBox(widget, "workingDistanceFarMm")->setValue(100);
  EXPECT_EQ(widget.parameters().disparityRangeMode, tissuemosaic::DisparityRangeMode::WorkingDistance)
      << "typing a working distance uses it";
  EXPECT_EQ(mode->currentIndex(), 2);
  EXPECT_TRUE(label->text().contains("50..100 mm is 48..103 px")) << label->text().toStdString();
  EXPECT_EQ(widget.workingDistanceText(), label->text());

  // An inverted working distance is refused and named.
  realBox(widget, "workingDistanceFarMm")->setValue(40);
  EXPECT_FLOAT_EQ(widget.parameters().workingDistanceFarMm, 100.0f);
  EXPECT_TRUE(widget.errorText().contains("workingDistanceFarMm")) << widget.errorText().toStdString();
  realBox(widget, "workingDistanceFarMm")->setValue(100);

  // Typing a disparity fixes the range; the combo box goes back to automatic.
  intBox(widget, "maxDisparityPx")->setValue(70);
  EXPECT_EQ(widget.parameters().disparityRangeMode, tissuemosaic::DisparityRangeMode::Fixed);
  EXPECT_EQ(mode->currentIndex(), 1);
  mode->setCurrentIndex(0);
  EXPECT_EQ(widget.parameters().disparityRangeMode, tissuemosaic::DisparityRangeMode::Automatic);
  EXPECT_EQ(widget.parameters().maxDisparityPx, 70) << "the fixed range is kept for later";
  EXPECT_TRUE(label->text().contains("followed during the scan")) << label->text().toStdString();
  widget.setRigGeometry(nullptr);
  EXPECT_TRUE(label->text().contains("once the calibration is known")) << label->text().toStdString();
}
