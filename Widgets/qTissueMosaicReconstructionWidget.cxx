#include "qTissueMosaicReconstructionWidget.h"

#include "qTissueMosaicMessageLine.h"
#include "qTissueMosaicReconstructionParametersWidget.h"
#include "qTissueMosaicStereoParametersWidget.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include <vtkNew.h>
#include <vtkPolyData.h>

#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLineEdit>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QGridLayout>
#include <QGroupBox>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>

#include <algorithm>
#include <map>

namespace {

/// The paper's wording (Table "Average Runtime of 3D Reconstruction") for TimingTable's stage keys.
QString stageLabel(const std::string& key) {
  static const std::map<std::string, const char*> labels = {
      {"video_reading", "video reading"},   {"stereo", "stereo matching"},
      {"orb_voting", "ORB + voting"},       {"dynamic_r1ppnp", "DynamicR1PPnP"},
      {"model_agreement", "model agreement"}, {"refinement", "refinement"},
      {"tsdf", "TSDF"},
      {"total", "total"}};
  const auto label = labels.find(key);
  return label != labels.end() ? QObject::tr(label->second) : QString::fromStdString(key);
}

QPushButton* button(const QString& text, const char* name, const QString& toolTip, QWidget* parent) {
  auto* pushButton = new QPushButton(text, parent);
  pushButton->setObjectName(name);
  pushButton->setToolTip(toolTip);
  return pushButton;
}

}  // namespace

class qTissueMosaicReconstructionWidgetPrivate {
  Q_DECLARE_PUBLIC(qTissueMosaicReconstructionWidget);

public:
  explicit qTissueMosaicReconstructionWidgetPrivate(qTissueMosaicReconstructionWidget& object) : q_ptr(&object) {}
  void setupUi();
  void updateControls();
  void updateTimingTable();
  void show(const QString& text, bool error, qTissueMosaicMessageLine* line);
  /// Runs a logic call that can fail; shows its error text in `line`, or `success` when it worked.
  bool report(bool ok, const QString& success, qTissueMosaicMessageLine* line);
  qTissueMosaicMessageLine* line(qTissueMosaicReconstructionWidget::MessagePlace place) const;

  qTissueMosaicReconstructionWidget* const q_ptr;
  vtkNew<vtkTissueMosaicReconstructionLogic> logic;
  qTissueMosaicReconstructionParametersWidget* parameters = nullptr;
  QTableWidget* timing = nullptr;
  QLabel* inputLabel = nullptr;
  QLabel* stateLabel = nullptr;
  QLabel* agreementLabel = nullptr;  ///< the quality signal: green / amber / red with the numbers
  qTissueMosaicMessageLine* startProblemLabel = nullptr;  ///< why Start is disabled
  qTissueMosaicMessageLine* inputMessage = nullptr;
  qTissueMosaicMessageLine* scanMessage = nullptr;
  qTissueMosaicMessageLine* exportMessage = nullptr;
  QLabel* sceneMotionLabel = nullptr;  ///< what moved: the camera, the tissue, both, nothing
  QLabel* disparityRangeLabel = nullptr;
  QGroupBox* parametersBox = nullptr;
  QCheckBox* rectifiedCheckBox = nullptr;
  QComboBox* layoutComboBox = nullptr;
  QPushButton *startButton = nullptr, *pauseButton = nullptr, *stopButton = nullptr, *resetButton = nullptr;
  QPushButton *exportModelButton = nullptr, *exportTrajectoryButton = nullptr;
  QTimer pollTimer;
  int lastState = -1;
  int pollsSinceTiming = 0;
  QString lastMessage;
  QString startProblem;
  vtkMTimeType exportedModelTime = 0;  ///< the model's modification time at its last export
};

