#include "qTissueMosaicRegistrationWidget.h"

#include "qTissueMosaicHistogramPlot.h"
#include "qTissueMosaicLandmarkTable.h"
#include "qTissueMosaicMessageLine.h"
#include "qTissueMosaicRegistrationResults.h"
#include "qTissueMosaicWheelGuard.h"
#include "vtkTissueMosaicRegistrationLogic.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <QButtonGroup>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QEventLoop>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QPointer>
#include <QProgressBar>
#include <QPushButton>
#include <QRadioButton>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>

#include <cmath>
#include <functional>
#include <memory>
#include <thread>

namespace {

using tissuemosaic::ModelFrameChoice;
using RegistrationLogic = vtkTissueMosaicRegistrationLogic;

QString pointCount(vtkIdType points) { return QLocale().toString(static_cast<qlonglong>(points)); }

/// A frame choice for the next file: what the file declares (Slicer's SPACE mark; LPS when none), LPS or RAS.
QComboBox* frameComboBox(const char* name) {
  auto* combo = new QComboBox;
  combo->setObjectName(name);
  combo->addItem(QObject::tr("frame from file"), static_cast<int>(ModelFrameChoice::FromFile));
  combo->addItem("LPS", static_cast<int>(ModelFrameChoice::LPS));
  combo->addItem("RAS", static_cast<int>(ModelFrameChoice::RAS));
  combo->setToolTip(QObject::tr("Frame of the next file's coordinates: what the file declares (Slicer's SPACE "
                                "mark; LPS when it declares none), or LPS / RAS explicitly."));
  tissuemosaic::widgets::guardWheel(combo);
  return combo;
}

QPushButton* namedButton(const QString& text, const char* name, const QString& toolTip = QString()) {
  auto* button = new QPushButton(text);
  button->setObjectName(name);
  button->setToolTip(toolTip);
  return button;
}

}  // namespace

class qTissueMosaicRegistrationWidgetPrivate {
  Q_DECLARE_PUBLIC(qTissueMosaicRegistrationWidget);

public:
  explicit qTissueMosaicRegistrationWidgetPrivate(qTissueMosaicRegistrationWidget& object) : q_ptr(&object) {}

  void setupUi();
  QGroupBox* modelsBox();
  QGroupBox* landmarksBox();
  QGroupBox* registrationBox();
  QGroupBox* exportBox();

  /// Shows the logic's error text in `line` when a call failed, `success` (may be empty) otherwise; returns ok.
  bool report(qTissueMosaicMessageLine* line, bool ok, const QString& success = QString());
  void updateModelText();
  void updateResultsNotice();
  void updateControls();
  /// After a registration step: the view, the numbers and the table follow.
  void showRegistration();
  void finishIcp();
  /// A file dialog, then `action(path)`; nothing when cancelled.
  void withSaveFile(const QString& title, const QString& filter, const std::function<bool(const QString&)>& action);

  qTissueMosaicRegistrationWidget* q_ptr;
  vtkNew<RegistrationLogic> Logic;
  QPointer<qTissueMosaicRegistrationView> View;
  vtkSmartPointer<vtkPolyData> LiveModel;  ///< the reconstruction's model (grows in place)
  QString ModelFileName;                   ///< of the model loaded from a file
  vtkIdType LivePointsSeen = 0;            ///< the live model's size at the last liveModelChanged()

  QRadioButton* UseScan = nullptr;
  QRadioButton* UseFile = nullptr;
  QComboBox* ModelFrame = nullptr;
  QComboBox* TargetFrame = nullptr;
  QLabel* TargetInfo = nullptr;
  qTissueMosaicMessageLine* ModelsMessage = nullptr;
  QPushButton* PickModelButton = nullptr;
  QPushButton* PickTargetButton = nullptr;
  qTissueMosaicLandmarkTable* Table = nullptr;
  qTissueMosaicMessageLine* LandmarksMessage = nullptr;
  QCheckBox* Scale = nullptr;
  QSpinBox* IcpIterations = nullptr;
  QDoubleSpinBox* IcpInlierFraction = nullptr;
  QDoubleSpinBox* IcpMaxDistance = nullptr;
  QPushButton* RegisterButton = nullptr;
  QPushButton* IcpButton = nullptr;
  QPushButton* UndoButton = nullptr;
  QProgressBar* IcpProgress = nullptr;
  qTissueMosaicMessageLine* RegistrationMessage = nullptr;
  qTissueMosaicRegistrationResults* Results = nullptr;
  QPushButton* ExportButtons[4] = {};
  qTissueMosaicMessageLine* ExportMessage = nullptr;
  qTissueMosaicMessageLine* LastLine = nullptr;  ///< where the last message went

