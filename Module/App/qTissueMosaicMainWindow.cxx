#include "qTissueMosaicMainWindow.h"

#include "qTissueMosaicModelView.h"
#include "qTissueMosaicReconstructionWidget.h"
#if defined(TM_WITH_IGTLINK)
#include "qTissueMosaicIgtLinkWidget.h"
#endif
#include "qTissueMosaicRegistrationWidget.h"
#include "qTissueMosaicVideoPanel.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include <vtkPolyData.h>

#include <QAbstractButton>
#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPixmap>
#include <QProgressBar>
#include <QPushButton>
#include <QScreen>
#include <QScrollArea>
#include <QSplitter>
#include <QStackedWidget>
#include <QStatusBar>
#include <QTabWidget>

#include <algorithm>

namespace {

QString pointCountText(long long points) {
  if (points >= 1000000) return QObject::tr("%1 M points").arg(points / 1e6, 0, 'f', 2);
  if (points >= 1000) return QObject::tr("%1 k points").arg(points / 1e3, 0, 'f', 1);
  return QObject::tr("%1 points").arg(points);
}

/// QProgressBar::setValue repaints synchronously, and in a window with an OpenGL view every repaint composes the
/// whole window (tens of ms with software OpenGL). With updates off, the change waits for the next paint of the
/// window instead, together with the 3D view's.
void setProgressDeferred(QProgressBar* bar, int maximum, int value, const QString& format) {
  bar->setUpdatesEnabled(false);
  bar->setRange(0, maximum);
  bar->setValue(value);
  bar->setFormat(format);
  bar->setUpdatesEnabled(true);  // schedules an (asynchronous) update
}

/// A status bar label that never pushes its neighbours aside: text too long for it is shortened with "..." (the
/// whole of it in the tooltip).
class ElidedLabel : public QLabel {
public:
  using QLabel::QLabel;
  void setFullText(const QString& text) {
    if (text == this->Full) return;
    this->Full = text;
    this->setToolTip(text);
    this->elide();
  }
  const QString& fullText() const { return this->Full; }
  QSize minimumSizeHint() const override { return QSize(0, QLabel::minimumSizeHint().height()); }

protected:
  void resizeEvent(QResizeEvent* event) override {
    QLabel::resizeEvent(event);
    this->elide();
  }

private:
  void elide() {
    const int width = this->contentsRect().width() - 2 * this->margin() - this->indent() - 12;
    const QString shown = this->fontMetrics().elidedText(this->Full, Qt::ElideRight, std::max(width, 0));
    if (shown != this->text()) this->setText(shown);
  }
  QString Full;
};

/// The panel's width: every control whole at the smallest window (1280x800), no wider than that needs.
constexpr int kModulePanelWidth = 545;

}  // namespace

