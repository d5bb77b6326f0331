#pragma once
/// @class qTissueMosaicMainWindow
/// @brief The desktop application's window, laid out like 3D Slicer: the module panel on the left (tabs
/// "Reconstruction" and "Registration"), the views on the right (the 3D model view above the live video), a status
/// bar (frame rate, key frames, points, tracking state) with a progress bar, and menus for every action.
#include "qTissueMosaicDemoInput.h"

#include <QMainWindow>
#include <QTemporaryDir>

#include <memory>

class QLabel;
class QProgressBar;
class QTabWidget;
class qTissueMosaicModelView;
class qTissueMosaicReconstructionWidget;
class qTissueMosaicRegistrationWidget;
class qTissueMosaicVideoPanel;

class qTissueMosaicMainWindow : public QMainWindow {
  Q_OBJECT
public:
  explicit qTissueMosaicMainWindow(QWidget* parent = nullptr);
  ~qTissueMosaicMainWindow() override;

  qTissueMosaicReconstructionWidget* reconstructionPanel() const { return this->Reconstruction; }
  qTissueMosaicRegistrationWidget* registrationPanel() const { return this->Registration; }
  qTissueMosaicModelView* modelView() const { return this->ModelView; }
  qTissueMosaicVideoPanel* videoPanel() const { return this->VideoPanel; }
  QTabWidget* moduleTabs() const { return this->Modules; }

  /// Size and length of the demo scan that "Open demo" generates.
  void setDemoOptions(const qTissueMosaicDemoInput::Options& options) { this->DemoOptions = options; }
  /// The folder the last demo was written to (a temporary folder, removed with the window), empty before.
  QString demoDirectory() const;
  bool isDemoBeingGenerated() const { return this->Demo.isRunning(); }

  /// The status bar's texts, for tests and logs: "12.3 fps", "5 key frames", "1.2 M points", tracking state.
  QString statusText() const;

public slots:
  /// Generates the demo scan in a temporary folder (on a worker thread), then opens it (frames, rig.yml,
  /// rectified). demoOpened() follows.
  void openDemo();
  /// A PNG picture of the whole window (module panel, 3D view with its OpenGL content, video, status bar).
  bool saveScreenshot(const QString& path);
  void refreshViews();

signals:
  void demoOpened(bool ok);

private:
  void setupMenus();
  void updateStatusBar();
  void onDemoFinished(bool ok, const QString& directory, const QString& errorText);

  QTabWidget* Modules = nullptr;
  qTissueMosaicReconstructionWidget* Reconstruction = nullptr;
  qTissueMosaicRegistrationWidget* Registration = nullptr;
  qTissueMosaicModelView* ModelView = nullptr;
  qTissueMosaicVideoPanel* VideoPanel = nullptr;
  QLabel* FpsLabel = nullptr;
  QLabel* KeyFramesLabel = nullptr;
  QLabel* PointsLabel = nullptr;
  QLabel* TrackingLabel = nullptr;
  QProgressBar* Progress = nullptr;
  qTissueMosaicDemoInput Demo;
  qTissueMosaicDemoInput::Options DemoOptions;
  std::unique_ptr<QTemporaryDir> DemoDirectory;
  int ShownFrameIndex = -1;
};