  // A running ICP (worker thread; polled on the GUI thread).
  std::shared_ptr<RegistrationLogic::Job> IcpJob;
  std::thread IcpThread;
  std::shared_ptr<std::atomic<bool>> IcpDone;
  QTimer IcpPoll;
  double RmseBeforeIcp = -1;  ///< distance RMSE of the state ICP started from (-1: none)
};

// ---- construction -----------------------------------------------------------------------------------------------

void qTissueMosaicRegistrationWidgetPrivate::setupUi() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* column = new QVBoxLayout(q);
  column->addWidget(this->modelsBox());
  column->addWidget(this->landmarksBox());
  column->addWidget(this->registrationBox());
  this->Results = new qTissueMosaicRegistrationResults(q);
  column->addWidget(this->Results);
  column->addWidget(this->exportBox());
  column->addStretch(1);

  QObject::connect(this->Results, &qTissueMosaicRegistrationResults::colourByDistanceToggled, q,
                   [this](bool enabled) { this->View->setColourByDistance(enabled); });
  QObject::connect(this->Results, &qTissueMosaicRegistrationResults::binWidthChanged, q, [this](double mm) {
    this->report(this->RegistrationMessage, this->Logic->SetHistogramBinWidthMm(mm));
    this->Results->showResults(this->Logic);
  });
  QObject::connect(this->Results, &qTissueMosaicRegistrationResults::updateDistancesRequested, q,
                   [q] { q->updateDistances(); });
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::modelsBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Models"));
  auto* grid = new QGridLayout(box);
  this->UseScan = new QRadioButton(QObject::tr("Use the current scan"));
  this->UseScan->setObjectName("useCurrentScanRadio");
  this->UseScan->setToolTip(QObject::tr("The live reconstruction, kept up to date as the scan grows"));
  this->UseFile = new QRadioButton(QObject::tr("Model file"));
  this->UseFile->setObjectName("useModelFileRadio");
  auto* group = new QButtonGroup(box);
  group->addButton(this->UseScan);
  group->addButton(this->UseFile);
  auto* loadModel = namedButton(QObject::tr("Load model..."), "loadModelButton",
                                QObject::tr("A reconstructed model from a file (.ply .vtp .vtk .stl .obj)"));
  this->ModelFrame = frameComboBox("modelFrameCombo");
  auto* loadTarget = namedButton(QObject::tr("Load CT/MR..."), "loadTargetButton",
                                 QObject::tr("The CT/MR surface model, with triangles (.stl .vtp .vtk .ply .obj)"));
  this->TargetFrame = frameComboBox("targetFrameCombo");
  this->TargetInfo = new QLabel(QObject::tr("no CT/MR model"));
  this->TargetInfo->setObjectName("targetInfoLabel");
  this->TargetInfo->setWordWrap(true);
  this->ModelsMessage = new qTissueMosaicMessageLine;
  this->ModelsMessage->setObjectName("modelsMessage");
  grid->addWidget(this->UseScan, 0, 0, 1, 3);
  grid->addWidget(this->UseFile, 1, 0);
  grid->addWidget(loadModel, 1, 1);
  grid->addWidget(this->ModelFrame, 1, 2);
  grid->addWidget(new QLabel(QObject::tr("CT/MR")), 2, 0);
  grid->addWidget(loadTarget, 2, 1);
  grid->addWidget(this->TargetFrame, 2, 2);
  grid->addWidget(this->TargetInfo, 3, 0, 1, 3);
  grid->addWidget(this->ModelsMessage, 4, 0, 1, 3);
  grid->setColumnStretch(1, 1);

  const QString filter = QObject::tr("Surface models (*.ply *.vtp *.vtk *.stl *.obj)");
  QObject::connect(this->UseScan, &QRadioButton::clicked, q, [q] { q->useCurrentScan(); });
  QObject::connect(this->UseFile, &QRadioButton::clicked, q, [this, loadModel] {
    if (this->ModelFileName.isEmpty()) loadModel->click();  // nothing loaded yet: choose the file
    this->updateModelText();
  });
  QObject::connect(loadModel, &QPushButton::clicked, q, [this, q, filter] {
    const QString path = QFileDialog::getOpenFileName(q, QObject::tr("Load the reconstructed model"), QString(), filter);
    if (!path.isEmpty()) q->loadModelFile(path);
    this->updateModelText();
  });
  QObject::connect(loadTarget, &QPushButton::clicked, q, [q, filter] {
    const QString path = QFileDialog::getOpenFileName(q, QObject::tr("Load the CT/MR model"), QString(), filter);
    if (!path.isEmpty()) q->loadTargetFile(path);
  });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::landmarksBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Landmarks"));
  auto* layout = new QVBoxLayout(box);
  auto* pickRow = new QHBoxLayout;
  this->PickModelButton = namedButton(QObject::tr("Pick on model"), "pickModelButton");
  this->PickTargetButton = namedButton(QObject::tr("Pick on CT/MR"), "pickTargetButton");
  for (QPushButton* button : {this->PickModelButton, this->PickTargetButton}) {
    button->setCheckable(true);
    button->setToolTip(QObject::tr("Then click in the 3D view (dragging still rotates). Each pick completes the "
                                   "first pair that lacks this point, or starts a new pair."));
    pickRow->addWidget(button);
  }
  layout->addLayout(pickRow);
  using View = qTissueMosaicRegistrationView;
  QObject::connect(this->PickModelButton, &QPushButton::toggled, q, [q](bool on) {
    if (on) q->setPickMode(View::PickOnModel);
    else if (q->pickMode() == View::PickOnModel) q->setPickMode(View::PickNone);
  });
  QObject::connect(this->PickTargetButton, &QPushButton::toggled, q, [q](bool on) {
    if (on) q->setPickMode(View::PickOnTarget);
    else if (q->pickMode() == View::PickOnTarget) q->setPickMode(View::PickNone);
  });

  this->Table = new qTissueMosaicLandmarkTable(this->Logic);
  layout->addWidget(this->Table);
  QObject::connect(this->Table, &qTissueMosaicLandmarkTable::landmarksChanged, q, [this, q] {
    this->LandmarksMessage->clearMessage();
    this->View->updateLandmarks();
    emit q->landmarksChanged();
  });
  QObject::connect(this->Table, &qTissueMosaicLandmarkTable::editRefused, q, [this](const QString& reason) {
    this->LandmarksMessage->showError(qTissueMosaicMessageLine::sentence(reason));
    this->LastLine = this->LandmarksMessage;
  });

  auto* buttons = new QHBoxLayout;
  auto* remove = namedButton(QObject::tr("Delete"), "deleteLandmarksButton", QObject::tr("Delete the selected pairs"));
  auto* clear = namedButton(QObject::tr("Clear"), "clearLandmarksButton", QObject::tr("Delete every pair"));
  auto* load = namedButton(QObject::tr("Load..."), "loadLandmarksButton",
                           QObject::tr("A .mrk.json with two lists, the model's then the CT/MR model's (as exported)"));
  buttons->addWidget(remove);
  buttons->addWidget(clear);
  buttons->addWidget(load);
  layout->addLayout(buttons);
  this->LandmarksMessage = new qTissueMosaicMessageLine;
  this->LandmarksMessage->setObjectName("landmarksMessage");
  layout->addWidget(this->LandmarksMessage);
  QObject::connect(remove, &QPushButton::clicked, q, [this] { this->Table->deleteSelectedRows(); });
  QObject::connect(clear, &QPushButton::clicked, q, [this, q] {
    this->Logic->ClearLandmarks();
    this->Table->updateFromLogic();
    this->View->updateLandmarks();
    emit q->landmarksChanged();
  });
  QObject::connect(load, &QPushButton::clicked, q, [q] {
    const QString path = QFileDialog::getOpenFileName(q, QObject::tr("Load landmark pairs"), QString(),
                                                      QObject::tr("Markups (*.mrk.json *.json)"));
    if (!path.isEmpty()) q->loadLandmarksFile(path);
  });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::registrationBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  const tissuemosaic::IcpParameters defaults;
  auto* box = new QGroupBox(QObject::tr("Registration"));
  auto* layout = new QVBoxLayout(box);
  auto* landmarkRow = new QHBoxLayout;
  this->Scale = new QCheckBox(QObject::tr("with uniform scale"));
  this->Scale->setObjectName("scaleCheckBox");
  this->Scale->setToolTip(QObject::tr("Similarity instead of rigid fit (the scale of the reconstruction is off)"));
  this->RegisterButton = namedButton(QObject::tr("Register landmarks"), "registerLandmarksButton");
  landmarkRow->addWidget(this->Scale);
  landmarkRow->addWidget(this->RegisterButton, 1);
  layout->addLayout(landmarkRow);

  auto* form = new QFormLayout;
  this->IcpIterations = new QSpinBox;
  this->IcpIterations->setObjectName("icpIterationsSpinBox");
  this->IcpIterations->setRange(1, 1000);
  this->IcpIterations->setValue(defaults.maxIterations);
  form->addRow(QObject::tr("ICP max iterations"), this->IcpIterations);
  this->IcpInlierFraction = new QDoubleSpinBox;
  this->IcpInlierFraction->setObjectName("icpInlierFractionSpinBox");
  this->IcpInlierFraction->setRange(0.05, 1.0);
  this->IcpInlierFraction->setSingleStep(0.05);
  this->IcpInlierFraction->setValue(defaults.inlierFraction);
  this->IcpInlierFraction->setToolTip(QObject::tr("Share of the closest correspondences used per step (trimmed "
                                                  "ICP), so that tissue the CT/MR model lacks does not pull"));
  form->addRow(QObject::tr("ICP inlier fraction"), this->IcpInlierFraction);
  this->IcpMaxDistance = new QDoubleSpinBox;
  this->IcpMaxDistance->setObjectName("icpMaxDistanceSpinBox");
  this->IcpMaxDistance->setRange(0, 1000);
  this->IcpMaxDistance->setSuffix(" mm");
  this->IcpMaxDistance->setSpecialValueText(QObject::tr("no limit"));
  this->IcpMaxDistance->setToolTip(QObject::tr("Correspondences farther than this are never used"));
  form->addRow(QObject::tr("ICP max distance"), this->IcpMaxDistance);
  for (QWidget* spinBox : {static_cast<QWidget*>(this->IcpIterations), static_cast<QWidget*>(this->IcpInlierFraction),
                           static_cast<QWidget*>(this->IcpMaxDistance)}) {
    tissuemosaic::widgets::guardWheel(spinBox);
  }
  layout->addLayout(form);

  auto* icpRow = new QHBoxLayout;
  this->IcpButton = namedButton(QObject::tr("Refine with ICP"), "refineIcpButton");
  this->UndoButton = namedButton(QObject::tr("Undo"), "undoRegistrationButton",
                                 QObject::tr("Put back the transform and results of before the last step"));
  icpRow->addWidget(this->IcpButton, 1);
  icpRow->addWidget(this->UndoButton);
  layout->addLayout(icpRow);
  this->IcpProgress = new QProgressBar;
  this->IcpProgress->setObjectName("icpProgressBar");
  this->IcpProgress->setFormat(QObject::tr("ICP step %v of at most %m"));
  this->IcpProgress->hide();
  layout->addWidget(this->IcpProgress);
  this->RegistrationMessage = new qTissueMosaicMessageLine;
  this->RegistrationMessage->setObjectName("registrationMessage");
  layout->addWidget(this->RegistrationMessage);

  QObject::connect(this->RegisterButton, &QPushButton::clicked, q, [q] { q->registerLandmarks(); });
  QObject::connect(this->IcpButton, &QPushButton::clicked, q, [this, q] {
    if (q->isIcpRunning()) q->cancelIcp();  // the button reads "Cancel ICP" meanwhile
    else q->startIcp();
  });
  QObject::connect(this->UndoButton, &QPushButton::clicked, q, [q] { q->undo(); });
  QObject::connect(&this->IcpPoll, &QTimer::timeout, q, [this] {
    if (!this->IcpJob) return;
    this->IcpProgress->setValue(RegistrationLogic::GetJobProgress(*this->IcpJob));
    if (this->IcpDone && *this->IcpDone) this->finishIcp();
  });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::exportBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Export"));
  auto* grid = new QGridLayout(box);
  auto* transform = namedButton(QObject::tr("Transform (.tfm)..."), "exportTransformButton",
                                QObject::tr("ITK transform for Slicer: holds CT/MR -> model (the resampling "
                                            "convention); put the model under it in Slicer to move it onto the CT/MR "
                                            "model"));
  auto* model = namedButton(QObject::tr("Registered model..."), "exportRegisteredModelButton",
                            QObject::tr("The model in the CT/MR frame with its distances (.vtp .ply .vtk)"));
  auto* landmarks = namedButton(QObject::tr("Landmarks..."), "exportLandmarksButton",
                                QObject::tr("The complete pairs as a .mrk.json (model list first)"));
  auto* distances = namedButton(QObject::tr("Distance report..."), "exportDistanceReportButton",
                                QObject::tr("The distances as CSV, and the histogram as a PNG beside it"));
  this->ExportButtons[0] = transform;
  this->ExportButtons[1] = model;
  this->ExportButtons[2] = landmarks;
  this->ExportButtons[3] = distances;
  grid->addWidget(transform, 0, 0);
  grid->addWidget(model, 0, 1);
  grid->addWidget(landmarks, 1, 0);
  grid->addWidget(distances, 1, 1);
  this->ExportMessage = new qTissueMosaicMessageLine;
  this->ExportMessage->setObjectName("exportMessage");
  grid->addWidget(this->ExportMessage, 2, 0, 1, 2);
  QObject::connect(transform, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the transform"), QObject::tr("ITK transform (*.tfm)"),
                       [q](const QString& path) { return q->exportTransform(path); });
  });
  QObject::connect(model, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the registered model"), QObject::tr("Models (*.vtp *.ply *.vtk)"),
                       [q](const QString& path) { return q->exportRegisteredModel(path); });
  });
  QObject::connect(landmarks, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the landmark pairs"), QObject::tr("Markups (*.mrk.json)"),
                       [q](const QString& path) { return q->exportLandmarks(path); });
  });
  QObject::connect(distances, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the distance report (the PNG plot goes next to it)"),
                       QObject::tr("CSV (*.csv)"), [q](const QString& path) {
                         const QFileInfo csv(path);
                         const QString png = csv.dir().filePath(csv.completeBaseName() + ".png");
                         return q->exportDistanceReport(path, png);
                       });
  });
  return box;
}

