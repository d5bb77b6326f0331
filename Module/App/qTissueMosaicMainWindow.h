#pragma once
/// @class qTissueMosaicMainWindow
/// @brief The desktop application's window, laid out like 3D Slicer: the module panel on the left (tabs
/// "Reconstruction" and "Registration", controls only), the view area on the right, which each module switches to
/// what its task needs (Reconstruction: the 3D model view above the live video; Registration: the registration
/// scene), a status bar (frame rate, key frames, points, tracking state) with a progress bar, and menus for every
/// action, enabled only when they can act. It fits screens from 1280x800 up. Closing it with a model that was
/// never exported asks first.
#include "qTissueMosaicDemoInput.h"

#include <QMainWindow>
#include <QTemporaryDir>

#include <memory>

class QAction;
class QLabel;
class QProgressBar;
class QStackedWidget;
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
  /// The view area: page 0 the reconstruction views, page 1 the registration scene.
  QStackedWidget* viewArea() const { return this->Views; }
  /// A menu action by object name ("exportModelAction", "startAction", ...), for tests.
  QAction* action(const QString& objectName) const;
  /// Ask before closing when the model was not exported (default on; off for batch runs).
  void setConfirmUnsavedModel(bool confirm) { this->ConfirmUnsavedModel = confirm; }

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
  /// A PNG picture of the whole window (module panel, 3D view with its OpenGL content, video, status bar). The
  /// reconstruction panel says where it went, or why it could not be written.
  bool saveScreenshot(const QString& path);
  void refreshViews();

signals:
  void demoOpened(bool ok);

protected:
  void closeEvent(QCloseEvent* event) override;

private:
  void setupMenus();
  void updateStatusBar();
  void updateActions();
  void showModule(int index);
  void onDemoFinished(bool ok, const QString& directory, const QString& errorText);

  QTabWidget* Modules = nullptr;
  QStackedWidget* Views = nullptr;
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
  bool ConfirmUnsavedModel = true;
};
