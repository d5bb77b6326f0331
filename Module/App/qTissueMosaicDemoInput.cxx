#include "qTissueMosaicDemoInput.h"

#include "SyntheticScan.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include "Core/Error.h"

#include <QDir>

#include <mutex>

/// Shared with the generator thread.
struct qTissueMosaicDemoInput::State {
  std::atomic<int> written{0};
  std::atomic<int> frames{0};
  std::atomic<bool> done{false};
  std::atomic<bool> cancelled{false};
  std::mutex mutex;
  std::string errorText;  ///< guarded by mutex
};

namespace {

// writeSyntheticScan takes a plain function pointer: the generator's state is reached through this slot, which
// only one generation uses at a time (start() refuses a second).
std::atomic<qTissueMosaicDemoInput::State*>* currentState() {
  static std::atomic<qTissueMosaicDemoInput::State*> state{nullptr};
  return &state;
}

void onFrameWritten(int frame, int frames) {
  qTissueMosaicDemoInput::State* state = currentState()->load();
  if (!state) return;
  state->written = frame + 1;
  state->frames = frames;
  if (state->cancelled) throw tissuemosaic::Error("the demo generation was cancelled");
}

}  // namespace

qTissueMosaicDemoInput::qTissueMosaicDemoInput(QObject* parent) : QObject(parent) {
  connect(&this->PollTimer, &QTimer::timeout, this, &qTissueMosaicDemoInput::poll);
}

qTissueMosaicDemoInput::~qTissueMosaicDemoInput() {
  this->cancel();
  if (this->Thread.joinable()) this->Thread.join();
}

QString qTissueMosaicDemoInput::leftFolder(const QString& directory) { return QDir(directory).filePath("left"); }
QString qTissueMosaicDemoInput::rightFolder(const QString& directory) { return QDir(directory).filePath("right"); }
QString qTissueMosaicDemoInput::calibrationFile(const QString& directory) { return QDir(directory).filePath("rig.yml"); }

bool qTissueMosaicDemoInput::isRunning() const { return this->State_ && !this->State_->done; }

void qTissueMosaicDemoInput::cancel() {
  if (this->State_) this->State_->cancelled = true;
}

bool qTissueMosaicDemoInput::start(const QString& directory, const Options& options) {
  if (this->isRunning()) return false;
  if (this->Thread.joinable()) this->Thread.join();
  this->Directory = directory;
  this->State_ = std::make_shared<State>();
  this->State_->frames = options.frames;
  std::shared_ptr<State> state = this->State_;
  const std::string folder = directory.toStdString();
  this->Thread = std::thread([state, folder, options] {
    vtkTissueMosaicReconstructionLogic::LowerCurrentThreadPriority(5);  // background work: the GUI comes first
    std::string errorText;
    try {
      tissuemosaic::synthetic::SyntheticScanOptions scanOptions;
      scanOptions.width = options.width;
      scanOptions.height = options.height;
      scanOptions.frames = options.frames;
      scanOptions.seed = options.seed;
      const tissuemosaic::synthetic::SyntheticScan scan(scanOptions);
      currentState()->store(state.get());
      tissuemosaic::synthetic::writeSyntheticScan(scan, folder, &onFrameWritten);
    } catch (const std::exception& error) {
      errorText = error.what();
    }
    currentState()->store(nullptr);
    {
      const std::lock_guard<std::mutex> lock(state->mutex);
      state->errorText = errorText;
    }
    state->done = true;
  });
  this->PollTimer.start(100);
  return true;
}

void qTissueMosaicDemoInput::poll() {
  if (!this->State_) return;
  emit progress(this->State_->written, this->State_->frames);
  if (!this->State_->done) return;
  this->PollTimer.stop();
  this->Thread.join();
  QString errorText;
  {
    const std::lock_guard<std::mutex> lock(this->State_->mutex);
    errorText = QString::fromStdString(this->State_->errorText);
  }
  emit finished(errorText.isEmpty(), this->Directory, errorText);
}