// ---- state ------------------------------------------------------------------------------------------------------

bool qTissueMosaicRegistrationWidgetPrivate::report(qTissueMosaicMessageLine* line, bool ok, const QString& success) {
  this->LastLine = line;
  if (ok) line->showDone(success);
  else line->showError(qTissueMosaicMessageLine::sentence(QString::fromStdString(this->Logic->GetLastErrorText())));
  return ok;
}

void qTissueMosaicRegistrationWidgetPrivate::updateModelText() {
  const bool scan = this->LiveModel && this->Logic->GetModel() == this->LiveModel;
  const QSignalBlocker blockScan(this->UseScan), blockFile(this->UseFile);
  this->UseScan->setEnabled(this->LiveModel != nullptr);
  this->UseScan->setChecked(scan);
  this->UseFile->setChecked(!scan && this->Logic->GetModel());
  if (!this->LiveModel) this->UseScan->setText(QObject::tr("Use the current scan (none)"));
  else if (this->LiveModel->GetNumberOfPoints() == 0) this->UseScan->setText(QObject::tr("Use the current scan (no points yet)"));
  else this->UseScan->setText(QObject::tr("Use the current scan (%1 points)").arg(pointCount(this->LiveModel->GetNumberOfPoints())));
  vtkPolyData* model = this->Logic->GetModel();
  if (!scan && model) {
    this->UseFile->setText(QObject::tr("%1 (%2 points)").arg(this->ModelFileName).arg(pointCount(model->GetNumberOfPoints())));
    this->UseFile->setToolTip(this->ModelFileName);
  } else {
    this->UseFile->setText(QObject::tr("Model file"));
  }
  vtkPolyData* target = this->Logic->GetTarget();
  this->TargetInfo->setText(target ? QObject::tr("CT/MR: %1 points, %2 triangles")
                                         .arg(pointCount(target->GetNumberOfPoints()))
                                         .arg(pointCount(target->GetNumberOfPolys()))
                                   : QObject::tr("no CT/MR model"));
}

