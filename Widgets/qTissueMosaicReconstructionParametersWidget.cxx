#include "qTissueMosaicReconstructionParametersWidget.h"

#include "qTissueMosaicParameterFields.h"
#include "qTissueMosaicPresetControls.h"
#include "qTissueMosaicStereoParametersWidget.h"
#include "qTissueMosaicWheelGuard.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "Core/Device.h"
#include "Fusion/FusionParameterTable.h"
#include "Refinement/RefinementParameterTable.h"
#include "Tracking/TrackingParameterTable.h"

#include <vtkSmartPointer.h>

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QStandardItemModel>
#include <QVBoxLayout>

#include <opencv2/core/persistence.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <type_traits>
#include <vector>

namespace {

using tissuemosaic::ReconstructionParameters;
using Parameters = ReconstructionParameters;
namespace widgets = tissuemosaic::widgets;

enum Group { Tracking, KeyFrames, Refinement, Fusion };

using Field = widgets::ParameterField<Parameters>;

/// One spin box per field outside the stereo panel, each a row of its stage's table (qTissueMosaicParameterFields.h):
/// limits, unit and tooltip are the table's. Here: label, group, step and decimals.
Field trackingRow(const char* key, const char* label, Group group, double step, int decimals) {
  return widgets::tableRow(tissuemosaic::trackingParameterTable(), &Parameters::tracking, key, label, group, step,
                           decimals);
}
Field refinementRow(const char* key, const char* label, Group group, double step, int decimals) {
  return widgets::tableRow(tissuemosaic::refinementParameterTable(), &Parameters::refinement, key, label, group, step,
                           decimals);
}
Field fusionRow(const char* key, const char* label, Group group, double step, int decimals) {
  return widgets::tableRow(tissuemosaic::fusionParameterTable(), &Parameters::fusion, key, label, group, step,
                           decimals);
}

const std::vector<Field>& fields() {
  static const std::vector<Field> table = {
      trackingRow("inlierThresholdPx", "Inlier threshold H", Tracking, 0.5, 2),
      trackingRow("candidateEta", "Candidate factor eta", Tracking, 0.1, 2),
      trackingRow("candidateRampIterations", "Candidate ramp T", Tracking, 1, 0),
      trackingRow("keyFramePoseThreshold", "Key frame threshold", KeyFrames, 0.5, 2),
      trackingRow("keyFrameMinGapFrames", "Key frame min gap", KeyFrames, 1, 0),
      trackingRow("keyFrameMinInliers", "Key frame min inliers", KeyFrames, 5, 0),
      refinementRow("icpWeightFactor", "ICP weight factor", Refinement, 0.05, 3),
      refinementRow("icpTukeyMm", "ICP Tukey constant", Refinement, 0.5, 3),
      refinementRow("maxMatchedKeyFrames", "Matched key frames", Refinement, 1, 0),
      fusionRow("truncationMm", "TSDF truncation", Fusion, 0.1, 3),
      fusionRow("colourMinWeight", "Edge colour weight", Fusion, 0.05, 3),
      fusionRow("newPointStepPx", "New point step", Fusion, 1, 0),
      fusionRow("conflictMinWeight", "Outlier guard", Fusion, 1, 0),
      fusionRow("maxPoints", "Point budget", Fusion, 100000, 0),
  };
  return table;
}

/// The parameters as YAML text: two objects are equal when their texts are.
std::string canonicalText(const Parameters& p) {
  cv::FileStorage storage(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  p.stereo.write(storage);
  p.features.write(storage);
  p.tracking.write(storage);
  p.refinement.write(storage);
  p.fusion.write(storage);
  storage << "extractor" << static_cast<int>(p.extractor);
  return storage.releaseAndGetString();
}

}  // namespace

class qTissueMosaicReconstructionParametersWidgetPrivate {
  Q_DECLARE_PUBLIC(qTissueMosaicReconstructionParametersWidget);

public:
  explicit qTissueMosaicReconstructionParametersWidgetPrivate(qTissueMosaicReconstructionParametersWidget& object)
      : q_ptr(&object) {}
  void setupUi();
  void loadPresets();
  void selectMatchingPreset();
  const Parameters& current() const { return logic ? logic->GetParameters() : ownParameters; }
  bool store(const Parameters& parameters);
  /// Marks the refused fields (reason empty: none) and tells the owner when that changed.
  void markRefused(const QString& reason);

