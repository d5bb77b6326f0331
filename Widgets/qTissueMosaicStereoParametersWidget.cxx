#include "qTissueMosaicStereoParametersWidget.h"

#include "qTissueMosaicPresetControls.h"
#include "vtkTissueMosaicStereoLogic.h"

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
#include <iterator>
#include <map>
#include <vector>

namespace {

using tissuemosaic::StereoMethod;
using tissuemosaic::StereoParameters;
namespace widgets = tissuemosaic::widgets;

/// Matching: what both methods use; Zncc, Outliers and Refinement: the paper's method (section II); AdCensus: the
/// optional second method. The groups of the method not chosen are disabled.
enum Group { Matching, Zncc, Outliers, Refinement, AdCensus, GroupCount };

/// One spin box per field. Ranges are those StereoParameters::validate accepts, so the spin boxes never clamp
/// silently; combinations (min <= max, odd window) are checked by validate and refused with its message.
struct IntField {
  const char* key;
  const char* label;
  Group group;
  int StereoParameters::*member;
  int minimum, maximum, step;
  const char* suffix;
  const char* toolTip;
};

struct RealField {
  const char* key;
  const char* label;
  Group group;
  float StereoParameters::*member;
  double minimum, maximum, step;
  int decimals;
  const char* suffix;
  const char* toolTip;
};

const IntField intFields[] = {
    {"minDisparityPx", "Min disparity", Matching, &StereoParameters::minDisparityPx, -1000, 1000, 1, " px",
     "Smallest candidate disparity (a left pixel x matches right pixel x - d). Paper IV: candidates from -20 to "
     "80 px. Must not exceed the max disparity; at most 1024 candidates."},
    {"maxDisparityPx", "Max disparity", Matching, &StereoParameters::maxDisparityPx, -1000, 1000, 1, " px",
     "Largest candidate disparity, inclusive. Paper IV: 80 px (range -20..80). The matching cost grows with the "
     "number of candidates."},
    {"leftRightMaxDifferencePx", "Left-right check", Matching, &StereoParameters::leftRightMaxDifferencePx, -1,
     1000, 1, " px",
     "Winners whose right-view winner disagrees by more than this are dropped (occlusions, fattened depth edges). "
     "-1 switches the check off. An addition to the paper."},
    {"specularMarginPx", "Highlight margin", Matching, &StereoParameters::specularMarginPx, 0, 20, 1, " px",
     "Estimates within this distance of a highlight (the left pixel, or its match in the right eye) are removed and "
     "refilled from the tissue around. The margin follows the highlight's outline. An addition to the paper."},
    {"specularMaxRadiusPx", "Highlight max. radius", Matching, &StereoParameters::specularMaxRadiusPx, 1, 100, 1,
     " px",
     "A saturated area reaching this far on both sides of a pixel (along a row or column) is bright tissue, not a "
     "highlight. Surroundings are sampled "
     "just beyond the run and its matching windows."},
    {"znccWindowPx", "ZNCC window", Zncc, &StereoParameters::znccWindowPx, 3, 21, 2, " px",
     "Side of the square ZNCC matching window, odd. Paper II.A: 11x11, using every other pixel (a chessboard)."},
    {"outlierIterations", "Iterations", Outliers, &StereoParameters::outlierIterations, 0, 10, 1, "",
     "Rounds of outlier removal alternating with hole filling. Paper II.B: 3."},
    {"outlierRadiusStartPx", "Detection radius r", Outliers, &StereoParameters::outlierRadiusStartPx, 1, 200, 1,
     " px",
     "Initial detection radius r: a pixel is an outlier when none of its 8 radial directions changes smoothly "
     "within r. Paper II.B: 10 px."},
    {"outlierRadiusStepPx", "Radius step dr", Outliers, &StereoParameters::outlierRadiusStepPx, 0, 200, 1, " px",
     "Growth of r per round, so that removed disparities can be filled and later rounds keep inliers. "
     "Paper II.B: 10 px."},
    {"holeRadialRadiusPx", "Radial filling radius", Outliers, &StereoParameters::holeRadialRadiusPx, 0, 500, 1,
     " px", "Hole filling, first method: search distance along the pixel's 8 radial directions. Paper II.B: 50 px."},
    {"holeRadialMinLines", "Radial filling lines", Outliers, &StereoParameters::holeRadialMinLines, 1, 4, 1, "",
     "Hole filling, first method: opposite direction pairs that must both reach a valid disparity before "
     "interpolating (the paper's 'sufficient number of neighbouring points')."},
    {"holeDiscRadiusPx", "Disc filling radius", Outliers, &StereoParameters::holeDiscRadiusPx, 0, 200, 1, " px",
     "Hole filling, second method: radius of the neighbourhood searched around the pixel. Paper II.B: 20 px."},
    {"refineIterations", "Iterations", Refinement, &StereoParameters::refineIterations, 0, 100, 1, "",
     "Rounds of improved Laplacian smoothing, each followed by re-selection of the discrete disparity o_i. "
     "The paper does not state the number."},
    {"refineRadiusPx", "Smoothing radius", Refinement, &StereoParameters::refineRadiusPx, 1, 200, 1, " px",
     "Neighbourhood radius of the Laplacian smoothing of the discrete disparities o_j (design default 15 px)."},
    {"refineSearchPx", "Re-selection range", Refinement, &StereoParameters::refineSearchPx, 0, 50, 1, " px",
     "o_i is re-selected within [d_i - s, d_i + s] minimising 1/ZNCC + eta (o - d_i)^2. Paper II.C: 5 px."},
    {"censusWidthPx", "Census width", AdCensus, &StereoParameters::censusWidthPx, 1, 15, 2, " px",
     "Census window width, odd; width x height - 1 may not exceed 64 bits. Mei et al.: 9."},
    {"censusHeightPx", "Census height", AdCensus, &StereoParameters::censusHeightPx, 1, 15, 2, " px",
     "Census window height, odd. Mei et al.: 7."},
    {"armMaxPx", "Arm length L1", AdCensus, &StereoParameters::armMaxPx, 0, 127, 1, " px",
     "Longest reach of a pixel's cross arms, the support region of the cost aggregation. Mei et al.: 34."},
    {"armLongPx", "Long arm from L2", AdCensus, &StereoParameters::armLongPx, 0, 127, 1, " px",
     "Beyond this reach an arm must also stay within the stricter grey limit tau2. Mei et al.: 17; at most L1."},
    {"armLimitGrey", "Arm grey limit tau1", AdCensus, &StereoParameters::armLimitGrey, 1, 256, 1, "",
     "An arm stops at a grey step of this much from its anchor or from its predecessor. Mei et al.: 20."},
    {"armLongLimitGrey", "Long arm limit tau2", AdCensus, &StereoParameters::armLongLimitGrey, 1, 256, 1, "",
     "Beyond L2 an arm stops at this grey difference from its anchor. Mei et al.: 6."},
    {"aggregationIterations", "Aggregation rounds", AdCensus, &StereoParameters::aggregationIterations, 0, 8, 1, "",
     "Rounds of cross-based aggregation, alternating horizontal-first and vertical-first. 2 scored as well as "
     "Mei et al.'s 4."},
    {"pathEdgeGrey", "Path edge tau_SO", AdCensus, &StereoParameters::pathEdgeGrey, 1, 256, 1, "",
     "A grey step of this much along a scanline path is an edge: the path penalties shrink there. Mei et al.: 15."},
};

const RealField realFields[] = {
    {"specularMinGrey", "Highlight grey level", Matching, &StereoParameters::specularMinGrey, 1.0, 256.0, 1.0, 1, "",
     "Grey level from which a pixel may be a specular highlight, which sits on a different surface point in each "
     "eye and matches consistently but falsely. 256 switches highlight removal off. An addition to the paper."},
    {"specularMinContrastGrey", "Highlight contrast", Matching, &StereoParameters::specularMinContrastGrey, 0.0,
     255.0, 1.0, 1, "",
     "A highlight is brighter than the mean of its surroundings by at least this many grey levels; bright tissue "
     "is about as bright as its surroundings."},
    {"specularViewToleranceGrey", "Highlight view tolerance", Matching, &StereoParameters::specularViewToleranceGrey,
     0.0, 255.0, 1.0, 1, "",
     "A highlight is view-dependent: at its surroundings' disparity the other eye is darker by more than this. "
     "Bright diffuse tissue looks alike to both eyes and keeps its estimates."},
    {"minWindowStdDev", "Min window std. dev.", Zncc, &StereoParameters::minWindowStdDev, 0.0, 100.0, 0.5, 2, "",
     "Grey-level standard deviation below which a window counts as textureless and gets no ZNCC estimate "
     "(an engine safeguard; not in the paper)."},
    {"outlierSmoothnessPx", "Smoothness threshold", Outliers, &StereoParameters::outlierSmoothnessPx, 0.0, 100.0,
     0.5, 2, " px",
     "Largest disparity difference between neighbouring points along a smooth radial direction. "
     "Paper II.B: 2.5."},
    {"holeMaxEdgeDifferencePx", "Filling edge limit", Outliers, &StereoParameters::holeMaxEdgeDifferencePx, -1.0,
     1000.0, 0.5, 2, " px",
     "Radial filling ignores a line whose two ends differ by more than this plus 0.25 px per pixel of its length "
     "(it crosses a depth edge). -1 switches it off. An addition to the paper."},
    {"holeDiscMinValidFraction", "Disc filling valid share", Outliers, &StereoParameters::holeDiscMinValidFraction,
     0.0, 1.0, 0.05, 2, "",
     "Hole filling, second method: share of the neighbourhood that must have a valid disparity before "
     "interpolating (the paper's 'sufficient number')."},
    {"refineAlpha", "Alpha", Refinement, &StereoParameters::refineAlpha, 0.0, 1.0, 0.05, 3, "",
     "Vollmer's weight in b_i = d_i(k) - alpha o_i - (1 - alpha) d_i(k-1), which keeps the surface from "
     "shrinking. Paper II.C: 0.1, in [0, 1]."},
    {"refineEta", "Eta", Refinement, &StereoParameters::refineEta, 0.0, 100.0, 0.005, 4, "",
     "Weight of the smoothness cost (o - d_i)^2 against the ZNCC cost 1/ZNCC when re-selecting o_i. "
     "Paper II.C: 0.01 with an 11x11 window."},
    {"refineMaxDeviationPx", "Max. smoothing deviation", Refinement, &StereoParameters::refineMaxDeviationPx, -1.0,
     1000.0, 0.5, 2, " px",
     "Where the smoothed d_i and the re-selected o_i differ by more, the output is o_i (a depth edge, where a "
     "neighbourhood average is meaningless). -1 switches it off. An addition to the paper."},
    {"censusLambda", "Census lambda", AdCensus, &StereoParameters::censusLambda, 0.01, 1000.0, 1.0, 2, "",
     "Census cost 1 - exp(-Hamming distance / lambda). Mei et al.: 30."},
    {"absoluteDifferenceLambda", "Grey difference lambda", AdCensus, &StereoParameters::absoluteDifferenceLambda,
     0.01, 1000.0, 1.0, 2, "", "Grey cost 1 - exp(-|I_L - I_R| / lambda). Mei et al.: 10 (on colour)."},
    {"pathPenaltySmall", "Path penalty P1", AdCensus, &StereoParameters::pathPenaltySmall, 0.0, 100.0, 0.25, 2, "",
     "Scanline optimisation: penalty of a 1 px disparity change, in cost units (census + grey cost <= 2). "
     "Divided by 4 across an edge in one image, by 10 across both. Mei et al.: 1."},
    {"pathPenaltyLarge", "Path penalty P2", AdCensus, &StereoParameters::pathPenaltyLarge, 0.0, 100.0, 0.25, 2, "",
     "Penalty of a larger disparity change; at least P1. Mei et al.: 3."},
};

struct MethodChoice {
  StereoMethod method;
  const char* label;
};
const MethodChoice methodChoices[] = {{StereoMethod::Paper, "Paper: ZNCC, outliers, Laplacian (section II)"},
                                      {StereoMethod::AdCensus, "AD-Census (Mei et al. 2011)"}};

/// The method's item in the method combo box.
int methodIndex(StereoMethod method) {
  const auto* choice = std::find_if(std::begin(methodChoices), std::end(methodChoices),
                                    [method](const MethodChoice& c) { return c.method == method; });
  return static_cast<int>(choice - std::begin(methodChoices));
}

bool sameParameters(const StereoParameters& a, const StereoParameters& b) {
  if (a.method != b.method) return false;
  for (const IntField& field : intFields) {
    if (a.*field.member != b.*field.member) return false;
  }
  for (const RealField& field : realFields) {
    if (a.*field.member != b.*field.member) return false;
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

  qTissueMosaicStereoParametersWidget* const q_ptr;
  StereoParameters ownParameters;
  vtkSmartPointer<vtkTissueMosaicStereoLogic> logic;
  std::vector<QSpinBox*> intSpinBoxes;        ///< parallel to intFields
  std::vector<QDoubleSpinBox*> realSpinBoxes; ///< parallel to realFields
  std::map<QString, StereoParameters> presets;
  QComboBox* methodComboBox = nullptr;  ///< items parallel to methodChoices
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

  const char* const groupTitles[GroupCount] = {"Matching", "ZNCC matching (paper II.A)",
                                               "Outlier removal and hole filling (II.B)",
                                               "Improved Laplacian refinement (II.C)",
                                               "AD-Census (optional second method)"};
  QFormLayout* forms[GroupCount];
  for (int group = 0; group < GroupCount; ++group) {
    groupBoxes[group] = new QGroupBox(QObject::tr(groupTitles[group]), q);
    forms[group] = new QFormLayout(groupBoxes[group]);
    layout->addWidget(groupBoxes[group]);
  }
  methodComboBox = new QComboBox(q);
  methodComboBox->setObjectName("methodComboBox");
  for (const MethodChoice& choice : methodChoices) methodComboBox->addItem(QObject::tr(choice.label));
  methodComboBox->setToolTip(
      QObject::tr("The paper's method suits smooth, steep tissue; AD-Census suits scenes with sharp depth edges "
                  "(it meets the Middlebury bar the paper's local method does not) and is far slower on the CPU. "
                  "docs/STEREO.md compares them."));
  forms[Matching]->addRow(QObject::tr("Method"), methodComboBox);
  QObject::connect(methodComboBox, QOverload<int>::of(&QComboBox::currentIndexChanged), q,
                   &qTissueMosaicStereoParametersWidget::updateParametersFromGUI);
  for (const IntField& field : intFields) {
    auto* spinBox = new QSpinBox(q);
    spinBox->setObjectName(QString(field.key) + "SpinBox");
    spinBox->setRange(field.minimum, field.maximum);
    spinBox->setSingleStep(field.step);
    spinBox->setSuffix(field.suffix);
    spinBox->setToolTip(QObject::tr(field.toolTip));
    forms[field.group]->addRow(QObject::tr(field.label), spinBox);
    QObject::connect(spinBox, QOverload<int>::of(&QSpinBox::valueChanged), q,
                     &qTissueMosaicStereoParametersWidget::updateParametersFromGUI);
    intSpinBoxes.push_back(spinBox);
  }
  for (const RealField& field : realFields) {
    auto* spinBox = new QDoubleSpinBox(q);
    spinBox->setObjectName(QString(field.key) + "SpinBox");
    spinBox->setDecimals(field.decimals);
    spinBox->setRange(field.minimum, field.maximum);
    spinBox->setSingleStep(field.step);
    spinBox->setSuffix(field.suffix);
    spinBox->setToolTip(QObject::tr(field.toolTip));
    forms[field.group]->addRow(QObject::tr(field.label), spinBox);
    QObject::connect(spinBox, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q,
                     &qTissueMosaicStereoParametersWidget::updateParametersFromGUI);
    realSpinBoxes.push_back(spinBox);
  }

  errorLabel = widgets::addErrorLabel(q, layout, "");
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
  d->enableMethodGroups(parameters.method);
  for (std::size_t i = 0; i < d->intSpinBoxes.size(); ++i) {
    const QSignalBlocker blocker(d->intSpinBoxes[i]);
    d->intSpinBoxes[i]->setValue(parameters.*intFields[i].member);
  }
  for (std::size_t i = 0; i < d->realSpinBoxes.size(); ++i) {
    const QSignalBlocker blocker(d->realSpinBoxes[i]);
    d->realSpinBoxes[i]->setValue(parameters.*realFields[i].member);
  }
  widgets::showError(d->errorLabel, QString());
  d->selectMatchingPreset();
}

bool qTissueMosaicStereoParametersWidget::updateParametersFromGUI() {
  Q_D(qTissueMosaicStereoParametersWidget);
  StereoParameters parameters = d->current();
  parameters.method = methodChoices[d->methodComboBox->currentIndex()].method;
  for (std::size_t i = 0; i < d->intSpinBoxes.size(); ++i) {
    parameters.*intFields[i].member = d->intSpinBoxes[i]->value();
  }
  for (std::size_t i = 0; i < d->realSpinBoxes.size(); ++i) {
    parameters.*realFields[i].member = static_cast<float>(d->realSpinBoxes[i]->value());
  }
  if (!d->store(parameters)) return false;
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