void qTissueMosaicRegistrationWidgetPrivate::updateResultsNotice() {
  vtkPolyData* model = this->Logic->GetModel();
  const vtkIdType now = model ? model->GetNumberOfPoints() : 0;
  const vtkIdType evaluated = this->Logic->GetEvaluatedModelPoints();
  if (this->Logic->HasEvaluation() && now != evaluated) {
    this->Results->setNotice(QObject::tr("Out of date: the model has changed since these results (%1 -> %2 points). "
                                         "Press Update distances, or register again.")
                                 .arg(pointCount(evaluated))
                                 .arg(pointCount(now)));
  } else {
    this->Results->setNotice(QString());
  }
}

void qTissueMosaicRegistrationWidgetPrivate::updateControls() {
  const bool running = this->IcpJob != nullptr;
  for (QWidget* widget : {static_cast<QWidget*>(this->RegisterButton), static_cast<QWidget*>(this->UndoButton),
                          static_cast<QWidget*>(this->Scale), static_cast<QWidget*>(this->IcpIterations),
                          static_cast<QWidget*>(this->IcpInlierFraction), static_cast<QWidget*>(this->IcpMaxDistance)}) {
    widget->setEnabled(!running);
  }
  this->UndoButton->setEnabled(!running && this->Logic->CanUndo());
  this->IcpButton->setText(running ? QObject::tr("Cancel ICP") : QObject::tr("Refine with ICP"));
  this->IcpProgress->setVisible(running);
  for (QPushButton* button : this->ExportButtons) button->setEnabled(!running);
}