void qTissueMosaicReconstructionWidgetPrivate::setupUi() {
  Q_Q(qTissueMosaicReconstructionWidget);
  auto* layout = new QVBoxLayout(q);

  auto* inputBox = new QGroupBox(QObject::tr("Input"), q);
  auto* inputLayout = new QGridLayout(inputBox);
  auto* demoButton = button(QObject::tr("Open demo"), "openDemoButton",
                            QObject::tr("A synthetic stereo-endoscope scan of liver-like tissue with its calibration "
                                        "(generated in a temporary folder): press Start to reconstruct it."),
                            q);
  demoButton->setStyleSheet("QPushButton { font-weight: bold; }");
  auto* foldersButton = button(QObject::tr("Frame folders..."), "openFoldersButton",
                               QObject::tr("Two folders of frames (left, right), paired in file-name order. Choosing a "
                                           "folder that holds left/ and right/ (and rig.yml) opens them all."),
                               q);
  auto* videoButton = button(QObject::tr("Two videos..."), "openVideoPairButton",
                             QObject::tr("A left and a right video file, read in lock step."), q);
  auto* sideBySideButton = button(QObject::tr("3D video..."), "openSideBySideButton",
                                  QObject::tr("One video with both eyes in each frame, packed as the layout beside "
                                              "says (sbs: the left eye in the left half)."),
                                  q);
  layoutComboBox = new QComboBox(q);
  layoutComboBox->setObjectName("videoLayoutComboBox");
  layoutComboBox->setToolTip(QObject::tr("How the 3D video packs the eyes: side by side, squeezed side by side, top "
                                         "bottom, squeezed top bottom, row-interlaced (even rows left)"));
  for (const char* name : {"sbs", "sbs-half", "tb", "tb-half", "rows"}) layoutComboBox->addItem(name);
  auto* liveButton = button(QObject::tr("Live..."), "openLiveButton",
                            QObject::tr("A capture device (/dev/video0) or a GStreamer pipeline ending in appsink, "
                                        "packed as the layout says; read in real time, the newest frame first."),
                            q);
  auto* calibrationButton = button(QObject::tr("Calibration..."), "loadCalibrationButton",
                                   QObject::tr("Stereo calibration of the raw rig, recognised by its keys: OpenCV, "
                                               "stereo_calib / SCARED (select intrinsics + extrinsics together), "
                                               "ROS camera_info (select both eyes), Kalibr or MATLAB. Frames are "
                                               "rectified with it."),
                                   q);
  rectifiedCheckBox = new QCheckBox(QObject::tr("Frames are already rectified"), q);
  rectifiedCheckBox->setObjectName("rectifiedCheckBox");
  rectifiedCheckBox->setToolTip(QObject::tr("Tick when the frames were rectified with this calibration already (as "
                                            "`tissuemosaic synth scan` writes them)."));
  inputLabel = new QLabel(q);
  inputLabel->setObjectName("inputLabel");
  inputLabel->setWordWrap(true);
  inputLayout->addWidget(demoButton, 0, 0);
  inputLayout->addWidget(foldersButton, 0, 1);
  inputLayout->addWidget(videoButton, 1, 0);
  inputLayout->addWidget(liveButton, 1, 1);
  // The 3D video button beside the layout it reads (also the live source's layout): a row of its own, so that
  // neither is squeezed at 1280x800.
  auto* packedRow = new QHBoxLayout;
  packedRow->addWidget(sideBySideButton, 1);
  packedRow->addWidget(layoutComboBox, 1);
  inputLayout->addLayout(packedRow, 2, 0, 1, 2);
  inputLayout->addWidget(calibrationButton, 3, 0);
  inputLayout->addWidget(rectifiedCheckBox, 3, 1);
  inputLayout->addWidget(inputLabel, 4, 0, 1, 2);
  inputMessage = new qTissueMosaicMessageLine(q);
  inputMessage->setObjectName("inputMessage");
  inputLayout->addWidget(inputMessage, 5, 0, 1, 2);
  layout->addWidget(inputBox);

  auto* scanBox = new QGroupBox(QObject::tr("Scan"), q);
  auto* scanLayout = new QGridLayout(scanBox);
  startButton = button(QObject::tr("Start"), "startButton", QObject::tr("Start the reconstruction, or resume it"), q);
  pauseButton = button(QObject::tr("Pause"), "pauseButton", QObject::tr("Pause after the current frame"), q);
  stopButton = button(QObject::tr("Stop"), "stopButton",
                      QObject::tr("End the scan after the current frame; the model stays for export"), q);
  resetButton = button(QObject::tr("Reset"), "resetButton",
                       QObject::tr("Drop the model and the poses; the next start begins at the first frame"), q);
  startButton->setStyleSheet("QPushButton:enabled { background-color: #2e7d32; color: white; font-weight: bold; }");
  scanLayout->addWidget(startButton, 0, 0);
  scanLayout->addWidget(pauseButton, 0, 1);
  scanLayout->addWidget(stopButton, 0, 2);
  scanLayout->addWidget(resetButton, 0, 3);
  stateLabel = new QLabel(q);
  stateLabel->setObjectName("stateLabel");
  stateLabel->setWordWrap(true);
  scanLayout->addWidget(stateLabel, 1, 0, 1, 4);
  agreementLabel = new QLabel(q);
  agreementLabel->setObjectName("modelAgreementLabel");
  agreementLabel->setToolTip(QObject::tr(
      "How well the model, seen from the tracked pose, agrees with this frame's stereo depth: the share of depths "
      "within 1 mm of the model and the median difference. Green: trust the model here; amber: part of the view "
      "moved or is covered; red: do not trust it. Thresholds: the agreement parameters."));
  scanLayout->addWidget(agreementLabel, 2, 0, 1, 4);
  sceneMotionLabel = new QLabel(q);
  sceneMotionLabel->setObjectName("sceneMotionLabel");
  sceneMotionLabel->setWordWrap(true);
  sceneMotionLabel->setToolTip(QObject::tr(
      "What moved at the last frame: the camera (its pose), the tissue (features that moved with the scene, or depth "
      "the model contradicts at a pose that continues the scope's motion), both, or nothing"));
  scanLayout->addWidget(sceneMotionLabel, 3, 0, 1, 4);
  disparityRangeLabel = new QLabel(q);
  disparityRangeLabel->setObjectName("disparityRangeLabel");
  disparityRangeLabel->setWordWrap(true);
  disparityRangeLabel->setToolTip(QObject::tr("The stereo matcher's disparity range and how it was chosen (the "
                                              "parameters' Disparity range)"));
  scanLayout->addWidget(disparityRangeLabel, 4, 0, 1, 4);
  startProblemLabel = new qTissueMosaicMessageLine(q);
  startProblemLabel->setObjectName("startProblemLabel");
  scanLayout->addWidget(startProblemLabel, 5, 0, 1, 4);
  scanMessage = new qTissueMosaicMessageLine(q);
  scanMessage->setObjectName("scanMessage");
  scanLayout->addWidget(scanMessage, 6, 0, 1, 4);
  layout->addWidget(scanBox);

  auto* exportBox = new QGroupBox(QObject::tr("Export"), q);
  auto* exportLayout = new QGridLayout(exportBox);
  exportModelButton = button(QObject::tr("Model..."), "exportModelButton",
                             QObject::tr("The fused model as .ply (xyz, rgb, normals) or .vtp (for 3D Slicer); "
                                         "world frame = first left rectified camera, mm"),
                             q);
  exportTrajectoryButton = button(QObject::tr("Trajectory..."), "exportTrajectoryButton",
                                  QObject::tr("The camera path as TUM text (t tx ty tz qx qy qz qw, mm)"), q);
  auto* screenshotButton = button(QObject::tr("Screenshot..."), "screenshotButton",
                                  QObject::tr("A PNG picture of the whole window"), q);
  exportLayout->addWidget(exportModelButton, 0, 0);
  exportLayout->addWidget(exportTrajectoryButton, 0, 1);
  exportLayout->addWidget(screenshotButton, 0, 2);
  exportMessage = new qTissueMosaicMessageLine(q);
  exportMessage->setObjectName("exportMessage");
  exportLayout->addWidget(exportMessage, 1, 0, 1, 3);
  layout->addWidget(exportBox);

  auto* timingBox = new QGroupBox(QObject::tr("Runtime per frame (ms)"), q);
  auto* timingLayout = new QVBoxLayout(timingBox);
  timing = new QTableWidget(q);
  timing->setObjectName("timingTable");
  timing->setColumnCount(4);
  timing->setHorizontalHeaderLabels(
      {QObject::tr("last"), QObject::tr("key med."), QObject::tr("key mean"), QObject::tr("other med.")});
  timing->horizontalHeaderItem(0)->setToolTip(QObject::tr("The last frame"));
  timing->horizontalHeaderItem(1)->setToolTip(QObject::tr("Median over the key frames"));
  timing->horizontalHeaderItem(2)->setToolTip(QObject::tr("Mean over the key frames, as the paper's runtime table"));
  timing->horizontalHeaderItem(3)->setToolTip(QObject::tr("Median over the other frames (no refinement, no fusion)"));
  timing->setEditTriggers(QAbstractItemView::NoEditTriggers);
  timing->setSelectionMode(QAbstractItemView::NoSelection);
  timing->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
  timing->verticalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  timing->setVerticalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  timingLayout->addWidget(timing);
  layout->addWidget(timingBox);

  parametersBox = new QGroupBox(QObject::tr("Parameters"), q);
  auto* parametersLayout = new QVBoxLayout(parametersBox);
  parameters = new qTissueMosaicReconstructionParametersWidget(q);
  parameters->setObjectName("reconstructionParametersPanel");
  parameters->setReconstructionLogic(logic);
  QObject::connect(parameters, &qTissueMosaicReconstructionParametersWidget::parametersChanged, q,
                   [this] { updateControls(); });  // the disparity range line says what the parameters ask for
  parametersLayout->addWidget(parameters);
  layout->addWidget(parametersBox);
  layout->addStretch(1);

  QObject::connect(demoButton, &QPushButton::clicked, q, &qTissueMosaicReconstructionWidget::demoRequested);
  QObject::connect(screenshotButton, &QPushButton::clicked, q, &qTissueMosaicReconstructionWidget::screenshotRequested);
  QObject::connect(startButton, &QPushButton::clicked, q, &qTissueMosaicReconstructionWidget::start);
  QObject::connect(pauseButton, &QPushButton::clicked, q, &qTissueMosaicReconstructionWidget::pause);
  QObject::connect(stopButton, &QPushButton::clicked, q, &qTissueMosaicReconstructionWidget::stop);
  QObject::connect(resetButton, &QPushButton::clicked, q, &qTissueMosaicReconstructionWidget::reset);
  QObject::connect(rectifiedCheckBox, &QCheckBox::toggled, q, &qTissueMosaicReconstructionWidget::setInputRectified);
  QObject::connect(foldersButton, &QPushButton::clicked, q, [q] {
    const QString left = QFileDialog::getExistingDirectory(q, QObject::tr("Left frames (or a folder with left/ and right/)"));
    if (left.isEmpty()) return;
    const QDir chosen(left);
    if (chosen.exists("left") && chosen.exists("right")) {
      if (chosen.exists("rig.yml")) q->loadCalibration(chosen.filePath("rig.yml"));
      q->openFrameFolders(chosen.filePath("left"), chosen.filePath("right"));
      return;
    }
    const QString right = QFileDialog::getExistingDirectory(q, QObject::tr("Right frames"), left);
    if (!right.isEmpty()) q->openFrameFolders(left, right);
  });
  QObject::connect(videoButton, &QPushButton::clicked, q, [q] {
    const QString filter = QObject::tr("Videos (*.mp4 *.avi *.mkv *.mov *.mpg);;All files (*)");
    const QString left = QFileDialog::getOpenFileName(q, QObject::tr("Left video"), QString(), filter);
    if (left.isEmpty()) return;
    const QString right = QFileDialog::getOpenFileName(q, QObject::tr("Right video"), QFileInfo(left).path(), filter);
    if (!right.isEmpty()) q->openVideoPair(left, right);
  });
  QObject::connect(sideBySideButton, &QPushButton::clicked, q, [q] {
    const QString video = QFileDialog::getOpenFileName(q, QObject::tr("Side-by-side video"), QString(),
                                                       QObject::tr("Videos (*.mp4 *.avi *.mkv *.mov *.mpg);;All files (*)"));
    if (!video.isEmpty()) q->openStereoVideo(video, q->findChild<QComboBox*>("videoLayoutComboBox")->currentText());
  });
  QObject::connect(liveButton, &QPushButton::clicked, q, [q] {
    bool ok = false;
    const QString input = QInputDialog::getText(
        q, QObject::tr("Live video"), QObject::tr("Capture device or GStreamer pipeline ending in appsink:"),
        QLineEdit::Normal, "/dev/video0", &ok);
    if (ok && !input.isEmpty()) q->openStereoVideo(input, q->findChild<QComboBox*>("videoLayoutComboBox")->currentText());
  });
  QObject::connect(calibrationButton, &QPushButton::clicked, q, [q] {
    const QStringList paths = QFileDialog::getOpenFileNames(
        q, QObject::tr("Stereo calibration (one file, or two: intrinsics + extrinsics, or left + right eye)"), QString(),
        QObject::tr("Calibration (*.yml *.yaml *.xml *.json);;All files (*)"));
    if (!paths.isEmpty()) q->loadCalibrationFiles(paths);
  });
  QObject::connect(exportModelButton, &QPushButton::clicked, q, [q] {
    const QString path = QFileDialog::getSaveFileName(q, QObject::tr("Export model"), "model.ply",
                                                      QObject::tr("PLY (*.ply);;VTK XML PolyData for Slicer (*.vtp)"));
    if (!path.isEmpty()) q->exportModel(path);
  });
  QObject::connect(exportTrajectoryButton, &QPushButton::clicked, q, [q] {
    const QString path = QFileDialog::getSaveFileName(q, QObject::tr("Export trajectory"), "trajectory.txt",
                                                      QObject::tr("TUM trajectory (*.txt)"));
    if (!path.isEmpty()) q->exportTrajectory(path);
  });
  QObject::connect(&pollTimer, &QTimer::timeout, q, &qTissueMosaicReconstructionWidget::updateFromLogic);
  // A refused parameter disables Start until it is fixed.
  QObject::connect(parameters, &qTissueMosaicReconstructionParametersWidget::validityChanged, q,
                   [this] { updateControls(); });
}

