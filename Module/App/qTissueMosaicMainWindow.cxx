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

#include <QAction>
#include <QApplication>
#include <QDir>
#include <QFileDialog>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QPixmap>
#include <QProgressBar>
#include <QScrollArea>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>

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

}  // namespace

qTissueMosaicMainWindow::qTissueMosaicMainWindow(QWidget* parent) : QMainWindow(parent) {
  this->setWindowTitle(tr("TissueMosaic: dense tissue surface reconstruction from stereo video"));
  this->setObjectName("tissueMosaicMainWindow");

  // Module panel (left), as in 3D Slicer.
  this->Modules = new QTabWidget(this);
  this->Modules->setObjectName("moduleTabs");
  this->Reconstruction = new qTissueMosaicReconstructionWidget(this);
  this->Reconstruction->setObjectName("reconstructionPanel");
  auto* scroll = new QScrollArea(this);
  scroll->setWidget(this->Reconstruction);
  scroll->setWidgetResizable(true);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  this->Modules->addTab(scroll, tr("Reconstruction"));
  this->Registration = new qTissueMosaicRegistrationWidget(this);
  this->Registration->setObjectName("registrationPanel");
  this->Registration->setReconstructedModel(this->Reconstruction->reconstructionLogic()->GetModel());
  this->Modules->addTab(this->Registration, tr("Registration"));
#if defined(TM_WITH_IGTLINK)
  // The OpenIGTLink link to 3D Slicer: streams the running scan while its server is on.
  auto* igtLink = new qTissueMosaicIgtLinkWidget(this);
  igtLink->setObjectName("igtLinkPanel");
  this->Reconstruction->reconstructionLogic()->SetScanObserver(igtLink->scanObserver());
  this->Modules->addTab(igtLink, tr("OpenIGTLink"));
#endif
  this->Modules->setMinimumWidth(500);

  // Views (right): the growing model above the live video.
  this->ModelView = new qTissueMosaicModelView(this);
  this->ModelView->setObjectName("modelView");
  this->ModelView->setReconstructionLogic(this->Reconstruction->reconstructionLogic());
  this->VideoPanel = new qTissueMosaicVideoPanel(this);
  this->VideoPanel->setObjectName("videoPanel");
  auto* views = new QSplitter(Qt::Vertical, this);
  views->addWidget(this->ModelView);
  views->addWidget(this->VideoPanel);
  views->setStretchFactor(0, 3);
  views->setStretchFactor(1, 1);
  views->setSizes({640, 260});  // the model first; the video strip below (frames are wide, 16:9)
  views->setCollapsible(0, false);
  auto* main = new QSplitter(Qt::Horizontal, this);
  main->addWidget(this->Modules);
  main->addWidget(views);
  main->setStretchFactor(0, 0);
  main->setStretchFactor(1, 1);
  main->setSizes({510, 1090});
  main->setCollapsible(1, false);
  this->setCentralWidget(main);

  // Status bar: what a surgeon glances at.
  this->TrackingLabel = new QLabel(this);
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

  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::outputsUpdated, this,
          &qTissueMosaicMainWindow::refreshViews);
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::scanStateChanged, this, [this](int state) {
    this->ModelView->setLiveUpdates(state == vtkTissueMosaicReconstructionLogic::StateRunning);
    this->refreshViews();
  });
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::demoRequested, this,
          &qTissueMosaicMainWindow::openDemo);
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::screenshotRequested, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save screenshot"), "tissuemosaic.png",
                                                      tr("PNG images (*.png)"));
    if (!path.isEmpty()) this->saveScreenshot(path);
  });
  connect(this->Reconstruction, &qTissueMosaicReconstructionWidget::message, this, [this](const QString& text, bool) {
    this->statusBar()->showMessage(text, 8000);
  });
  connect(&this->Demo, &qTissueMosaicDemoInput::progress, this, [this](int written, int frames) {
    setProgressDeferred(this->Progress, frames, written, tr("demo: frame %v of %m"));
  });
  connect(&this->Demo, &qTissueMosaicDemoInput::finished, this, &qTissueMosaicMainWindow::onDemoFinished);

  this->setupMenus();
  this->updateStatusBar();
  this->resize(1600, 960);
}

qTissueMosaicMainWindow::~qTissueMosaicMainWindow() = default;