qTissueMosaicMainWindow::qTissueMosaicMainWindow(QWidget* parent) : QMainWindow(parent) {
  this->setWindowTitle(tr("TissueMosaic: dense tissue surface reconstruction from stereo video"));
  this->setObjectName("tissueMosaicMainWindow");

  // Module panel (left), as in 3D Slicer: controls only.
  this->Modules = new QTabWidget(this);
  this->Modules->setObjectName("moduleTabs");
  const auto scrolled = [this](QWidget* panel) {
    auto* scroll = new QScrollArea(this);
    scroll->setWidget(panel);
    scroll->setWidgetResizable(true);
    scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    scroll->setFrameShape(QFrame::NoFrame);
    return scroll;
  };
  this->Reconstruction = new qTissueMosaicReconstructionWidget(this);
  this->Reconstruction->setObjectName("reconstructionPanel");
  this->Modules->addTab(scrolled(this->Reconstruction), tr("Reconstruction"));
  this->Registration = new qTissueMosaicRegistrationWidget(this);
  this->Registration->setObjectName("registrationPanel");
  this->Registration->setReconstructedModel(this->Reconstruction->reconstructionLogic()->GetModel());
  this->Modules->addTab(scrolled(this->Registration), tr("Registration"));
#if defined(TM_WITH_IGTLINK)
  // The OpenIGTLink link to 3D Slicer: streams the running scan while its server is on.
  auto* igtLink = new qTissueMosaicIgtLinkWidget(this);
  igtLink->setObjectName("igtLinkPanel");
  this->Reconstruction->reconstructionLogic()->SetScanObserver(igtLink->scanObserver());
  this->Modules->addTab(scrolled(igtLink), tr("OpenIGTLink"));
#endif
  this->Modules->setMinimumWidth(kModulePanelWidth);

  // View area (right), switched by the module: the growing model above the live video, or the registration scene.
  this->ModelView = new qTissueMosaicModelView(this);
  this->ModelView->setObjectName("modelView");
  this->ModelView->setReconstructionLogic(this->Reconstruction->reconstructionLogic());
  this->VideoPanel = new qTissueMosaicVideoPanel(this);
  this->VideoPanel->setObjectName("videoPanel");
  auto* reconstructionViews = new QSplitter(Qt::Vertical, this);
  reconstructionViews->setObjectName("reconstructionViews");
  reconstructionViews->addWidget(this->ModelView);
  reconstructionViews->addWidget(this->VideoPanel);
  reconstructionViews->setStretchFactor(0, 3);
  reconstructionViews->setStretchFactor(1, 1);
  reconstructionViews->setSizes({640, 260});  // the model first; the video strip below (frames are wide, 16:9)
  reconstructionViews->setCollapsible(0, false);
  this->Views = new QStackedWidget(this);
  this->Views->setObjectName("viewArea");
  this->Views->addWidget(reconstructionViews);
  this->Views->addWidget(this->Registration->sceneView());
  auto* main = new QSplitter(Qt::Horizontal, this);
  main->addWidget(this->Modules);
  main->addWidget(this->Views);
  main->setStretchFactor(0, 0);
  main->setStretchFactor(1, 1);
  main->setSizes({kModulePanelWidth, 1080});
  main->setCollapsible(0, false);
  main->setCollapsible(1, false);
  this->setCentralWidget(main);
  connect(this->Modules, &QTabWidget::currentChanged, this, &qTissueMosaicMainWindow::showModule);

  // Status bar: what a surgeon glances at.
  this->TrackingLabel = new ElidedLabel(this);
  this->TrackingLabel->setObjectName("trackingLabel");
  this->FpsLabel = new QLabel(this);
  this->FpsLabel->setObjectName("fpsLabel");
  this->KeyFramesLabel = new QLabel(this);
  this->KeyFramesLabel->setObjectName("keyFramesLabel");
  this->PointsLabel = new QLabel(this);
  this->PointsLabel->setObjectName("pointsLabel");
  this->Progress = new QProgressBar(this);
  this->Progress->setObjectName("progressBar");
  this->Progress->setMinimumWidth(180);
  this->Progress->setMaximumWidth(260);
  this->Progress->setTextVisible(true);
  this->statusBar()->addWidget(this->TrackingLabel, 1);
  this->statusBar()->addPermanentWidget(this->FpsLabel);
  this->statusBar()->addPermanentWidget(this->KeyFramesLabel);
  this->statusBar()->addPermanentWidget(this->PointsLabel);
  this->statusBar()->addPermanentWidget(this->Progress);

  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::outputsUpdated, this, [this] {
    this->refreshViews();
    this->Registration->liveModelChanged();  // its count, an out-of-date notice, a reset
  });
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::scanStateChanged, this, [this](int state) {
    this->ModelView->setLiveUpdates(state == vtkTissueMosaicReconstructionLogic::StateRunning);
    // "Demo ready: press Start" and other hints about the state before must not outlive it.
    if (state == vtkTissueMosaicReconstructionLogic::StateRunning) this->statusBar()->clearMessage();
    this->refreshViews();
  });
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::demoRequested, this,
          &qTissueMosaicMainWindow::openDemo);
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::screenshotRequested, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save screenshot"), "tissuemosaic.png",
                                                      tr("PNG images (*.png)"));
    if (!path.isEmpty()) this->saveScreenshot(path);
  });

  connect(&this->Demo, &qTissueMosaicDemoInput::progress, this, [this](int written, int frames) {
    setProgressDeferred(this->Progress, frames, written, tr("demo: frame %v of %m"));
  });
  connect(&this->Demo, &qTissueMosaicDemoInput::finished, this, &qTissueMosaicMainWindow::onDemoFinished);

  this->setupMenus();
  this->updateStatusBar();
  // 1600x960 where the screen has room, else what it has (1280x800 and up must fit whole).
  QSize size(1600, 960);
  if (const QScreen* screen = QGuiApplication::primaryScreen()) {
    size = size.boundedTo(screen->availableGeometry().size());
  }
  this->resize(size);
}