void qTissueMosaicRegistrationWidgetPrivate::showRegistration() {
  Q_Q(qTissueMosaicRegistrationWidget);
  q->updateFromLogic();
  emit q->registrationChanged();
}

void qTissueMosaicRegistrationWidgetPrivate::finishIcp() {
  Q_Q(qTissueMosaicRegistrationWidget);
  this->IcpPoll.stop();
  if (this->IcpThread.joinable()) this->IcpThread.join();
  const std::shared_ptr<RegistrationLogic::Job> job = std::move(this->IcpJob);
  this->IcpJob.reset();
  const bool ok = this->Logic->FinishJob(*job);
  this->updateControls();
  if (!ok) {
    this->report(this->RegistrationMessage, false);
  } else {
    const auto& icp = this->Logic->GetIcpResult();
    const double after = this->Logic->GetDistanceStatistics().rmseMm;
    // A refinement that made the fit worse (poor landmarks, a CT/MR model that covers a different part) must not
    // pass silently: say so and offer Undo.
    if (this->RmseBeforeIcp >= 0 && after > this->RmseBeforeIcp * 1.05 + 0.01) {
      this->RegistrationMessage->showWarning(
          QObject::tr("ICP made the fit worse: distance RMSE %1 -> %2 mm. Press Undo to go back, and check the "
                      "landmark pairs.")
              .arg(this->RmseBeforeIcp, 0, 'f', 3)
              .arg(after, 0, 'f', 3));
    } else if (icp && !icp->converged) {
      this->RegistrationMessage->showWarning(
          QObject::tr("ICP stopped at its limit of %1 steps without converging: distance RMSE %2 mm.")
              .arg(icp->iterations)
              .arg(after, 0, 'f', 3));
    } else {
      this->RegistrationMessage->showDone(
          QObject::tr("ICP converged in %1 steps: distance RMSE %2 mm.").arg(icp ? icp->iterations : 0).arg(after, 0, 'f', 3));
    }
    this->LastLine = this->RegistrationMessage;
    this->showRegistration();
  }
  emit q->icpFinished(ok);
}