qTissueMosaicMessageLine* qTissueMosaicReconstructionWidgetPrivate::line(
    qTissueMosaicReconstructionWidget::MessagePlace place) const {
  switch (place) {
    case qTissueMosaicReconstructionWidget::InputMessage: return inputMessage;
    case qTissueMosaicReconstructionWidget::ScanMessage: return scanMessage;
    default: return exportMessage;
  }
}

void qTissueMosaicReconstructionWidgetPrivate::show(const QString& text, bool error, qTissueMosaicMessageLine* where) {
  Q_Q(qTissueMosaicReconstructionWidget);
  lastMessage = text;
  // One message at a time: an older one elsewhere would read as if it were about the latest action.
  for (qTissueMosaicMessageLine* other : {inputMessage, scanMessage, exportMessage}) {
    if (other != where) other->clearMessage();
  }
  where->showMessage(text, error ? qTissueMosaicMessageLine::Error : qTissueMosaicMessageLine::Done);
  if (!text.isEmpty()) emit q->message(text, error);
}

bool qTissueMosaicReconstructionWidgetPrivate::report(bool ok, const QString& success, qTissueMosaicMessageLine* where) {
  if (ok) show(success, false, where);
  else show(qTissueMosaicMessageLine::sentence(QString::fromStdString(logic->GetLastErrorText())), true, where);
  updateControls();
  return ok;
}