  qTissueMosaicReconstructionParametersWidget* const q_ptr;
  Parameters ownParameters;
  int ownDeviceChoice = vtkTissueMosaicReconstructionLogic::DeviceAuto;
  vtkSmartPointer<vtkTissueMosaicReconstructionLogic> logic;
  qTissueMosaicStereoParametersWidget* stereoPanel = nullptr;
  widgets::ParameterSpinBoxes<Parameters> spinBoxes;  ///< parallel to fields()
  QString refusal;  ///< why the values shown were not applied; empty when they are the object's
  std::map<QString, Parameters> presets;
  widgets::PresetRow presetRow;
  QComboBox* deviceComboBox = nullptr;
  QLabel* errorLabel = nullptr;
};

void qTissueMosaicReconstructionParametersWidgetPrivate::setupUi() {
  Q_Q(qTissueMosaicReconstructionParametersWidget);
  auto* layout = new QVBoxLayout(q);
  layout->setContentsMargins(0, 0, 0, 0);

  presetRow = widgets::addPresetRow(
      q, layout,
      {"reconstruction",
       QObject::tr("Read a YAML/XML parameter file (nodes stereo, features, tracking, refinement, fusion; missing "
                   "keys keep the defaults)."),
       QObject::tr("Write every parameter to a YAML file (for `tissuemosaic reconstruct --params`)."),
       QObject::tr("Load reconstruction parameters"), QObject::tr("Save reconstruction parameters"),
       [q](const QString& path) { q->loadParametersFile(path); },
       [q](const QString& path) { q->saveParametersFile(path); }});
  // Beside Load/Save: where a file's error belongs.
  errorLabel = widgets::addErrorLabel(q, layout, "reconstruction");

  auto* deviceRow = new QHBoxLayout();
  deviceRow->addWidget(new QLabel(QObject::tr("Device:"), q));
  deviceComboBox = new QComboBox(q);
  deviceComboBox->setObjectName("deviceComboBox");
  deviceComboBox->addItem(QObject::tr("Auto (CUDA when available)"), vtkTissueMosaicReconstructionLogic::DeviceAuto);
  deviceComboBox->addItem(QObject::tr("CPU"), vtkTissueMosaicReconstructionLogic::DeviceCpu);
  deviceComboBox->addItem(QObject::tr("CUDA GPU"), vtkTissueMosaicReconstructionLogic::DeviceCuda);
  deviceComboBox->setToolTip(QObject::tr("Where the per-pixel stages run. The same algorithm runs on both; the GPU "
                                         "gives the paper's real-time speed."));
  if (!tissuemosaic::cudaAvailable()) {
    // Refuse CUDA where there is none, and say why, instead of failing at start.
    auto* model = qobject_cast<QStandardItemModel*>(deviceComboBox->model());
    QStandardItem* cuda = model->item(2);
    cuda->setEnabled(false);
    cuda->setToolTip(QString::fromStdString(tissuemosaic::cudaUnavailableReason()));
  }
  widgets::guardWheel(deviceComboBox);
  deviceRow->addWidget(deviceComboBox, 1);
  layout->addLayout(deviceRow);

  auto* stereoBox = new QGroupBox(QObject::tr("Stereo matching (paper II)"), q);
  auto* stereoLayout = new QVBoxLayout(stereoBox);
  stereoLayout->setContentsMargins(2, 2, 2, 2);
  stereoPanel = new qTissueMosaicStereoParametersWidget(stereoBox);
  stereoPanel->setObjectName("stereoParametersPanel");
  stereoPanel->setPresetControlsVisible(false);
  stereoLayout->addWidget(stereoPanel);
  layout->addWidget(stereoBox);

  const char* const groupTitles[] = {"Camera tracking (III.A-B)", "Key frames (III.C)", "Key-frame refinement (III.D)",
                                     "Fusion (III.E)"};
  std::vector<QFormLayout*> forms(4);
  for (int group = 0; group < 4; ++group) {
    auto* box = new QGroupBox(QObject::tr(groupTitles[group]), q);
    forms[group] = new QFormLayout(box);
    layout->addWidget(box);
  }
  spinBoxes.create(q, fields(), forms, [q] { q->updateParametersFromGUI(); });
  layout->addStretch(1);

  QObject::connect(stereoPanel, &qTissueMosaicStereoParametersWidget::parametersChanged, q,
                   &qTissueMosaicReconstructionParametersWidget::updateParametersFromGUI);
  QObject::connect(stereoPanel, &qTissueMosaicStereoParametersWidget::validityChanged, q,
                   &qTissueMosaicReconstructionParametersWidget::validityChanged);
  QObject::connect(deviceComboBox, QOverload<int>::of(&QComboBox::activated), q, [this](int index) {
    Q_Q(qTissueMosaicReconstructionParametersWidget);
    q->setDeviceChoice(deviceComboBox->itemData(index).toInt());
  });
  QObject::connect(presetRow.comboBox, QOverload<int>::of(&QComboBox::activated), q, [this](int index) {
    Q_Q(qTissueMosaicReconstructionParametersWidget);
    q->applyPreset(presetRow.comboBox->itemText(index));
  });
}

void qTissueMosaicReconstructionParametersWidgetPrivate::loadPresets() {
  presets = widgets::readPresets<Parameters>("reconstruction",
                                             &vtkTissueMosaicReconstructionLogic::ParseReconstructionParameters);
  widgets::fillPresetComboBox(presetRow.comboBox, presets);
}

void qTissueMosaicReconstructionParametersWidgetPrivate::selectMatchingPreset() {
  const std::string now = canonicalText(current());
  widgets::selectPreset(presetRow.comboBox, widgets::matchingPreset(presets, [&now](const Parameters& preset) {
                          return canonicalText(preset) == now;
                        }));
}

void qTissueMosaicReconstructionParametersWidgetPrivate::markRefused(const QString& reason) {
  Q_Q(qTissueMosaicReconstructionParametersWidget);
  const bool changed = reason != refusal;
  refusal = reason;
  spinBoxes.markRefused(current(), reason);
  if (changed) emit q->validityChanged();
}

bool qTissueMosaicReconstructionParametersWidgetPrivate::store(const Parameters& parameters) {
  return widgets::storeValidated(parameters, errorLabel, [this](const Parameters& valid, std::string& reason) {
    if (!logic) {
      ownParameters = valid;
      return true;
    }
    if (logic->SetParameters(valid)) return true;
    reason = logic->GetLastErrorText();
    return false;
  });
}

qTissueMosaicReconstructionParametersWidget::qTissueMosaicReconstructionParametersWidget(QWidget* parent)
    : QWidget(parent), d_ptr(new qTissueMosaicReconstructionParametersWidgetPrivate(*this)) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  d->setupUi();
  d->loadPresets();
  updateGUIFromParameters();
}