void qTissueMosaicMainWindow::setupMenus() {
  QMenu* file = this->menuBar()->addMenu(tr("&File"));
  QAction* demo = file->addAction(tr("Open &demo"), this, &qTissueMosaicMainWindow::openDemo);
  demo->setShortcut(QKeySequence(tr("Ctrl+D")));
  demo->setObjectName("openDemoAction");
  file->addAction(tr("Open frame &folders..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("openFoldersButton"), "click");
  });
  file->addAction(tr("Open &video pair..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("openVideoPairButton"), "click");
  });
  file->addAction(tr("Open &side-by-side video..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("openSideBySideButton"), "click");
  });
  file->addAction(tr("Load &calibration..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("loadCalibrationButton"), "click");
  });
  file->addSeparator();
  file->addAction(tr("Export &model..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("exportModelButton"), "click");
  });
  file->addAction(tr("Export &trajectory..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("exportTrajectoryButton"), "click");
  });
  file->addAction(tr("Save scree&nshot..."), this, [this] {
    QMetaObject::invokeMethod(this->Reconstruction->findChild<QWidget*>("screenshotButton"), "click");
  });
  file->addSeparator();
  file->addAction(tr("&Quit"), this, &QWidget::close)->setShortcut(QKeySequence::Quit);

  QMenu* scan = this->menuBar()->addMenu(tr("&Scan"));
  scan->addAction(tr("&Start / resume"), this->Reconstruction, &qTissueMosaicReconstructionWidget::start)
      ->setShortcut(QKeySequence(Qt::Key_F5));
  scan->addAction(tr("&Pause"), this->Reconstruction, &qTissueMosaicReconstructionWidget::pause)
      ->setShortcut(QKeySequence(Qt::Key_F6));
  scan->addAction(tr("S&top"), this->Reconstruction, &qTissueMosaicReconstructionWidget::stop);
  scan->addAction(tr("&Reset"), this->Reconstruction, &qTissueMosaicReconstructionWidget::reset);

  QMenu* view = this->menuBar()->addMenu(tr("&View"));
  view->addAction(tr("&Reset 3D view"), this->ModelView, &qTissueMosaicModelView::resetView)
      ->setShortcut(QKeySequence(tr("Ctrl+R")));
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
  if (ok) {
    // The synthetic frames are rendered with the rectified cameras of rig.yml: they are already rectified.
    ok = this->Reconstruction->loadCalibration(qTissueMosaicDemoInput::calibrationFile(directory));
    this->Reconstruction->setInputRectified(true);
    ok = ok && this->Reconstruction->openFrameFolders(qTissueMosaicDemoInput::leftFolder(directory),
                                                      qTissueMosaicDemoInput::rightFolder(directory));
    if (ok) this->statusBar()->showMessage(tr("Demo ready: press Start (F5)"), 8000);
  } else {
    this->statusBar()->showMessage(tr("The demo could not be generated: %1").arg(errorText));
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
    this->VideoPanel->setFrames(logic->GetLeftFrame(), logic->GetRightFrame(), logic->GetDisparityColorImage());
  }
  this->ModelView->requestRender();
  this->updateStatusBar();
}

void qTissueMosaicMainWindow::updateStatusBar() {
  vtkTissueMosaicReconstructionLogic* logic = this->Reconstruction->reconstructionLogic();
  const auto& status = logic->GetStatus();
  this->TrackingLabel->setText(QString::fromStdString(logic->GetTrackingStateText()));
  // Lost tracking must catch the eye.
  const QString trackingStyle = status.framesProcessed > 0 && !status.tracked
                                    ? "QLabel { color: white; background: #c62828; padding: 1px 6px; }"
                                    : "QLabel { padding: 1px 6px; }";
  if (this->TrackingLabel->styleSheet() != trackingStyle) this->TrackingLabel->setStyleSheet(trackingStyle);
  this->FpsLabel->setText(tr("%1 fps").arg(status.framesPerSecond, 0, 'f', 1));
  this->KeyFramesLabel->setText(tr("%1 key frames").arg(status.keyFrames));
  this->PointsLabel->setText(pointCountText(status.modelPoints));
  if (!this->Demo.isRunning()) {
    const int total = status.framesInInput > 0 ? status.framesInInput : logic->GetInputFrameCount();
    setProgressDeferred(this->Progress, std::max(total, 1), std::min(status.framesProcessed, std::max(total, 1)),
                        total > 0 ? tr("frame %v / %m") : tr("%v frames"));
  }
}

QString qTissueMosaicMainWindow::statusText() const {
  return QStringList{this->TrackingLabel->text(), this->FpsLabel->text(), this->KeyFramesLabel->text(),
                     this->PointsLabel->text(), this->Progress->text()}
      .join(" | ");
}

bool qTissueMosaicMainWindow::saveScreenshot(const QString& path) {
  this->ModelView->renderFullModel();
  // grab() composes the OpenGL views (QOpenGLWidget) with the other widgets.
  const QPixmap picture = this->grab();
  const bool ok = !picture.isNull() && picture.save(path, "PNG");
  this->statusBar()->showMessage(ok ? tr("Screenshot written to %1").arg(path)
                                    : tr("Cannot write the screenshot %1").arg(path),
                                 8000);
  return ok;
}
