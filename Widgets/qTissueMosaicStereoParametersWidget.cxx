#include "qTissueMosaicStereoParametersWidget.h"

#include "qTissueMosaicParameterFields.h"
#include "qTissueMosaicPresetControls.h"
#include "qTissueMosaicWheelGuard.h"
#include "vtkTissueMosaicStereoLogic.h"

#include "Stereo/DisparityRange.h"

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

/// One spin box per field (qTissueMosaicParameterFields.h). Ranges are those StereoParameters::validate accepts, so
/// the spin boxes never clamp silently; combinations (min <= max, odd window) are checked by validate and refused
/// with its message, shown at the fields.
const std::vector<Field>& fields() {
  static const std::vector<Field> table = {
    {"minDisparityPx", "Min disparity", Range, TM_PARAMETER_FIELD(StereoParameters, minDisparityPx), -1000, 1000, 1, 0, " px",
     "Smallest candidate disparity (a left pixel x matches right pixel x - d) of a fixed range; editing it fixes "
     "the range. Paper IV: candidates from -20 to 80 px. Must not exceed the max disparity; at most 1024 "
     "candidates."},
    {"maxDisparityPx", "Max disparity", Range, TM_PARAMETER_FIELD(StereoParameters, maxDisparityPx), -1000, 1000, 1, 0, " px",
     "Largest candidate disparity of a fixed range, inclusive; editing it fixes the range. Paper IV: 80 px (range "
     "-20..80). The matching cost grows with the number of candidates."},
    {"workingDistanceNearMm", "Working distance from", Range, TM_PARAMETER_FIELD(StereoParameters, workingDistanceNearMm), 1.0,
     10000.0, 5.0, 1, " mm",
     "The nearest tissue, in mm from the scope (along its axis); editing it sets the range from the working "
     "distance, through the calibration: d = f B / Z - doffs."},
    {"workingDistanceFarMm", "Working distance to", Range, TM_PARAMETER_FIELD(StereoParameters, workingDistanceFarMm), 1.0,
     10000.0, 5.0, 1, " mm",
     "The farthest tissue, in mm from the scope; editing it sets the range from the working distance."},
    {"leftRightMaxDifferencePx", "Left-right check", Matching, TM_PARAMETER_FIELD(StereoParameters, leftRightMaxDifferencePx), -1, 1000, 1, 0, " px",
     "Winners whose right-view winner disagrees by more than this are dropped (occlusions, fattened depth edges). "
     "-1 switches the check off. An addition to the paper."},
    {"rangeEndMarginPx", "Range-end margin", Matching, TM_PARAMETER_FIELD(StereoParameters, rangeEndMarginPx), -1, 100, 1, 0, " px",
     "Winners this close to either end of the disparity range are dropped: their match most likely lies beyond it "
     "(an instrument nearer than the tissue the range follows). 0 drops the end candidates only; -1 switches it off. "
     "An addition to the paper."},
    {"specularMarginPx", "Highlight margin", Matching, TM_PARAMETER_FIELD(StereoParameters, specularMarginPx), 0, 20, 1, 0, " px",
     "Estimates within this distance of a highlight (the left pixel, or its match in the right eye) that disagree "
     "with the tissue around it are removed and refilled from that tissue. The margin follows the highlight's "
     "outline. For 960 px wide images: wider ones scale it with their width. An addition to the paper."},
    {"specularMaxRadiusPx", "Highlight max. radius", Matching, TM_PARAMETER_FIELD(StereoParameters, specularMaxRadiusPx), 1, 100, 1, 0,
     " px",
     "A saturated area reaching this far on both sides of a pixel (along a row or column) is bright tissue, not a "
     "highlight. Surroundings are sampled just beyond the bright spot and its matching windows. For 960 px wide "
     "images: wider ones scale it with their width."},
    {"trackingHighlightMarginPx", "Tracking highlight margin", Matching,
     TM_PARAMETER_FIELD(StereoParameters, trackingHighlightMarginPx), 0, 50, 1, 0, " px",
     "Tracking and fusion leave out the pixels within this distance (a square) of a highlight in the left image. "
     "The stereo output keeps the refilled tissue depth there, but a highlight slides over the tissue as the camera "
     "moves, so features on it would mislead tracking. For 960 px wide images: wider ones scale it with their width. "
     "An addition to the paper."},
    {"znccWindowPx", "ZNCC window", Zncc, TM_PARAMETER_FIELD(StereoParameters, znccWindowPx), 3, 21, 2, 0, " px",
     "Side of the square ZNCC matching window, odd. Paper II.A: 11x11, using every other pixel (a chessboard)."},
    {"outlierIterations", "Iterations", Outliers, TM_PARAMETER_FIELD(StereoParameters, outlierIterations), 0, 10, 1, 0, "",
     "Rounds of outlier removal alternating with hole filling. Paper II.B: 3."},
    {"outlierRadiusStartPx", "Detection radius r", Outliers, TM_PARAMETER_FIELD(StereoParameters, outlierRadiusStartPx), 1, 200, 1, 0, " px",
     "Initial detection radius r: a pixel is an outlier when none of its 8 radial directions changes smoothly "
     "within r. Paper II.B: 10 px."},
    {"outlierRadiusStepPx", "Radius step dr", Outliers, TM_PARAMETER_FIELD(StereoParameters, outlierRadiusStepPx), 0, 200, 1, 0, " px",
     "Growth of r per round, so that removed disparities can be filled and later rounds keep inliers. "
     "Paper II.B: 10 px."},
    {"holeRadialRadiusPx", "Radial filling radius", Outliers, TM_PARAMETER_FIELD(StereoParameters, holeRadialRadiusPx), 0, 500, 1, 0, " px", "Hole filling, first method: search distance along the pixel's 8 radial directions. Paper II.B: 50 px."},
    {"holeRadialMinLines", "Radial filling lines", Outliers, TM_PARAMETER_FIELD(StereoParameters, holeRadialMinLines), 1, 4, 1, 0, "",
     "Hole filling, first method: opposite direction pairs that must both reach a valid disparity before "
     "interpolating (the paper's 'sufficient number of neighbouring points')."},
    {"holeDiscRadiusPx", "Disc filling radius", Outliers, TM_PARAMETER_FIELD(StereoParameters, holeDiscRadiusPx), 0, 200, 1, 0, " px",
     "Hole filling, second method: radius of the neighbourhood searched around the pixel. Paper II.B: 20 px."},
    {"refineIterations", "Iterations", Refinement, TM_PARAMETER_FIELD(StereoParameters, refineIterations), 0, 100, 1, 0, "",
     "Rounds of improved Laplacian smoothing, each followed by re-selection of the discrete disparity o_i. "
     "The paper does not state the number."},
    {"refineRadiusPx", "Smoothing radius", Refinement, TM_PARAMETER_FIELD(StereoParameters, refineRadiusPx), 1, 200, 1, 0, " px",
     "Neighbourhood radius of the Laplacian smoothing of the discrete disparities o_j (design default 15 px)."},
    {"refineSearchPx", "Re-selection range", Refinement, TM_PARAMETER_FIELD(StereoParameters, refineSearchPx), 0, 50, 1, 0, " px",
     "o_i is re-selected within [d_i - s, d_i + s] minimising 1/ZNCC + eta (o - d_i)^2. Paper II.C: 5 px."},
    {"censusWidthPx", "Census width", AdCensus, TM_PARAMETER_FIELD(StereoParameters, censusWidthPx), 1, 15, 2, 0, " px",
     "Census window width, odd; width x height - 1 may not exceed 64 bits. Mei et al.: 9."},
    {"censusHeightPx", "Census height", AdCensus, TM_PARAMETER_FIELD(StereoParameters, censusHeightPx), 1, 15, 2, 0, " px",
     "Census window height, odd. Mei et al.: 7."},
    {"armMaxPx", "Arm length L1", AdCensus, TM_PARAMETER_FIELD(StereoParameters, armMaxPx), 0, 127, 1, 0, " px",
     "Longest reach of a pixel's cross arms, the support region of the cost aggregation. Mei et al.: 34."},
    {"armLongPx", "Long arm from L2", AdCensus, TM_PARAMETER_FIELD(StereoParameters, armLongPx), 0, 127, 1, 0, " px",
     "Beyond this reach an arm must also stay within the stricter grey limit tau2. Mei et al.: 17; at most L1."},
    {"armLimitGrey", "Arm grey limit tau1", AdCensus, TM_PARAMETER_FIELD(StereoParameters, armLimitGrey), 1, 256, 1, 0, "",
     "An arm stops at a grey step of this much from its anchor or from its predecessor. Mei et al.: 20."},
    {"armLongLimitGrey", "Long arm limit tau2", AdCensus, TM_PARAMETER_FIELD(StereoParameters, armLongLimitGrey), 1, 256, 1, 0, "",
     "Beyond L2 an arm stops at this grey difference from its anchor. Mei et al.: 6."},
    {"aggregationIterations", "Aggregation rounds", AdCensus, TM_PARAMETER_FIELD(StereoParameters, aggregationIterations), 0, 8, 1, 0, "",
     "Rounds of cross-based aggregation, alternating horizontal-first and vertical-first. 2 scored as well as "
     "Mei et al.'s 4."},
    {"pathEdgeGrey", "Path edge tau_SO", AdCensus, TM_PARAMETER_FIELD(StereoParameters, pathEdgeGrey), 1, 256, 1, 0, "",
     "A grey step of this much along a scanline path is an edge: the path penalties shrink there. Mei et al.: 15."},
    {"specularMinGrey", "Highlight grey level", Matching, TM_PARAMETER_FIELD(StereoParameters, specularMinGrey), 1.0, 256.0, 1.0, 1, "",
     "Grey level from which a pixel may be a specular highlight, which sits on a different surface point in each "
     "eye and matches consistently but falsely. 256 switches highlight removal off. An addition to the paper."},
    {"specularMinContrastGrey", "Highlight contrast", Matching, TM_PARAMETER_FIELD(StereoParameters, specularMinContrastGrey), 0.0,
     255.0, 1.0, 1, "",
     "A highlight is brighter than the mean of its surroundings by at least this many grey levels (by half the "
     "headroom to 255 on bright tissue); bright tissue is about as bright as its surroundings."},
    {"specularViewToleranceGrey", "Highlight view tolerance", Matching, TM_PARAMETER_FIELD(StereoParameters, specularViewToleranceGrey),
     0.0, 255.0, 1.0, 1, "",
     "A highlight is view-dependent: at its surroundings' disparity the other eye is darker by more than this (or "
     "the highlight matched elsewhere). Bright diffuse tissue looks alike to both eyes and keeps its estimates."},
    {"minWindowStdDev", "Min window std. dev.", Zncc, TM_PARAMETER_FIELD(StereoParameters, minWindowStdDev), 0.0, 100.0, 0.5, 2, "",
     "Grey-level standard deviation below which a window counts as textureless and gets no ZNCC estimate "
     "(an engine safeguard; not in the paper)."},
    {"outlierSmoothnessPx", "Smoothness threshold", Outliers, TM_PARAMETER_FIELD(StereoParameters, outlierSmoothnessPx), 0.0, 100.0,
     0.5, 2, " px",
     "Largest disparity difference between neighbouring points along a smooth radial direction. "
     "Paper II.B: 2.5."},
    {"holeMaxEdgeDifferencePx", "Filling edge limit", Outliers, TM_PARAMETER_FIELD(StereoParameters, holeMaxEdgeDifferencePx), -1.0,
     1000.0, 0.5, 2, " px",
     "Radial filling ignores a line whose two ends differ by more than this plus 0.25 px per pixel of its length "
     "(it crosses a depth edge). -1 switches it off. An addition to the paper."},
    {"holeDiscMinValidFraction", "Disc filling valid share", Outliers, TM_PARAMETER_FIELD(StereoParameters, holeDiscMinValidFraction), 0.0, 1.0, 0.05, 2, "",
     "Hole filling, second method: share of the neighbourhood that must have a valid disparity before "
     "interpolating (the paper's 'sufficient number')."},
    {"refineAlpha", "Alpha", Refinement, TM_PARAMETER_FIELD(StereoParameters, refineAlpha), 0.0, 1.0, 0.05, 3, "",
     "Vollmer's weight in b_i = d_i(k) - alpha o_i - (1 - alpha) d_i(k-1), which keeps the surface from "
     "shrinking. Paper II.C: 0.1, in [0, 1]."},
    {"refineEta", "Eta", Refinement, TM_PARAMETER_FIELD(StereoParameters, refineEta), 0.0, 100.0, 0.005, 4, "",
     "Weight of the smoothness cost (o - d_i)^2 against the ZNCC cost 1/ZNCC when re-selecting o_i. "
     "Paper II.C: 0.01 with an 11x11 window."},
    {"refineMaxDeviationPx", "Max. smoothing deviation", Refinement, TM_PARAMETER_FIELD(StereoParameters, refineMaxDeviationPx), -1.0,
     1000.0, 0.5, 2, " px",
     "Where the smoothed d_i and the re-selected o_i differ by more, the output is o_i (a depth edge, where a "
     "neighbourhood average is meaningless). -1 switches it off. An addition to the paper."},
    {"censusLambda", "Census lambda", AdCensus, TM_PARAMETER_FIELD(StereoParameters, censusLambda), 0.01, 1000.0, 1.0, 2, "",
     "Census cost 1 - exp(-Hamming distance / lambda). Mei et al.: 30."},
    {"absoluteDifferenceLambda", "Grey difference lambda", AdCensus, TM_PARAMETER_FIELD(StereoParameters, absoluteDifferenceLambda), 0.01, 1000.0, 1.0, 2, "", "Grey cost 1 - exp(-|I_L - I_R| / lambda). Mei et al.: 10 (on colour)."},
    {"pathPenaltySmall", "Path penalty P1", AdCensus, TM_PARAMETER_FIELD(StereoParameters, pathPenaltySmall), 0.0, 100.0, 0.25, 2, "",
     "Scanline optimisation: penalty of a 1 px disparity change, in cost units (census + grey cost <= 2). "
     "Divided by 4 across an edge in one image, by 10 across both. Mei et al.: 1."},
    {"pathPenaltyLarge", "Path penalty P2", AdCensus, TM_PARAMETER_FIELD(StereoParameters, pathPenaltyLarge), 0.0, 100.0, 0.25, 2, "",
     "Penalty of a larger disparity change; at least P1. Mei et al.: 3."},
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