void qTissueMosaicRegistrationWidgetPrivate::withSaveFile(const QString& title, const QString& filter,
                                                          const std::function<bool(const QString&)>& action) {
  Q_Q(qTissueMosaicRegistrationWidget);
  const QString path = QFileDialog::getSaveFileName(q, title, QString(), filter);
  if (!path.isEmpty()) action(path);
}

// ---- public API -------------------------------------------------------------------------------------------------

qTissueMosaicRegistrationWidget::qTissueMosaicRegistrationWidget(QWidget* parent)
    : QWidget(parent), d_ptr(new qTissueMosaicRegistrationWidgetPrivate(*this)) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->View = new qTissueMosaicRegistrationView(d->Logic);
  d->View->setObjectName("registrationView");
  d->setupUi();
  d->IcpPoll.setInterval(50);
  connect(d->View, &qTissueMosaicRegistrationView::landmarkPicked, this, [this, d] {
    d->LandmarksMessage->clearMessage();
    d->Table->updateFromLogic();
    emit landmarksChanged();
  });
  connect(d->View, &qTissueMosaicRegistrationView::pickMissed, this, [d](const QString& reason) {
    d->LandmarksMessage->showError(reason);
    d->LastLine = d->LandmarksMessage;
  });
  this->updateFromLogic();
}

qTissueMosaicRegistrationWidget::~qTissueMosaicRegistrationWidget() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (d->IcpJob) RegistrationLogic::CancelJob(*d->IcpJob);
  if (d->IcpThread.joinable()) d->IcpThread.join();
  if (d->View && !d->View->parent()) delete d->View;  // nobody placed it
}

vtkTissueMosaicRegistrationLogic* qTissueMosaicRegistrationWidget::registrationLogic() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Logic;
}

qTissueMosaicRegistrationView* qTissueMosaicRegistrationWidget::sceneView() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->View;
}

void qTissueMosaicRegistrationWidget::updateFromLogic() {
  Q_D(qTissueMosaicRegistrationWidget);
  d->updateModelText();
  d->Results->showResults(d->Logic);
  d->updateResultsNotice();
  d->Table->updateFromLogic();
  d->updateControls();
  d->View->updateFromLogic();  // renders
}

void qTissueMosaicRegistrationWidget::setReconstructedModel(vtkPolyData* liveModel) {
  Q_D(qTissueMosaicRegistrationWidget);
  const bool follow = !d->Logic->GetModel() || d->Logic->GetModel() == d->LiveModel;
  d->LiveModel = liveModel;
  if (follow) this->useCurrentScan();
  else d->updateModelText();
}

bool qTissueMosaicRegistrationWidget::useCurrentScan() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->LiveModel) {
    d->ModelsMessage->showError(tr("There is no scan in this application to use."));
    d->updateModelText();
    return false;
  }
  const bool first = d->Logic->GetModel() == nullptr;
  if (d->Logic->GetModel() != d->LiveModel) {
    d->Logic->SetModel(d->LiveModel);
    d->ModelsMessage->clearMessage();
    this->updateFromLogic();
    if (first) d->View->resetCamera();
    emit registrationChanged();
  }
  d->updateModelText();
  return true;
}

bool qTissueMosaicRegistrationWidget::usesCurrentScan() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->LiveModel && d->Logic->GetModel() == d->LiveModel;
}

