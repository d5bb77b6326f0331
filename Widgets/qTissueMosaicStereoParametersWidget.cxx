#include "qTissueMosaicStereoParametersWidget.h"

#include "qTissueMosaicParameterFields.h"
#include "qTissueMosaicPresetControls.h"
#include "qTissueMosaicWheelGuard.h"
#include "vtkTissueMosaicStereoLogic.h"

#include "Stereo/DisparityRange.h"
#include "Stereo/StereoParameterTable.h"

#include <vtkSmartPointer.h>

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QLabel>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QVBoxLayout>

#include <algorithm>
#include <exception>
#include <iterator>
#include <map>
#include <optional>
#include <vector>

namespace {

using tissuemosaic::StereoMethod;
using tissuemosaic::StereoParameters;
namespace widgets = tissuemosaic::widgets;

/// Range: the disparity range (both methods); Matching: what else both methods use; Zncc, Outliers and Refinement:
/// the paper's method (section II); AdCensus: the optional second method. The groups of the method not chosen are
/// disabled.
enum Group { Range, Matching, Zncc, Outliers, Refinement, AdCensus, GroupCount };

using Field = widgets::ParameterField<StereoParameters>;

/// One spin box per numeric row of the stereo table (qTissueMosaicParameterFields.h): limits, unit and tooltip are
/// the table's, so a spin box holds what validate() takes; combinations (min <= max, odd window) are checked by
/// validate and refused with its message, shown at the fields. Here: label, group, step and decimals.
Field row(const char* key, const char* label, Group group, double step, int decimals) {
  return widgets::tableRow(tissuemosaic::stereoParameterTable(), key, label, group, step, decimals);
}

const std::vector<Field>& fields() {
  static const std::vector<Field> table = {
    row("minDisparityPx", "Min disparity", Range, 1, 0),
    row("maxDisparityPx", "Max disparity", Range, 1, 0),
    row("workingDistanceNearMm", "Working distance from", Range, 5.0, 1),
    row("workingDistanceFarMm", "Working distance to", Range, 5.0, 1),
    row("leftRightMaxDifferencePx", "Left-right check", Matching, 1, 0),
    row("rangeEndMarginPx", "Range-end margin", Matching, 1, 0),
    row("specularMarginPx", "Highlight margin", Matching, 1, 0),
    row("specularMaxRadiusPx", "Highlight max. radius", Matching, 1, 0),
    row("trackingHighlightMarginPx", "Tracking highlight margin", Matching, 1, 0),
    row("znccWindowPx", "ZNCC window", Zncc, 2, 0),
    row("outlierIterations", "Iterations", Outliers, 1, 0),
    row("outlierRadiusStartPx", "Detection radius r", Outliers, 1, 0),
    row("outlierRadiusStepPx", "Radius step dr", Outliers, 1, 0),
    row("holeRadialRadiusPx", "Radial filling radius", Outliers, 1, 0),
    row("holeRadialMinLines", "Radial filling lines", Outliers, 1, 0),
    row("holeDiscRadiusPx", "Disc filling radius", Outliers, 1, 0),
    row("refineIterations", "Iterations", Refinement, 1, 0),
    row("refineRadiusPx", "Smoothing radius", Refinement, 1, 0),
    row("refineSearchPx", "Re-selection range", Refinement, 1, 0),
    row("censusWidthPx", "Census width", AdCensus, 2, 0),
    row("censusHeightPx", "Census height", AdCensus, 2, 0),
    row("armMaxPx", "Arm length L1", AdCensus, 1, 0),
    row("armLongPx", "Long arm from L2", AdCensus, 1, 0),
    row("armLimitGrey", "Arm grey limit tau1", AdCensus, 1, 0),
    row("armLongLimitGrey", "Long arm limit tau2", AdCensus, 1, 0),
    row("aggregationIterations", "Aggregation rounds", AdCensus, 1, 0),
    row("pathEdgeGrey", "Path edge tau_SO", AdCensus, 1, 0),
    row("specularMinGrey", "Highlight grey level", Matching, 1.0, 1),
    row("specularMinContrastGrey", "Highlight contrast", Matching, 1.0, 1),
    row("specularViewToleranceGrey", "Highlight view tolerance", Matching, 1.0, 1),
    row("minWindowStdDev", "Min window std. dev.", Zncc, 0.5, 2),
    row("outlierSmoothnessPx", "Smoothness threshold", Outliers, 0.5, 2),
    row("holeMaxEdgeDifferencePx", "Filling edge limit", Outliers, 0.5, 2),
    row("holeDiscMinValidFraction", "Disc filling valid share", Outliers, 0.05, 2),
    row("refineAlpha", "Alpha", Refinement, 0.05, 3),
    row("refineEta", "Eta", Refinement, 0.005, 4),
    row("refineMaxDeviationPx", "Max. smoothing deviation", Refinement, 0.5, 2),
    row("censusLambda", "Census lambda", AdCensus, 1.0, 2),
    row("absoluteDifferenceLambda", "Grey difference lambda", AdCensus, 1.0, 2),
    row("pathPenaltySmall", "Path penalty P1", AdCensus, 0.25, 2),
    row("pathPenaltyLarge", "Path penalty P2", AdCensus, 0.25, 2),
  };
  return table;
}

struct MethodChoice {
  StereoMethod method;
  const char* label;
};
// Short enough for the module panel at 1280x800; the tooltip says more.
const MethodChoice methodChoices[] = {{StereoMethod::Paper, "Paper (ZNCC, section II)"},
                                      {StereoMethod::AdCensus, "AD-Census (Mei et al.)"}};

/// The method's item in the method combo box.
int methodIndex(StereoMethod method) {
  const auto* choice = std::find_if(std::begin(methodChoices), std::end(methodChoices),
                                    [method](const MethodChoice& c) { return c.method == method; });
  return static_cast<int>(choice - std::begin(methodChoices));
}

struct RangeChoice {
  tissuemosaic::DisparityRangeMode mode;
  const char* label;
};
const RangeChoice rangeChoices[] = {
    {tissuemosaic::DisparityRangeMode::Automatic, "Automatic (from the video)"},
    {tissuemosaic::DisparityRangeMode::Fixed, "Fixed: min..max disparity"},
    {tissuemosaic::DisparityRangeMode::WorkingDistance, "Working distance (mm)"}};

int rangeIndex(tissuemosaic::DisparityRangeMode mode) {
  const auto* choice = std::find_if(std::begin(rangeChoices), std::end(rangeChoices),
                                    [mode](const RangeChoice& c) { return c.mode == mode; });
  return static_cast<int>(choice - std::begin(rangeChoices));
}

bool sameParameters(const StereoParameters& a, const StereoParameters& b) {
  if (a.method != b.method || a.disparityRangeMode != b.disparityRangeMode) return false;
  for (const Field& field : fields()) {
    if (field.get(a) != field.get(b)) return false;
  }
  return true;
}

}  // namespace