qTissueMosaicReconstructionParametersWidget::~qTissueMosaicReconstructionParametersWidget() = default;

ReconstructionParameters qTissueMosaicReconstructionParametersWidget::parameters() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return d->current();
}

bool qTissueMosaicReconstructionParametersWidget::setParameters(const ReconstructionParameters& parameters) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  if (!d->store(parameters)) return false;
  updateGUIFromParameters();
  return true;
}

void qTissueMosaicReconstructionParametersWidget::setReconstructionLogic(vtkTissueMosaicReconstructionLogic* logic) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  d->logic = logic;
  updateGUIFromParameters();
}

vtkTissueMosaicReconstructionLogic* qTissueMosaicReconstructionParametersWidget::reconstructionLogic() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return d->logic;
}

int qTissueMosaicReconstructionParametersWidget::deviceChoice() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return d->logic ? d->logic->GetDeviceChoice() : d->ownDeviceChoice;
}

void qTissueMosaicReconstructionParametersWidget::setDeviceChoice(int choice) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  if (d->logic) d->logic->SetDeviceChoice(choice);
  else d->ownDeviceChoice = choice;
  const QSignalBlocker blocker(d->deviceComboBox);
  d->deviceComboBox->setCurrentIndex(d->deviceComboBox->findData(deviceChoice()));
}

