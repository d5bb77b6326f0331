#pragma once
/// @class qTissueMosaicReconstructionWidget
/// @brief The "Reconstruction" module panel: input (a video, two frame folders, the demo) and calibration, scan
/// control (start, pause, stop, reset), export (model, trajectory, screenshot), the parameter panel and the
/// paper's runtime table. It owns the vtkTissueMosaicReconstructionLogic and polls it on a timer (30 Hz): the
/// engine runs on the logic's worker thread, the GUI thread only takes over finished results, so the interface
/// never waits for a frame. Views (3D, video) connect to outputsUpdated().
#include <QScopedPointer>
#include <QStringList>
#include <QWidget>

class QTableWidget;
class qTissueMosaicReconstructionParametersWidget;
class qTissueMosaicReconstructionWidgetPrivate;
class vtkTissueMosaicReconstructionLogic;

class qTissueMosaicReconstructionWidget : public QWidget {
  Q_OBJECT
public:
  /// Where a message appears: under the input, the scan or the export controls.
  enum MessagePlace { InputMessage, ScanMessage, ExportMessage };

  explicit qTissueMosaicReconstructionWidget(QWidget* parent = nullptr);
  ~qTissueMosaicReconstructionWidget() override;

  /// The logic (owned by the panel).
  vtkTissueMosaicReconstructionLogic* reconstructionLogic() const;
  qTissueMosaicReconstructionParametersWidget* parametersPanel() const;
  /// Rows: the paper's stages; columns: last frame, key-frame median, key-frame mean, other-frame median (ms).
  QTableWidget* timingTable() const;
  /// The last message shown to the user (errors and confirmations).
  QString lastMessage() const;
  /// Why Start is disabled (no input, a calibration for another frame size, a parameter refused, ...); empty when
  /// it can start. Shown beside the Start button.
  QString startProblem() const;
  /// True when the model holds points that no export has written since they changed.
  bool hasUnexportedModel() const;
  /// How often the logic is polled (default 33 ms).
  void setPollingIntervalMs(int intervalMs);

public slots:
  bool openFrameFolders(const QString& leftFolder, const QString& rightFolder, double fps = 30.0);
  bool openVideoPair(const QString& leftVideo, const QString& rightVideo);
  bool openSideBySideVideo(const QString& video);
  /// A 3D video file, device or GStreamer pipeline with the eyes packed as `layout` (sbs, sbs-half, tb, tb-half,
  /// rows).
  bool openStereoVideo(const QString& video, const QString& layout);
  bool loadCalibration(const QString& path);
  /// One or two files in any order (intrinsics + extrinsics, or each eye's ROS camera_info).
  bool loadCalibrationFiles(const QStringList& paths);
  void setInputRectified(bool rectified);
  bool start();
  void pause();
  void stop();
  void reset();
  bool exportModel(const QString& path);
  bool exportTrajectory(const QString& path);
  /// Shows a message where the action was (error: in red).
  void showMessage(const QString& text, bool error, MessagePlace place = ExportMessage);
  /// Takes over the logic's new results and refreshes the controls; emits outputsUpdated() when there were any.
  /// Called by the polling timer; call it directly to update at once.
  bool updateFromLogic();

signals:
  /// The logic's outputs changed (model, frusta, frames, status): views redraw.
  void outputsUpdated();
  /// The scan state changed (idle, running, paused, finished, stopped, failed).
  void scanStateChanged(int state);
  /// The user asked for the bundled demo input (the application generates it).
  void demoRequested();
  /// The user asked for a screenshot of the application.
  void screenshotRequested();
  /// A message for the user (error: shown in red).
  void message(const QString& text, bool error);

protected:
  QScopedPointer<qTissueMosaicReconstructionWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qTissueMosaicReconstructionWidget);
  Q_DISABLE_COPY(qTissueMosaicReconstructionWidget);
};