void qTissueMosaicReconstructionWidgetPrivate::updateControls() {
  using Logic = vtkTissueMosaicReconstructionLogic;
  const int state = logic->GetScanState();
  // Start says why it cannot start, beside it, instead of failing when pressed.
  QString problem = QString::fromStdString(logic->GetStartProblem());
  if (problem.isEmpty() && state == Logic::StateIdle && parameters->hasRefusedValues()) {
    problem = QObject::tr("a parameter was not applied: %1").arg(parameters->errorText());
  }
  startProblem = problem.isEmpty() ? QString() : qTissueMosaicMessageLine::sentence(problem);
  const bool startable = state == Logic::StateIdle || state == Logic::StatePaused;
  startButton->setEnabled(problem.isEmpty() && startable);
  startButton->setToolTip(problem.isEmpty() ? QObject::tr("Start the reconstruction, or resume it")
                                            : QObject::tr("Cannot start: %1").arg(startProblem));
  if (startable && !problem.isEmpty()) startProblemLabel->showWarning(QObject::tr("Cannot start: %1").arg(startProblem));
  else startProblemLabel->clearMessage();
  startButton->setText(state == Logic::StatePaused ? QObject::tr("Resume") : QObject::tr("Start"));
  pauseButton->setEnabled(state == Logic::StateRunning);
  stopButton->setEnabled(state == Logic::StateRunning || state == Logic::StatePaused);
  resetButton->setEnabled(state != Logic::StateIdle);
  const bool hasModel = logic->GetModel()->GetNumberOfPoints() > 0;
  exportModelButton->setEnabled(hasModel);
  exportTrajectoryButton->setEnabled(logic->GetStatus().framesProcessed > 0);
  parameters->setEnabled(logic->CanChangeParameters());
  parametersBox->setTitle(logic->CanChangeParameters() ? QObject::tr("Parameters")
                                                       : QObject::tr("Parameters (fixed during the scan: Reset to edit)"));
  parameters->setToolTip(logic->CanChangeParameters() ? QString()
                                                      : QObject::tr("Parameters are fixed during a scan: reset first"));
  {
    const QSignalBlocker blocker(rectifiedCheckBox);
    rectifiedCheckBox->setChecked(logic->GetInputRectified());
  }

  QString input = logic->HasInput() ? QString::fromStdString(logic->GetInputDescription()) : QObject::tr("no input");
  if (logic->HasInput() && logic->GetInputFrameCount() > 0) {
    input += QObject::tr(" (%1 frames)").arg(logic->GetInputFrameCount());
  }
  // "calibrated" only when the calibration fits the frames (a previous input's calibration may not).
  const bool sizeMismatch = QString::fromStdString(logic->GetStartProblem()).startsWith("the calibration is for");
  input += !logic->HasCalibration() ? QObject::tr("; no calibration")
           : sizeMismatch           ? QObject::tr("; the calibration is for another frame size")
                                    : QObject::tr("; calibrated");
  inputLabel->setText(input);
  const auto& status = logic->GetStatus();
  stateLabel->setText(QString::fromStdString(logic->GetTrackingStateText()));
  const bool lost = status.framesProcessed > 0 && !status.tracked && status.state != Logic::StateIdle;
  stateLabel->setStyleSheet(lost ? "QLabel { color: #c62828; font-weight: bold; }" : QString());
  agreementLabel->setText(QString::fromStdString(logic->GetAgreementText()));
  // The traffic light: tissuemosaic::AgreementLevel (none, good, fair, poor).
  static const char* const colours[] = {"#9e9e9e", "#2e7d32", "#f9a825", "#c62828"};
  const int level = lost ? 0 : std::clamp(status.agreementLevel, 0, 3);
  agreementLabel->setStyleSheet(QString("QLabel { background-color: %1; color: white; padding: 2px 6px; }").arg(colours[level]));
  agreementLabel->setProperty("agreementLevel", level);
  const QString moved = QString::fromStdString(logic->GetSceneMotionText());
  sceneMotionLabel->setText(moved);
  sceneMotionLabel->setVisible(!moved.isEmpty());
  disparityRangeLabel->setText(
      QObject::tr("Disparities: %1").arg(QString::fromStdString(logic->GetDisparityRangeText())));
  // A pair out of rectification is matched after a correction the user should know of: the line stands out.
  disparityRangeLabel->setStyleSheet(status.rowOffsetPx != 0 ? "QLabel { color: #e65100; font-weight: bold; }" : QString());
  tissuemosaic::RectifiedGeometry geometry;
  const bool known = logic->GetRectifiedGeometry(geometry);
  parameters->stereoPanel()->setRigGeometry(known ? &geometry : nullptr);
}