class qTissueMosaicStereoParametersWidgetPrivate {
  Q_DECLARE_PUBLIC(qTissueMosaicStereoParametersWidget);

public:
  explicit qTissueMosaicStereoParametersWidgetPrivate(qTissueMosaicStereoParametersWidget& object) : q_ptr(&object) {}
  void setupUi();
  void loadPresets();
  void selectMatchingPreset();
  /// Enables the groups of the method in use and disables the other method's.
  void enableMethodGroups(StereoMethod method);
  /// The parameters the panel shows: the logic's when set, else the panel's own.
  const StereoParameters& current() const { return logic ? logic->GetStereoParameters() : ownParameters; }
  bool store(const StereoParameters& parameters);
  /// Marks the refused fields (reason empty: none) and tells the owner when that changed.
  void markRefused(const QString& reason);
  /// Says what the working distance fields mean in disparities (with the rig's geometry, when known).
  void showWorkingDistanceDisparities();
  /// The rig's geometry: the logic's when it has one, else what setRigGeometry gave.
  const tissuemosaic::RectifiedGeometry* geometry() const {
    if (logic && logic->HasRectifiedGeometry()) return &logic->GetRectifiedGeometry();
    return rigGeometry ? &*rigGeometry : nullptr;
  }

  qTissueMosaicStereoParametersWidget* const q_ptr;
  StereoParameters ownParameters;
  vtkSmartPointer<vtkTissueMosaicStereoLogic> logic;
  widgets::ParameterSpinBoxes<StereoParameters> spinBoxes;  ///< parallel to fields()
  QString refusal;  ///< why the values shown were not applied; empty when they are the object's
  std::map<QString, StereoParameters> presets;
  QComboBox* methodComboBox = nullptr;  ///< items parallel to methodChoices
  QComboBox* rangeComboBox = nullptr;   ///< items parallel to rangeChoices
  QLabel* workingDistanceLabel = nullptr;
  std::optional<tissuemosaic::RectifiedGeometry> rigGeometry;
  QGroupBox* groupBoxes[GroupCount] = {};
  widgets::PresetRow presetRow;
  QLabel* errorLabel = nullptr;
};