qTissueMosaicMainWindow::~qTissueMosaicMainWindow() = default;

void qTissueMosaicMainWindow::setupMenus() {
  // Menu items act through the panel's buttons, so both do the same; updateActions() enables them alike.
  const auto clickButton = [this](const char* buttonName) {
    return [this, buttonName] {
      if (auto* button = this->Reconstruction->findChild<QAbstractButton*>(buttonName)) button->click();
    };
  };
  const auto named = [](QAction* action, const char* name) {
    action->setObjectName(name);
    return action;
  };
  QMenu* file = this->menuBar()->addMenu(tr("&File"));
  named(file->addAction(tr("Open &demo"), this, &qTissueMosaicMainWindow::openDemo), "openDemoAction")
      ->setShortcut(QKeySequence(tr("Ctrl+D")));
  named(file->addAction(tr("Open frame &folders..."), this, clickButton("openFoldersButton")), "openFoldersAction");
  named(file->addAction(tr("Open &video pair..."), this, clickButton("openVideoPairButton")), "openVideoPairAction");
  named(file->addAction(tr("Open &side-by-side video..."), this, clickButton("openSideBySideButton")),
        "openSideBySideAction");
  named(file->addAction(tr("Load &calibration..."), this, clickButton("loadCalibrationButton")),
        "loadCalibrationAction");
  file->addSeparator();
  named(file->addAction(tr("Export &model..."), this, clickButton("exportModelButton")), "exportModelAction");
  named(file->addAction(tr("Export &trajectory..."), this, clickButton("exportTrajectoryButton")),
        "exportTrajectoryAction");
  named(file->addAction(tr("Save scree&nshot..."), this, clickButton("screenshotButton")), "screenshotAction");
  file->addSeparator();
  named(file->addAction(tr("&Quit"), this, &QWidget::close), "quitAction")->setShortcut(QKeySequence::Quit);

  QMenu* scan = this->menuBar()->addMenu(tr("&Scan"));
  named(scan->addAction(tr("&Start / resume"), this, clickButton("startButton")), "startAction")
      ->setShortcut(QKeySequence(Qt::Key_F5));
  named(scan->addAction(tr("&Pause"), this, clickButton("pauseButton")), "pauseAction")
      ->setShortcut(QKeySequence(Qt::Key_F6));
  named(scan->addAction(tr("S&top"), this, clickButton("stopButton")), "stopAction");
  named(scan->addAction(tr("&Reset"), this, clickButton("resetButton")), "resetAction");

  QMenu* view = this->menuBar()->addMenu(tr("&View"));
  named(view->addAction(tr("&Reset 3D view"), this->ModelView, &qTissueMosaicModelView::resetView), "resetViewAction")
      ->setShortcut(QKeySequence(tr("Ctrl+R")));
  this->updateActions();
}

QAction* qTissueMosaicMainWindow::action(const QString& objectName) const {
  return this->findChild<QAction*>(objectName);
}

void qTissueMosaicMainWindow::updateActions() {
  // An item that cannot act is disabled, with the button's reason as its status tip.
  const std::pair<const char*, const char*> mirrored[] = {
      {"exportModelAction", "exportModelButton"}, {"exportTrajectoryAction", "exportTrajectoryButton"},
      {"startAction", "startButton"},             {"pauseAction", "pauseButton"},
      {"stopAction", "stopButton"},               {"resetAction", "resetButton"}};
  for (const auto& [actionName, buttonName] : mirrored) {
    QAction* menuAction = this->action(actionName);
    const auto* button = this->Reconstruction->findChild<QAbstractButton*>(buttonName);
    if (!menuAction || !button) continue;
    if (menuAction->isEnabled() != button->isEnabled()) menuAction->setEnabled(button->isEnabled());
  }
}