void qTissueMosaicReconstructionWidgetPrivate::updateTimingTable() {
  const auto rows = logic->GetTimingTable();
  timing->setRowCount(static_cast<int>(rows.size()));
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    auto* header = timing->verticalHeaderItem(r);
    if (!header) timing->setVerticalHeaderItem(r, header = new QTableWidgetItem);
    header->setText(stageLabel(rows[r].stage));
    const double values[4] = {rows[r].lastMs, rows[r].keyFrameMedianMs, rows[r].keyFrameMeanMs,
                              rows[r].otherFrameMedianMs};
    for (int c = 0; c < 4; ++c) {
      auto* item = timing->item(r, c);
      if (!item) {
        timing->setItem(r, c, item = new QTableWidgetItem);
        item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
      }
      item->setText(QString::number(values[c], 'f', 1));
    }
  }
  int height = timing->horizontalHeader()->height() + 4;
  for (int r = 0; r < timing->rowCount(); ++r) height += timing->rowHeight(r);
  timing->setFixedHeight(height);
  // Whole, never cut at the right: the stage names and the widest column title in every (equal, stretched)
  // column; the numbers are narrower.
  int widestTitle = 0;
  for (int c = 0; c < timing->columnCount(); ++c) {
    widestTitle = std::max(widestTitle, timing->horizontalHeader()->sectionSizeHint(c));
  }
  timing->horizontalHeader()->setMinimumSectionSize(widestTitle);
  timing->setMinimumWidth(timing->verticalHeader()->sizeHint().width() + 2 * timing->frameWidth() +
                          timing->columnCount() * widestTitle);
}

