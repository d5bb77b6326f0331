#pragma once
/// @class qTissueMosaicDemoInput
/// @brief The bundled demo input: a synthetic stereo-endoscope scan of liver-like tissue (Logic/Synthetic,
/// exact ground truth), written as rectified frame folders + rig.yml (+ groundtruth/) into a folder, on a worker
/// thread so that the interface stays live. Progress and the end are reported by signals on the GUI thread.
#include <QObject>
#include <QString>
#include <QTimer>

#include <atomic>
#include <memory>
#include <thread>

class qTissueMosaicDemoInput : public QObject {
  Q_OBJECT
public:
  struct Options {
    int width = 480, height = 270;  ///< small, so that the demo runs fast on a CPU
    int frames = 60;
    unsigned seed = 1;
  };

  explicit qTissueMosaicDemoInput(QObject* parent = nullptr);
  ~qTissueMosaicDemoInput() override;  ///< waits for the generator (a frame at most after cancel())

  /// Starts writing the demo into `directory` (created). False when a generation is already running.
  bool start(const QString& directory, const Options& options);
  bool isRunning() const;
  /// Stops after the current frame; finished() then reports failure.
  void cancel();

  /// The demo's folders in `directory`.
  static QString leftFolder(const QString& directory);
  static QString rightFolder(const QString& directory);
  static QString calibrationFile(const QString& directory);

  struct State;  ///< shared with the generator thread (defined in the .cxx)

signals:
  void progress(int framesWritten, int frames);
  /// ok: the folders are complete; else errorText says why.
  void finished(bool ok, const QString& directory, const QString& errorText);

private:
  void poll();

  std::shared_ptr<State> State_;
  std::thread Thread;
  QTimer PollTimer;
  QString Directory;
};