void qTissueMosaicRegistrationWidget::liveModelChanged() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!this->usesCurrentScan()) {
    d->LivePointsSeen = d->LiveModel ? d->LiveModel->GetNumberOfPoints() : 0;
    d->updateModelText();
    return;
  }
  const vtkIdType points = d->LiveModel->GetNumberOfPoints();
  const bool reset = points < d->LivePointsSeen;  // a reset empties the model; a new scan grows it from nothing
  const bool grew = points > d->LivePointsSeen;
  d->LivePointsSeen = points;
  if (reset) {
    // The scan was reset: transform, results and model landmarks belonged to a model that no longer exists.
    d->Logic->SetModel(nullptr);
    d->Logic->SetModel(d->LiveModel);
    d->Logic->ClearModelLandmarks();
    d->RegistrationMessage->clearMessage();
    d->ExportMessage->clearMessage();
    this->updateFromLogic();
    d->Results->setNotice(tr("The scan was reset: its registration results and model landmarks were dropped."));
    emit registrationChanged();
    emit landmarksChanged();
    return;
  }
  d->updateModelText();
  d->updateResultsNotice();
  if (grew) d->View->updateFromLogic();  // colours that came with the points; a shown view draws
}

bool qTissueMosaicRegistrationWidget::loadModelFile(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  const auto frame = static_cast<ModelFrameChoice>(d->ModelFrame->currentData().toInt());
  if (!d->report(d->ModelsMessage, d->Logic->LoadModel(path.toStdString(), frame))) return false;
  d->ModelFileName = QFileInfo(path).fileName();
  this->updateFromLogic();
  d->View->resetCamera();
  emit registrationChanged();
  return true;
}

bool qTissueMosaicRegistrationWidget::loadTargetFile(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  const auto frame = static_cast<ModelFrameChoice>(d->TargetFrame->currentData().toInt());
  if (!d->report(d->ModelsMessage, d->Logic->LoadTarget(path.toStdString(), frame),
                 tr("Loaded %1").arg(QFileInfo(path).fileName()))) {
    return false;
  }
  this->updateFromLogic();
  d->View->resetCamera();
  emit registrationChanged();
  return true;
}

void qTissueMosaicRegistrationWidget::setModelFrameChoice(int choice) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->ModelFrame->setCurrentIndex(d->ModelFrame->findData(choice));
}

void qTissueMosaicRegistrationWidget::setTargetFrameChoice(int choice) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->TargetFrame->setCurrentIndex(d->TargetFrame->findData(choice));
}

int qTissueMosaicRegistrationWidget::addLandmarkPair(const Eigen::Vector3d& modelLps, const Eigen::Vector3d& targetLps) {
  Q_D(qTissueMosaicRegistrationWidget);
  const int row = d->Logic->AddLandmarkPair(modelLps, targetLps);
  if (!d->report(d->LandmarksMessage, row >= 0)) return -1;
  d->Table->updateFromLogic();
  d->View->updateLandmarks();
  emit landmarksChanged();
  return row;
}

bool qTissueMosaicRegistrationWidget::removeLandmarkPair(int row) {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->report(d->LandmarksMessage, d->Logic->RemoveLandmarkPair(row))) return false;
  d->Table->updateFromLogic();
  d->View->updateLandmarks();
  emit landmarksChanged();
  return true;
}

bool qTissueMosaicRegistrationWidget::loadLandmarksFile(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->report(d->LandmarksMessage, d->Logic->LoadLandmarkPairs(path.toStdString()))) return false;
  d->Table->updateFromLogic();
  d->View->updateLandmarks();
  emit landmarksChanged();
  return true;
}

qTissueMosaicLandmarkTable* qTissueMosaicRegistrationWidget::landmarkTable() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Table;
}

void qTissueMosaicRegistrationWidget::setPickMode(qTissueMosaicRegistrationView::PickMode mode) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->View->setPickMode(mode);
  const QSignalBlocker blockModel(d->PickModelButton), blockTarget(d->PickTargetButton);
  d->PickModelButton->setChecked(mode == qTissueMosaicRegistrationView::PickOnModel);
  d->PickTargetButton->setChecked(mode == qTissueMosaicRegistrationView::PickOnTarget);
}

qTissueMosaicRegistrationView::PickMode qTissueMosaicRegistrationWidget::pickMode() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->View->pickMode();
}

void qTissueMosaicRegistrationWidget::setScaleEnabled(bool withScale) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->Scale->setChecked(withScale);
}

bool qTissueMosaicRegistrationWidget::scaleEnabled() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Scale->isChecked();
}

bool qTissueMosaicRegistrationWidget::registerLandmarks() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (d->IcpJob) return false;
  const bool ok = d->Logic->RegisterLandmarks(d->Scale->isChecked());
  const QString done = ok ? tr("Registered %1 landmark pairs: landmark RMSE %2 mm.")
                                .arg(d->Logic->GetNumberOfCompleteLandmarkPairs())
                                .arg(d->Logic->GetLandmarkRegistration()->rmseMm, 0, 'f', 3)
                          : QString();
  if (!d->report(d->RegistrationMessage, ok, done)) return false;
  d->showRegistration();
  return true;
}