void qTissueMosaicMainWindow::showModule(int index) {
  // The registration scene takes the view area while its module is active; back on Reconstruction, the model
  // view and the video return as they were.
  const bool registration = this->Modules->widget(index) && this->Modules->tabText(index) == tr("Registration");
  this->Views->setCurrentIndex(registration ? 1 : 0);
  if (registration) {
    this->Registration->liveModelChanged();
    this->Registration->sceneView()->render();
  } else {
    this->ModelView->requestRender();
  }
}

void qTissueMosaicMainWindow::closeEvent(QCloseEvent* event) {
  if (this->ConfirmUnsavedModel && this->Reconstruction->hasUnexportedModel()) {
    const long long points = this->Reconstruction->reconstructionLogic()->GetModel()->GetNumberOfPoints();
    QMessageBox question(QMessageBox::Question, tr("Quit TissueMosaic"),
                         tr("The model (%1) has not been exported. Quit and discard it?").arg(pointCountText(points)),
                         QMessageBox::NoButton, this);
    question.setObjectName("unsavedModelQuestion");
    QPushButton* exportFirst = question.addButton(tr("Export model..."), QMessageBox::AcceptRole);
    QPushButton* discard = question.addButton(tr("Quit without exporting"), QMessageBox::DestructiveRole);
    QPushButton* cancel = question.addButton(QMessageBox::Cancel);
    question.setDefaultButton(cancel);
    question.exec();
    if (question.clickedButton() == exportFirst) {
      const QString path = QFileDialog::getSaveFileName(this, tr("Export model"), "model.ply",
                                                        tr("PLY (*.ply);;VTK XML PolyData for Slicer (*.vtp)"));
      if (path.isEmpty() || !this->Reconstruction->exportModel(path)) {
        event->ignore();  // not exported: stay, the panel says why
        return;
      }
    } else if (question.clickedButton() != discard) {
      event->ignore();
      return;
    }
  }
  this->Reconstruction->stop();
  QMainWindow::closeEvent(event);
}

QString qTissueMosaicMainWindow::demoDirectory() const {
  return this->DemoDirectory ? this->DemoDirectory->path() : QString();
}

void qTissueMosaicMainWindow::openDemo() {
  if (this->Demo.isRunning()) return;
  this->Reconstruction->reset();
  this->DemoDirectory = std::make_unique<QTemporaryDir>(QDir::tempPath() + "/tissuemosaic-demo-XXXXXX");
  if (!this->DemoDirectory->isValid()) {
    this->statusBar()->showMessage(tr("Cannot create a temporary folder for the demo"));
    emit demoOpened(false);
    return;
  }
  this->statusBar()->showMessage(tr("Generating the demo scan (%1 frames, %2x%3 px)...")
                                     .arg(this->DemoOptions.frames)
                                     .arg(this->DemoOptions.width)
                                     .arg(this->DemoOptions.height));
  this->Demo.start(this->DemoDirectory->path(), this->DemoOptions);
}

void qTissueMosaicMainWindow::onDemoFinished(bool ok, const QString& directory, const QString& errorText) {
  this->statusBar()->clearMessage();  // "Generating the demo scan...": done; the panel says what follows
  if (ok) {
    // The synthetic frames are rendered with the rectified cameras of rig.yml: they are already rectified.
    ok = this->Reconstruction->loadCalibration(qTissueMosaicDemoInput::calibrationFile(directory));
    this->Reconstruction->setInputRectified(true);
    ok = ok && this->Reconstruction->openFrameFolders(qTissueMosaicDemoInput::leftFolder(directory),
                                                      qTissueMosaicDemoInput::rightFolder(directory));
    if (ok) {
      this->Reconstruction->showMessage(tr("Demo ready: press Start (F5)"), false,
                                        qTissueMosaicReconstructionWidget::InputMessage);
    }
  } else {
    this->Reconstruction->showMessage(tr("The demo could not be generated: %1").arg(errorText), true,
                                      qTissueMosaicReconstructionWidget::InputMessage);
  }
  this->updateStatusBar();
  emit demoOpened(ok);
}