QStringList qTissueMosaicReconstructionParametersWidget::presetNames() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return widgets::presetNames(d->presetRow.comboBox);
}

QString qTissueMosaicReconstructionParametersWidget::errorText() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return d->errorLabel->text().isEmpty() ? d->stereoPanel->errorText() : d->errorLabel->text();
}

bool qTissueMosaicReconstructionParametersWidget::hasRefusedValues() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return !d->refusal.isEmpty() || d->stereoPanel->hasRefusedValues();
}

qTissueMosaicStereoParametersWidget* qTissueMosaicReconstructionParametersWidget::stereoPanel() const {
  Q_D(const qTissueMosaicReconstructionParametersWidget);
  return d->stereoPanel;
}

void qTissueMosaicReconstructionParametersWidget::updateGUIFromParameters() {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  const Parameters& parameters = d->current();
  d->stereoPanel->setParameters(parameters.stereo);
  d->spinBoxes.show(parameters);
  {
    const QSignalBlocker blocker(d->deviceComboBox);
    d->deviceComboBox->setCurrentIndex(d->deviceComboBox->findData(deviceChoice()));
  }
  widgets::showError(d->errorLabel, QString());
  d->markRefused(QString());
  d->selectMatchingPreset();
}

bool qTissueMosaicReconstructionParametersWidget::updateParametersFromGUI() {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  Parameters parameters = d->current();
  parameters.stereo = d->stereoPanel->parameters();
  d->spinBoxes.read(parameters);
  if (!d->store(parameters)) {
    // Shown at the fields, in red, until fixed; the object keeps its last valid values.
    d->markRefused(d->errorLabel->text());
    return false;
  }
  d->markRefused(QString());
  d->selectMatchingPreset();
  emit parametersChanged();
  return true;
}

bool qTissueMosaicReconstructionParametersWidget::applyPreset(const QString& name) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  const auto preset = d->presets.find(name);
  if (preset == d->presets.end()) {
    if (name != widgets::kCustomPresetLabel) widgets::showError(d->errorLabel, tr("Unknown preset '%1'").arg(name));
    return false;
  }
  if (!setParameters(preset->second)) return false;
  emit parametersChanged();
  return true;
}

bool qTissueMosaicReconstructionParametersWidget::loadParametersFile(const QString& path) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  Parameters parameters;
  std::string errorText;
  if (!vtkTissueMosaicReconstructionLogic::ReadReconstructionParametersFile(path.toStdString(), parameters,
                                                                            errorText)) {
    widgets::showError(d->errorLabel, tr("Not loaded: %1").arg(QString::fromStdString(errorText)));
    return false;
  }
  if (!setParameters(parameters)) return false;
  emit parametersChanged();
  return true;
}

bool qTissueMosaicReconstructionParametersWidget::saveParametersFile(const QString& path) {
  Q_D(qTissueMosaicReconstructionParametersWidget);
  std::string errorText;
  if (!vtkTissueMosaicReconstructionLogic::WriteReconstructionParametersFile(path.toStdString(), d->current(),
                                                                             errorText)) {
    widgets::showError(d->errorLabel, tr("Not saved: %1").arg(QString::fromStdString(errorText)));
    return false;
  }
  return true;
}