qTissueMosaicReconstructionWidget::qTissueMosaicReconstructionWidget(QWidget* parent)
    : QWidget(parent), d_ptr(new qTissueMosaicReconstructionWidgetPrivate(*this)) {
  Q_D(qTissueMosaicReconstructionWidget);
  d->setupUi();
  d->updateTimingTable();
  d->updateControls();
  d->pollTimer.start(33);
}

qTissueMosaicReconstructionWidget::~qTissueMosaicReconstructionWidget() = default;

vtkTissueMosaicReconstructionLogic* qTissueMosaicReconstructionWidget::reconstructionLogic() const {
  Q_D(const qTissueMosaicReconstructionWidget);
  return d->logic;
}

qTissueMosaicReconstructionParametersWidget* qTissueMosaicReconstructionWidget::parametersPanel() const {
  Q_D(const qTissueMosaicReconstructionWidget);
  return d->parameters;
}

QTableWidget* qTissueMosaicReconstructionWidget::timingTable() const {
  Q_D(const qTissueMosaicReconstructionWidget);
  return d->timing;
}

QString qTissueMosaicReconstructionWidget::lastMessage() const {
  Q_D(const qTissueMosaicReconstructionWidget);
  return d->lastMessage;
}

void qTissueMosaicReconstructionWidget::setPollingIntervalMs(int intervalMs) {
  Q_D(qTissueMosaicReconstructionWidget);
  d->pollTimer.start(intervalMs);
}