void qTissueMosaicMainWindow::refreshViews() {
  vtkTissueMosaicReconstructionLogic* logic = this->Reconstruction->reconstructionLogic();
  const int frame = logic->GetStatus().lastFrameIndex;
  if (logic->GetLeftFrame().empty()) {
    if (this->ShownFrameIndex != -1) this->VideoPanel->clear();
    this->ShownFrameIndex = -1;
  } else if (frame != this->ShownFrameIndex) {
    this->ShownFrameIndex = frame;
    const auto& stereo = logic->GetParameters().stereo;
    this->VideoPanel->setFrames(logic->GetLeftFrame(), logic->GetRightFrame(), logic->GetDisparityPx(),
                                logic->GetScanGeometry(), stereo.minDisparityPx, stereo.maxDisparityPx);
  }
  this->ModelView->requestRender();
  this->updateStatusBar();
}

void qTissueMosaicMainWindow::updateStatusBar() {
  using Logic = vtkTissueMosaicReconstructionLogic;
  Logic* logic = this->Reconstruction->reconstructionLogic();
  const auto& status = logic->GetStatus();
  const int state = logic->GetScanState();
  static_cast<ElidedLabel*>(this->TrackingLabel)->setFullText(QString::fromStdString(logic->GetTrackingStateText()));
  // Lost tracking must catch the eye.
  const QString trackingStyle = status.framesProcessed > 0 && !status.tracked
                                    ? "QLabel { color: white; background: #c62828; padding: 1px 6px; }"
                                    : "QLabel { padding: 1px 6px; }";
  if (this->TrackingLabel->styleSheet() != trackingStyle) this->TrackingLabel->setStyleSheet(trackingStyle);
  // A rate only while frames flow; the scan's average once it has ended.
  QString fps = tr("- fps");
  if (state == Logic::StateRunning) fps = tr("%1 fps").arg(status.framesPerSecond, 0, 'f', 1);
  else if (state == Logic::StatePaused) fps = tr("paused");
  else if (status.framesProcessed > 0) fps = tr("%1 fps average").arg(status.framesPerSecond, 0, 'f', 1);
  this->FpsLabel->setText(fps);
  this->KeyFramesLabel->setText(tr("%1 key frames").arg(status.keyFrames));
  this->PointsLabel->setText(pointCountText(status.modelPoints));
  if (!this->Demo.isRunning()) {
    // Before a scan the input's own length (a newly opened input's, not the last scan's).
    const int total = state == Logic::StateIdle ? logic->GetInputFrameCount()
                      : status.framesInInput > 0 ? status.framesInInput
                                                 : logic->GetInputFrameCount();
    setProgressDeferred(this->Progress, std::max(total, 1), std::min(status.framesProcessed, std::max(total, 1)),
                        total > 0 ? tr("frame %v / %m") : tr("%v frames"));
  }
  this->updateActions();
}

QString qTissueMosaicMainWindow::statusText() const {
  return QStringList{static_cast<ElidedLabel*>(this->TrackingLabel)->fullText(), this->FpsLabel->text(), this->KeyFramesLabel->text(),
                     this->PointsLabel->text(), this->Progress->text()}
      .join(" | ");
}

bool qTissueMosaicMainWindow::saveScreenshot(const QString& path) {
  this->ModelView->renderFullModel();
  // grab() composes the OpenGL views (QOpenGLWidget) with the other widgets.
  const QPixmap picture = this->grab();
  const QFileInfo file(path);
  QString reason;
  if (picture.isNull()) reason = tr("the window could not be captured");
  else if (!file.dir().exists()) reason = tr("the folder %1 does not exist").arg(file.dir().path());
  else if (!picture.save(path, "PNG")) reason = tr("the file cannot be written there (is the folder writable?)");
  if (reason.isEmpty()) this->Reconstruction->showMessage(tr("Screenshot written to %1").arg(path), false);
  else this->Reconstruction->showMessage(tr("The screenshot was not saved: %1.").arg(reason), true);
  return reason.isEmpty();
}