void qTissueMosaicStereoParametersWidgetPrivate::setupUi() {
  Q_Q(qTissueMosaicStereoParametersWidget);
  auto* layout = new QVBoxLayout(q);
  presetRow = widgets::addPresetRow(
      q, layout,
      {"", QObject::tr("Read the 'stereo' map of a YAML/XML parameter file."),
       QObject::tr("Write the current parameters to a YAML parameter file."), QObject::tr("Load stereo parameters"),
       QObject::tr("Save stereo parameters"), [q](const QString& path) { q->loadParametersFile(path); },
       [q](const QString& path) { q->saveParametersFile(path); }});
  // Beside Load/Save: where a file's error belongs.
  errorLabel = widgets::addErrorLabel(q, layout, "");

  const char* const groupTitles[GroupCount] = {"Disparity range", "Matching", "ZNCC matching (paper II.A)",
                                               "Outlier removal and hole filling (II.B)",
                                               "Improved Laplacian refinement (II.C)",
                                               "AD-Census (optional second method)"};
  std::vector<QFormLayout*> forms(GroupCount);
  for (int group = 0; group < GroupCount; ++group) {
    groupBoxes[group] = new QGroupBox(QObject::tr(groupTitles[group]), q);
    forms[group] = new QFormLayout(groupBoxes[group]);
    layout->addWidget(groupBoxes[group]);
  }
  rangeComboBox = new QComboBox(q);
  rangeComboBox->setObjectName("disparityRangeModeComboBox");
  for (const RangeChoice& choice : rangeChoices) rangeComboBox->addItem(QObject::tr(choice.label));
  rangeComboBox->setToolTip(
      QObject::tr("How the candidate disparities are chosen. Automatic: from sparse feature matches of the first "
                  "frames, then following the tissue as the scope moves (the default: no number to know). Fixed: "
                  "the min..max below. Working distance: the tissue's distance from the scope in mm, turned into "
                  "disparities through the calibration."));
  forms[Range]->addRow(QObject::tr("Range"), rangeComboBox);
  QObject::connect(rangeComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   &qTissueMosaicStereoParametersWidget::updateParametersFromGUI);
  widgets::guardWheel(rangeComboBox);
  methodComboBox = new QComboBox(q);
  methodComboBox->setObjectName("methodComboBox");
  for (const MethodChoice& choice : methodChoices) methodComboBox->addItem(QObject::tr(choice.label));
  methodComboBox->setToolTip(
      QObject::tr("Paper: ZNCC matching, outlier removal and hole filling, improved Laplacian refinement "
                  "(section II). AD-Census: Mei et al. 2011. The paper's method suits smooth, steep tissue; AD-Census suits scenes with sharp depth edges "
                  "(it meets the Middlebury bar the paper's local method does not) and is far slower on the CPU. "
                  "docs/STEREO.md compares them."));
  forms[Matching]->addRow(QObject::tr("Method"), methodComboBox);
  QObject::connect(methodComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   &qTissueMosaicStereoParametersWidget::updateParametersFromGUI);
  widgets::guardWheel(methodComboBox);
  spinBoxes.create(q, fields(), forms, [q] { q->updateParametersFromGUI(); });
  workingDistanceLabel = new QLabel(q);
  workingDistanceLabel->setObjectName("workingDistanceDisparitiesLabel");
  workingDistanceLabel->setWordWrap(true);
  forms[Range]->addRow(QString(), workingDistanceLabel);

  layout->addStretch(1);

  QObject::connect(presetRow.comboBox, QOverload<int>::of(&QComboBox::activated), q, [this](int index) {
    Q_Q(qTissueMosaicStereoParametersWidget);
    q->applyPreset(presetRow.comboBox->itemText(index));
  });
}

void qTissueMosaicStereoParametersWidgetPrivate::loadPresets() {
  presets = widgets::readPresets<StereoParameters>("stereo", &vtkTissueMosaicStereoLogic::ParseStereoParameters);
  widgets::fillPresetComboBox(presetRow.comboBox, presets);
}

void qTissueMosaicStereoParametersWidgetPrivate::enableMethodGroups(StereoMethod method) {
  const bool paper = method == StereoMethod::Paper;
  for (Group group : {Zncc, Outliers, Refinement}) groupBoxes[group]->setEnabled(paper);
  groupBoxes[AdCensus]->setEnabled(!paper);
}