bool qTissueMosaicRegistrationWidget::startIcp() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (d->IcpJob) return false;
  tissuemosaic::IcpParameters parameters;
  parameters.maxIterations = d->IcpIterations->value();
  parameters.inlierFraction = d->IcpInlierFraction->value();
  if (d->IcpMaxDistance->value() > 0) parameters.maxDistanceMm = d->IcpMaxDistance->value();
  std::shared_ptr<RegistrationLogic::Job> job = d->Logic->PrepareIcp(parameters);
  if (!d->report(d->RegistrationMessage, job != nullptr)) return false;
  d->RmseBeforeIcp = d->Logic->HasEvaluation() ? d->Logic->GetDistanceStatistics().rmseMm : -1;
  d->IcpJob = job;
  d->IcpDone = std::make_shared<std::atomic<bool>>(false);
  d->IcpThread = std::thread([job, done = d->IcpDone] {
    RegistrationLogic::RunJob(*job);
    *done = true;
  });
  d->IcpProgress->setRange(0, parameters.maxIterations);
  d->IcpProgress->setValue(0);
  d->RegistrationMessage->showDone(tr("ICP is running..."));
  d->updateControls();
  d->IcpPoll.start();
  return true;
}

bool qTissueMosaicRegistrationWidget::refineIcp() {
  bool result = false;
  QEventLoop loop;
  const QMetaObject::Connection connection = connect(this, &qTissueMosaicRegistrationWidget::icpFinished, &loop,
                                                     [&](bool ok) {
                                                       result = ok;
                                                       loop.quit();
                                                     });
  if (this->startIcp()) loop.exec();
  disconnect(connection);
  return result;
}

void qTissueMosaicRegistrationWidget::cancelIcp() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (d->IcpJob) RegistrationLogic::CancelJob(*d->IcpJob);
}

bool qTissueMosaicRegistrationWidget::isIcpRunning() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->IcpJob != nullptr;
}

bool qTissueMosaicRegistrationWidget::undo() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (d->IcpJob) return false;
  if (!d->report(d->RegistrationMessage, d->Logic->Undo(), tr("The previous registration is back."))) return false;
  d->showRegistration();
  return true;
}

void qTissueMosaicRegistrationWidget::setIcpMaxIterations(int iterations) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->IcpIterations->setValue(iterations);
}

void qTissueMosaicRegistrationWidget::setIcpInlierFraction(double fraction) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->IcpInlierFraction->setValue(fraction);
}

bool qTissueMosaicRegistrationWidget::updateDistances() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (d->IcpJob) return false;
  if (!d->report(d->RegistrationMessage, d->Logic->Evaluate())) return false;
  d->showRegistration();
  return true;
}

QString qTissueMosaicRegistrationWidget::shownNumber(const QString& name) const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->number(name);
}

QString qTissueMosaicRegistrationWidget::shownTransform() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->transformText();
}

QString qTissueMosaicRegistrationWidget::shownModelText() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return this->usesCurrentScan() ? d->UseScan->text() : d->UseFile->text();
}

QString qTissueMosaicRegistrationWidget::errorText() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->LastLine && d->LastLine->isError() ? d->LastLine->text() : QString();
}

QString qTissueMosaicRegistrationWidget::lastMessage() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->LastLine ? d->LastLine->text() : QString();
}

QString qTissueMosaicRegistrationWidget::resultsNotice() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->notice();
}

QVector<double> qTissueMosaicRegistrationWidget::histogramPercent() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->histogram()->percent();
}

double qTissueMosaicRegistrationWidget::histogramBinWidthMm() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->histogram()->binWidthMm();
}

QString qTissueMosaicRegistrationWidget::histogramOverflowNote() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->histogram()->overflowNote();
}

void qTissueMosaicRegistrationWidget::setColourByDistance(bool enabled) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->Results->colourByDistanceCheckBox()->setChecked(enabled);
}

bool qTissueMosaicRegistrationWidget::colourByDistance() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Results->colourByDistanceCheckBox()->isChecked();
}

bool qTissueMosaicRegistrationWidget::exportTransform(const QString& tfmPath) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->ExportMessage, d->Logic->WriteTransform(tfmPath.toStdString()),
                   tr("Transform written to %1").arg(tfmPath));
}

bool qTissueMosaicRegistrationWidget::exportRegisteredModel(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->ExportMessage, d->Logic->WriteRegisteredModel(path.toStdString()),
                   tr("Registered model written to %1").arg(path));
}

bool qTissueMosaicRegistrationWidget::exportLandmarks(const QString& mrkJsonPath) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->ExportMessage, d->Logic->WriteLandmarks(mrkJsonPath.toStdString()),
                   tr("Landmarks written to %1").arg(mrkJsonPath));
}

bool qTissueMosaicRegistrationWidget::exportDistanceReport(const QString& csvPath, const QString& pngPath) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->ExportMessage,
                   d->Logic->WriteDistanceCsv(csvPath.toStdString()) && d->Logic->WriteHistogramPng(pngPath.toStdString()),
                   tr("Distances written to %1 and %2").arg(csvPath, pngPath));
}