bool qTissueMosaicReconstructionWidget::openFrameFolders(const QString& leftFolder, const QString& rightFolder,
                                                         double fps) {
  Q_D(qTissueMosaicReconstructionWidget);
  const bool ok = d->logic->OpenFrameFolders(leftFolder.toStdString(), rightFolder.toStdString(), fps);
  emit outputsUpdated();
  return d->report(ok, tr("Opened %1").arg(QString::fromStdString(d->logic->GetInputDescription())), d->inputMessage);
}

bool qTissueMosaicReconstructionWidget::openVideoPair(const QString& leftVideo, const QString& rightVideo) {
  Q_D(qTissueMosaicReconstructionWidget);
  const bool ok = d->logic->OpenVideoPair(leftVideo.toStdString(), rightVideo.toStdString());
  emit outputsUpdated();
  return d->report(ok, tr("Opened %1").arg(QString::fromStdString(d->logic->GetInputDescription())), d->inputMessage);
}

bool qTissueMosaicReconstructionWidget::openSideBySideVideo(const QString& video) {
  return this->openStereoVideo(video, "sbs");
}

bool qTissueMosaicReconstructionWidget::openStereoVideo(const QString& video, const QString& layout) {
  Q_D(qTissueMosaicReconstructionWidget);
  tissuemosaic::VideoLayout parsed;
  try {
    parsed = tissuemosaic::parseVideoLayout(layout.toStdString());
  } catch (const std::exception& e) {
    d->show(QString::fromStdString(e.what()), true, d->inputMessage);
    return false;
  }
  const bool ok = d->logic->OpenStereoVideo(video.toStdString(), parsed);
  emit outputsUpdated();
  return d->report(ok, tr("Opened %1").arg(QString::fromStdString(d->logic->GetInputDescription())), d->inputMessage);
}

bool qTissueMosaicReconstructionWidget::loadCalibration(const QString& path) {
  return this->loadCalibrationFiles({path});
}