void qTissueMosaicStereoParametersWidgetPrivate::selectMatchingPreset() {
  widgets::selectPreset(presetRow.comboBox, widgets::matchingPreset(presets, [this](const StereoParameters& preset) {
                          return sameParameters(preset, current());
                        }));
}

void qTissueMosaicStereoParametersWidgetPrivate::markRefused(const QString& reason) {
  Q_Q(qTissueMosaicStereoParametersWidget);
  const bool changed = reason != refusal;
  refusal = reason;
  spinBoxes.markRefused(current(), reason);
  if (changed) emit q->validityChanged();
}

void qTissueMosaicStereoParametersWidgetPrivate::showWorkingDistanceDisparities() {
  const StereoParameters& p = current();
  const QString distance = QObject::tr("%1..%2 mm").arg(p.workingDistanceNearMm).arg(p.workingDistanceFarMm);
  QString text;
  if (const tissuemosaic::RectifiedGeometry* rig = geometry()) {
    try {
      const tissuemosaic::DisparityRange range =
          tissuemosaic::disparityRangeForDepthMm(*rig, p.workingDistanceNearMm, p.workingDistanceFarMm);
      text = QObject::tr("A working distance of %1 is %2 with this rig.").arg(distance, QString::fromStdString(range.text()));
    } catch (const std::exception& error) {
      text = QString::fromStdString(error.what());
    }
  } else {
    text = QObject::tr("A working distance of %1: its disparities show once the calibration is known.").arg(distance);
  }
  if (p.disparityRangeMode == tissuemosaic::DisparityRangeMode::Automatic) {
    text = QObject::tr("Chosen from the video's first frames and followed during the scan. ") + text;
  }
  workingDistanceLabel->setText(text);
}

bool qTissueMosaicStereoParametersWidgetPrivate::store(const StereoParameters& parameters) {
  return widgets::storeValidated(parameters, errorLabel, [this](const StereoParameters& valid, std::string& reason) {
    if (!logic) {
      ownParameters = valid;
      return true;
    }
    if (logic->SetStereoParameters(valid)) return true;
    reason = logic->GetLastErrorText();
    return false;
  });
}

qTissueMosaicStereoParametersWidget::qTissueMosaicStereoParametersWidget(QWidget* parent)
    : QWidget(parent), d_ptr(new qTissueMosaicStereoParametersWidgetPrivate(*this)) {
  Q_D(qTissueMosaicStereoParametersWidget);
  d->setupUi();
  d->loadPresets();
  updateGUIFromParameters();
}

qTissueMosaicStereoParametersWidget::~qTissueMosaicStereoParametersWidget() = default;

tissuemosaic::StereoParameters qTissueMosaicStereoParametersWidget::parameters() const {
  Q_D(const qTissueMosaicStereoParametersWidget);
  return d->current();
}

bool qTissueMosaicStereoParametersWidget::setParameters(const tissuemosaic::StereoParameters& parameters) {
  Q_D(qTissueMosaicStereoParametersWidget);
  if (!d->store(parameters)) return false;
  updateGUIFromParameters();
  return true;
}

void qTissueMosaicStereoParametersWidget::setStereoLogic(vtkTissueMosaicStereoLogic* logic) {
  Q_D(qTissueMosaicStereoParametersWidget);
  d->logic = logic;
  updateGUIFromParameters();
}

vtkTissueMosaicStereoLogic* qTissueMosaicStereoParametersWidget::stereoLogic() const {
  Q_D(const qTissueMosaicStereoParametersWidget);
  return d->logic;
}

QStringList qTissueMosaicStereoParametersWidget::presetNames() const {
  Q_D(const qTissueMosaicStereoParametersWidget);
  return widgets::presetNames(d->presetRow.comboBox);
}

QString qTissueMosaicStereoParametersWidget::errorText() const {
  Q_D(const qTissueMosaicStereoParametersWidget);
  return d->errorLabel->text();
}

void qTissueMosaicStereoParametersWidget::setRigGeometry(const tissuemosaic::RectifiedGeometry* geometry) {
  Q_D(qTissueMosaicStereoParametersWidget);
  if (geometry) d->rigGeometry = *geometry;
  else d->rigGeometry.reset();
  d->showWorkingDistanceDisparities();
}

QString qTissueMosaicStereoParametersWidget::workingDistanceText() const {
  Q_D(const qTissueMosaicStereoParametersWidget);
  return d->workingDistanceLabel->text();
}

bool qTissueMosaicStereoParametersWidget::hasRefusedValues() const {
  Q_D(const qTissueMosaicStereoParametersWidget);
  return !d->refusal.isEmpty();
}

void qTissueMosaicStereoParametersWidget::setPresetControlsVisible(bool visible) {
  Q_D(qTissueMosaicStereoParametersWidget);
  widgets::setPresetRowVisible(d->presetRow, visible);
}

void qTissueMosaicStereoParametersWidget::updateGUIFromParameters() {
  Q_D(qTissueMosaicStereoParametersWidget);
  const StereoParameters& parameters = d->current();
  {
    const QSignalBlocker blocker(d->methodComboBox);
    d->methodComboBox->setCurrentIndex(methodIndex(parameters.method));
  }
  {
    const QSignalBlocker blocker(d->rangeComboBox);
    d->rangeComboBox->setCurrentIndex(rangeIndex(parameters.disparityRangeMode));
  }
  d->enableMethodGroups(parameters.method);
  d->spinBoxes.show(parameters);
  widgets::showError(d->errorLabel, QString());
  d->markRefused(QString());
  d->showWorkingDistanceDisparities();
  d->selectMatchingPreset();
}

bool qTissueMosaicStereoParametersWidget::updateParametersFromGUI() {
  Q_D(qTissueMosaicStereoParametersWidget);
  const StereoParameters before = d->current();
  StereoParameters parameters = before;
  parameters.method = methodChoices[d->methodComboBox->currentIndex()].method;
  d->spinBoxes.read(parameters);
  // Typing a range or a working distance means using it; otherwise the range combo box says how.
  if (parameters.minDisparityPx != before.minDisparityPx || parameters.maxDisparityPx != before.maxDisparityPx) {
    parameters.disparityRangeMode = tissuemosaic::DisparityRangeMode::Fixed;
  } else if (parameters.workingDistanceNearMm != before.workingDistanceNearMm ||
             parameters.workingDistanceFarMm != before.workingDistanceFarMm) {
    parameters.disparityRangeMode = tissuemosaic::DisparityRangeMode::WorkingDistance;
  } else {
    parameters.disparityRangeMode = rangeChoices[d->rangeComboBox->currentIndex()].mode;
  }
  if (!d->store(parameters)) {
    // Shown at the fields, in red, until fixed; the object keeps its last valid values.
    d->markRefused(d->errorLabel->text());
    return false;
  }
  d->markRefused(QString());
  {
    const QSignalBlocker blocker(d->rangeComboBox);
    d->rangeComboBox->setCurrentIndex(rangeIndex(parameters.disparityRangeMode));
  }
  d->showWorkingDistanceDisparities();
  d->enableMethodGroups(parameters.method);
  d->selectMatchingPreset();
  emit parametersChanged();
  return true;
}

bool qTissueMosaicStereoParametersWidget::applyPreset(const QString& name) {
  Q_D(qTissueMosaicStereoParametersWidget);
  const auto preset = d->presets.find(name);
  if (preset == d->presets.end()) {
    if (name != widgets::kCustomPresetLabel) widgets::showError(d->errorLabel, tr("Unknown preset '%1'").arg(name));
    return false;
  }
  if (!setParameters(preset->second)) return false;
  emit parametersChanged();
  return true;
}

bool qTissueMosaicStereoParametersWidget::loadParametersFile(const QString& path) {
  Q_D(qTissueMosaicStereoParametersWidget);
  StereoParameters parameters;
  std::string errorText;
  if (!vtkTissueMosaicStereoLogic::ReadStereoParametersFile(path.toStdString(), parameters, errorText)) {
    widgets::showError(d->errorLabel, tr("Not loaded: %1").arg(QString::fromStdString(errorText)));
    return false;
  }
  if (!setParameters(parameters)) return false;
  emit parametersChanged();
  return true;
}

bool qTissueMosaicStereoParametersWidget::saveParametersFile(const QString& path) {
  Q_D(qTissueMosaicStereoParametersWidget);
  std::string errorText;
  if (!vtkTissueMosaicStereoLogic::WriteStereoParametersFile(path.toStdString(), d->current(), errorText)) {
    widgets::showError(d->errorLabel, tr("Not saved: %1").arg(QString::fromStdString(errorText)));
    return false;
  }
  return true;
}