bool qTissueMosaicReconstructionWidget::loadCalibrationFiles(const QStringList& paths) {
  Q_D(qTissueMosaicReconstructionWidget);
  std::vector<std::string> files;
  QStringList names;
  for (const QString& path : paths) {
    files.push_back(path.toStdString());
    names << QFileInfo(path).fileName();
  }
  const bool ok = d->logic->LoadCalibrationFiles(files);
  emit outputsUpdated();
  return d->report(ok, tr("Calibration %1 loaded").arg(names.join(" + ")), d->inputMessage);
}

void qTissueMosaicReconstructionWidget::setInputRectified(bool rectified) {
  Q_D(qTissueMosaicReconstructionWidget);
  d->logic->SetInputRectified(rectified);
  emit outputsUpdated();
  d->updateControls();
}

bool qTissueMosaicReconstructionWidget::start() {
  Q_D(qTissueMosaicReconstructionWidget);
  const bool ok = d->logic->Start();
  return d->report(ok, QString(), d->scanMessage);
}

void qTissueMosaicReconstructionWidget::pause() {
  Q_D(qTissueMosaicReconstructionWidget);
  d->logic->Pause();
  d->updateControls();
}

void qTissueMosaicReconstructionWidget::stop() {
  Q_D(qTissueMosaicReconstructionWidget);
  d->logic->Stop();
  d->updateControls();
}

void qTissueMosaicReconstructionWidget::reset() {
  Q_D(qTissueMosaicReconstructionWidget);
  d->logic->Reset();
  d->show(QString(), false, d->scanMessage);
  d->updateTimingTable();
  d->updateControls();
  emit outputsUpdated();
}

bool qTissueMosaicReconstructionWidget::exportModel(const QString& path) {
  Q_D(qTissueMosaicReconstructionWidget);
  const bool ok = d->logic->ExportModel(path.toStdString());
  if (ok) d->exportedModelTime = d->logic->GetModel()->GetMTime();
  return d->report(ok, tr("Model written to %1").arg(path), d->exportMessage);
}

bool qTissueMosaicReconstructionWidget::exportTrajectory(const QString& path) {
  Q_D(qTissueMosaicReconstructionWidget);
  const bool ok = d->logic->ExportTrajectory(path.toStdString());
  return d->report(ok, tr("Trajectory written to %1").arg(path), d->exportMessage);
}

void qTissueMosaicReconstructionWidget::showMessage(const QString& text, bool error, MessagePlace place) {
  Q_D(qTissueMosaicReconstructionWidget);
  d->show(text, error, d->line(place));
}

QString qTissueMosaicReconstructionWidget::startProblem() const {
  Q_D(const qTissueMosaicReconstructionWidget);
  return d->startProblem;
}

bool qTissueMosaicReconstructionWidget::hasUnexportedModel() const {
  Q_D(const qTissueMosaicReconstructionWidget);
  vtkPolyData* model = d->logic->GetModel();
  return model->GetNumberOfPoints() > 0 && model->GetMTime() != d->exportedModelTime;
}

bool qTissueMosaicReconstructionWidget::updateFromLogic() {
  Q_D(qTissueMosaicReconstructionWidget);
  const bool changed = d->logic->UpdateOutputs();
  // The state taken with the outputs, not the worker's state now: a scan that ended after UpdateOutputs took its
  // last model is reported ended at the next poll, once that final model is here.
  const int state = d->logic->GetStatus().state;
  if (changed) {
    // The table is for reading, not for watching every frame: a few updates per second are plenty.
    if (++d->pollsSinceTiming >= 8 || state != vtkTissueMosaicReconstructionLogic::StateRunning) {
      d->pollsSinceTiming = 0;
      d->updateTimingTable();
    }
    d->updateControls();
    emit outputsUpdated();
  }
  if (state != d->lastState) {
    d->lastState = state;
    d->updateControls();
    if (state == vtkTissueMosaicReconstructionLogic::StateFailed) {
      d->show(tr("The scan failed: %1")
                  .arg(qTissueMosaicMessageLine::sentence(QString::fromStdString(d->logic->GetStatus().errorText))),
              true, d->scanMessage);
    }
    emit scanStateChanged(state);
  }
  return changed;
}
