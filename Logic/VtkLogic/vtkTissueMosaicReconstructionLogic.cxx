#include "vtkTissueMosaicReconstructionLogic.h"

#include "IO/AtomicFile.h"
#include "IO/Calibration/CalibrationFile.h"
#include "vtkTissueMosaicDisparityColours.h"
#include "vtkTissueMosaicRunCatching.h"

#include "vtkTissueMosaicFrusta.h"
#include "vtkTissueMosaicGrowingModel.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/Stopwatch.h"
#include "IO/Calibration/CalibrationFile.h"
#include "IO/PointCloudPly.h"
#include "IO/StereoFrameSource.h"
#include "IO/TrajectoryTum.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "Reconstruction/TimingTable.h"

#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#endif

vtkStandardNewMacro(vtkTissueMosaicReconstructionLogic);

using tissuemosaic::FrameResult;
using tissuemosaic::KeyFramePose;
using tissuemosaic::ModelPoints;
using tissuemosaic::ReconstructionParameters;
using tissuemosaic::ReconstructionPipeline;
using tissuemosaic::StageTimesMs;
using tissuemosaic::StereoFrameSource;
using tissuemosaic::runCatching;

namespace {

using Clock = std::chrono::steady_clock;

/// One processed frame as the owner keeps it.
struct FrameRecord {
  int frameIndex = 0;
  double timeS = 0;
  bool tracked = false;
  bool keyFrame = false;
  std::string message;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  StageTimesMs timesMs;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using FrameRecords = std::vector<FrameRecord, Eigen::aligned_allocator<FrameRecord>>;

void lowerThisThreadsPriority(int niceIncrement) {
  vtkTissueMosaicReconstructionLogic::LowerCurrentThreadPriority(niceIncrement);
}

}  // namespace

void vtkTissueMosaicReconstructionLogic::LowerCurrentThreadPriority(int niceIncrement) {
#ifdef __linux__
  if (niceIncrement <= 0) return;
  const id_t thread = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int current = getpriority(PRIO_PROCESS, thread);
  if (errno == 0) setpriority(PRIO_PROCESS, thread, std::min(current + niceIncrement, 19));
#else
  (void)niceIncrement;
#endif
}

/// What the worker hands over; guarded by Session::mutex. Every member is moved out by the owner.
struct vtkTissueMosaicReconstructionLogic::Results {
  std::optional<ModelPoints> model;                 ///< set after each key frame: the whole current model
  std::optional<tissuemosaic::ModelArrays> modelArrays;  ///< the same as VTK arrays, made on the worker
  std::optional<std::vector<KeyFramePose>> keyFrames;  ///< set after each key frame (poses may be refined)
  FrameRecords frames;                              ///< frames processed since the last hand-over
  cv::Mat left, right, disparityPx;                 ///< the latest frame (its own copies)
  std::optional<tissuemosaic::RectifiedGeometry> geometry;  ///< once the pipeline exists
  ScanStatus status;
  tissuemosaic::TimingTable timing;                 ///< owner only: every frame so far
};

/// One scan: the input, the pipeline and the worker thread that runs them.
struct vtkTissueMosaicReconstructionLogic::Session {
  // Set by Start() before the thread runs, then used by the worker only.
  std::unique_ptr<StereoFrameSource> source;
  std::optional<tissuemosaic::StereoCalibration> calibration;  ///< raw rig: the pipeline rectifies
  std::optional<tissuemosaic::RectifiedGeometry> geometry;     ///< rectified input
  ReconstructionParameters parameters;
  tissuemosaic::Device device = tissuemosaic::Device::Cpu;
  int maximumFrames = -1;
  int workerNiceIncrement = 0;
  ScanObserver observer;

  std::mutex mutex;
  std::condition_variable wake;
  bool paused = false;          ///< guarded by mutex
  bool stopRequested = false;   ///< guarded by mutex
  bool ended = false;           ///< guarded by mutex
  Results published;            ///< guarded by mutex
  std::vector<tissuemosaic::ModelArrays> retired;  ///< guarded by mutex: replaced arrays, released by the worker
  std::atomic<int> state{StateRunning};
  std::thread thread;

  void run();
  void publishEnd(int endState, const std::string& errorText);
};

void vtkTissueMosaicReconstructionLogic::Session::run() {
  lowerThisThreadsPriority(workerNiceIncrement);
  std::string errorText;
  int endState = StateFinished;
  std::unique_ptr<ReconstructionPipeline> pipeline;
  double lastTimeS = 0;
  const bool ranToEnd = runCatching(
      [&] {
        pipeline = geometry ? std::make_unique<ReconstructionPipeline>(*geometry, parameters, device)
                            : std::make_unique<ReconstructionPipeline>(*calibration, parameters, device);
        {
          const std::lock_guard<std::mutex> lock(mutex);
          published.geometry = pipeline->geometry();
          published.status.device = tissuemosaic::deviceLabel(device);
        }
        std::deque<Clock::time_point> recentFrameEnds;
        int processed = 0;
        double busyS = 0;
        for (;;) {
          {
            std::unique_lock<std::mutex> lock(mutex);
            wake.wait(lock, [&] { return !paused || stopRequested; });
            if (stopRequested) {
              endState = StateStopped;
              return;
            }
          }
          if (maximumFrames >= 0 && processed >= maximumFrames) return;
          const Clock::time_point start = Clock::now();
          tissuemosaic::StereoFrame frame;
          if (!source->next(frame)) {
            const std::lock_guard<std::mutex> lock(mutex);
            if (stopRequested) endState = StateStopped;  // a live source's wait was interrupted
            return;
          }
          const double readingMs = tissuemosaic::millisecondsSince(start);
          FrameResult result = pipeline->process(frame.left, frame.right, frame.timeS);
          result.timesMs.videoReading += readingMs;  // the pipeline counts its rectification here
          result.timesMs.total += readingMs;  // the paper's total includes reading the video
          lastTimeS = frame.timeS;
          if (observer.frameProcessed) observer.frameProcessed(result, frame.timeS, *pipeline);

          std::optional<ModelPoints> model;
          std::optional<tissuemosaic::ModelArrays> modelArrays;
          std::optional<std::vector<KeyFramePose>> keyFrames;
          // The model changes at key frames (fusion) and where motion evidence removed points (any tracked frame);
          // while it deforms, at every fitted frame: the view shows it where the tissue is now (the live model).
          if (result.keyFrame || result.pointsRemoved > 0 || result.deformation.fitted) {
            model = pipeline->liveModelSnapshot();
            // Double buffering: the owner swaps these in without touching the model's memory.
            modelArrays = tissuemosaic::makeModelArrays(model->cloud);
            keyFrames = pipeline->keyFrames();
          }
          FrameRecord record;
          record.frameIndex = result.frameIndex;
          record.timeS = frame.timeS;
          record.tracked = result.tracked;
          record.keyFrame = result.keyFrame;
          record.message = result.trackingMessage;
          record.T_world_camera = result.T_world_camera;
          record.timesMs = result.timesMs;
          // Own copies: the pipeline may reuse its buffers for the next frame while the owner still shows these.
          cv::Mat left = result.leftRectified.clone(), right = result.rightRectified.clone();
          cv::Mat disparity = result.disparityPx.clone();

          ++processed;
          const Clock::time_point end = Clock::now();
          busyS += std::chrono::duration<double>(end - start).count();
          recentFrameEnds.push_back(end);
          if (recentFrameEnds.size() > 30) recentFrameEnds.pop_front();

          std::vector<tissuemosaic::ModelArrays> released;  // freed after the lock, on this thread
          const std::lock_guard<std::mutex> lock(mutex);
          released.swap(retired);
          if (model) published.model = std::move(model);
          if (modelArrays) published.modelArrays = std::move(modelArrays);
          if (keyFrames) published.keyFrames = std::move(keyFrames);
          published.left = left;
          published.right = right;
          published.disparityPx = disparity;
          ScanStatus& status = published.status;
          status.framesProcessed = processed;
          status.lastFrameIndex = result.frameIndex;
          status.keyFrames = static_cast<int>(pipeline->keyFrames().size());
          status.modelPoints = static_cast<long long>(result.modelPoints);
          status.pointBudgetReached = result.pointBudgetReached;
          status.tracked = result.tracked;
          status.lostFrames += result.tracked ? 0 : 1;
          status.inliers = result.inliers;
          status.trackingMessage = result.trackingMessage;
          status.frameStatus = static_cast<int>(result.status);
          if (result.status == tissuemosaic::FrameStatus::Relocalised) {
            ++status.relocalisations;
            status.lastRelocalisedFrame = result.frameIndex;
          }
          status.agreement = result.agreement;
          status.agreementLevel = static_cast<int>(result.agreementLevel);
          status.sceneMotion = static_cast<int>(result.sceneMotion);
          status.elapsedS = busyS;
          status.disparityRange = result.disparityRange;
          status.disparityRangeText = pipeline->disparityRangeDescription();
          status.rowOffsetPx = pipeline->disparityRangeHistory().rowOffsetPx;
          if (recentFrameEnds.size() >= 2) {
            const double spanS = std::chrono::duration<double>(recentFrameEnds.back() - recentFrameEnds.front()).count();
            status.framesPerSecond = spanS > 0 ? (recentFrameEnds.size() - 1) / spanS : 0;
          } else {
            status.framesPerSecond = busyS > 0 ? processed / busyS : 0;
          }
          published.frames.push_back(std::move(record));
        }
      },
      errorText);
  if (observer.scanEnded) {
    std::string ignored;
    runCatching(
        [&] {
          const bool any = pipeline && pipeline->frameCount() > 0;
          const ModelPoints model = any ? pipeline->liveModelSnapshot() : ModelPoints{};
          observer.scanEnded(any ? &model : nullptr, lastTimeS,
                             !ranToEnd ? "failed: " + errorText : endState == StateStopped ? "stopped" : "finished");
        },
        ignored);
  }
  publishEnd(ranToEnd ? endState : StateFailed, errorText);
}

void vtkTissueMosaicReconstructionLogic::Session::publishEnd(int endState, const std::string& errorText) {
  {
    const std::lock_guard<std::mutex> lock(mutex);
    ended = true;
    published.status.errorText = errorText;
    // Ended: the average over the scan instead of the recent rate.
    published.status.framesPerSecond =
        published.status.elapsedS > 0 ? published.status.framesProcessed / published.status.elapsedS : 0;
    state = endState;
  }
  wake.notify_all();
}

//----------------------------------------------------------------------------------------------------------------------

vtkTissueMosaicReconstructionLogic::vtkTissueMosaicReconstructionLogic()
    : Owned(new Results),
      Model(vtkSmartPointer<vtkPolyData>::New()),
      KeyFrameFrusta(vtkSmartPointer<vtkPolyData>::New()),
      CurrentFrustum(vtkSmartPointer<vtkPolyData>::New()),
      Trajectory(vtkSmartPointer<vtkPolyData>::New()) {
  this->ClearOutputs();
}

vtkTissueMosaicReconstructionLogic::~vtkTissueMosaicReconstructionLogic() {
  this->EndSession();
  for (auto& session : this->Retiring) {
    if (session->thread.joinable()) session->thread.join();
  }
}

void vtkTissueMosaicReconstructionLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DeviceChoice: " << GetDeviceChoiceAsString(this->DeviceChoice) << "\n";
  os << indent << "Input: " << (this->HasInput() ? this->InputDescription : "(none)") << "\n";
  os << indent << "InputRectified: " << this->InputRectified << "\n";
  os << indent << "ScanState: " << GetScanStateAsString(this->GetScanState()) << "\n";
  os << indent << "FramesProcessed: " << this->Status.framesProcessed << "\n";
  os << indent << "KeyFrames: " << this->Status.keyFrames << "\n";
  os << indent << "DisparityRange: " << this->GetDisparityRangeText() << "\n";
  os << indent << "ModelPoints: " << this->Model->GetNumberOfPoints() << "\n";
  os << indent << "MaximumFrames: " << this->MaximumFrames << "\n";
  os << indent << "FrustumDepthMm: " << this->FrustumDepthMm << "\n";
  os << indent << "LastErrorText: " << this->LastErrorText << "\n";
}

bool vtkTissueMosaicReconstructionLogic::Fail(const std::string& message) {
  this->LastErrorText = message;
  return false;
}

//----------------------------------------------------------------------------------------------------------------------
// Parameters

const ReconstructionParameters& vtkTissueMosaicReconstructionLogic::GetParameters() const { return this->Parameters; }

bool vtkTissueMosaicReconstructionLogic::CanChangeParameters() const { return !this->Current; }

bool vtkTissueMosaicReconstructionLogic::SetParameters(const ReconstructionParameters& parameters) {
  if (!runCatching([&] { parameters.validate(); }, this->LastErrorText)) return false;
  if (!this->CanChangeParameters()) {
    return this->Fail("the parameters are fixed during a scan: reset the scan to change them");
  }
  this->Parameters = parameters;
  this->Modified();
  return true;
}

bool vtkTissueMosaicReconstructionLogic::ReadParametersFile(const std::string& path) {
  ReconstructionParameters parameters;
  if (!ReadReconstructionParametersFile(path, parameters, this->LastErrorText)) return false;
  return this->SetParameters(parameters);
}

bool vtkTissueMosaicReconstructionLogic::WriteParametersFile(const std::string& path) {
  return WriteReconstructionParametersFile(path, this->Parameters, this->LastErrorText);
}

bool vtkTissueMosaicReconstructionLogic::ReadReconstructionParametersFile(const std::string& path,
                                                                          ReconstructionParameters& parameters,
                                                                          std::string& errorText) {
  ReconstructionParameters read;
  if (!runCatching([&] { read = ReconstructionParameters::readFile(path); }, errorText)) {
    if (errorText.find(path) == std::string::npos) errorText = path + ": " + errorText;
    return false;
  }
  parameters = read;
  return true;
}

bool vtkTissueMosaicReconstructionLogic::ParseReconstructionParameters(const std::string& yamlText,
                                                                       ReconstructionParameters& parameters,
                                                                       std::string& errorText) {
  ReconstructionParameters read;
  if (!runCatching([&] { read = ReconstructionParameters::parse(yamlText); }, errorText)) return false;
  parameters = read;
  return true;
}

bool vtkTissueMosaicReconstructionLogic::WriteReconstructionParametersFile(const std::string& path,
                                                                           const ReconstructionParameters& parameters,
                                                                           std::string& errorText) {
  return runCatching([&] { parameters.writeFile(path); }, errorText);
}

const char* vtkTissueMosaicReconstructionLogic::GetDeviceChoiceAsString(int choice) {
  switch (choice) {
    case DeviceCpu: return "cpu";
    case DeviceCuda: return "cuda";
    default: return "auto";
  }
}

//----------------------------------------------------------------------------------------------------------------------
// Input

bool vtkTissueMosaicReconstructionLogic::SetFrameSourceFactory(const FrameSourceFactory& factory) {
  this->Reset();
  this->SourceFactory = nullptr;
  this->InputDescription.clear();
  this->InputFrameCount = 0;
  this->InputFrameSize = cv::Size();
  if (!factory) return this->Fail("no frame source");
  std::unique_ptr<StereoFrameSource> source;
  if (!runCatching([&] { source = factory(); }, this->LastErrorText)) return false;
  if (!source) return this->Fail("the frame source could not be opened");
  this->SourceFactory = factory;
  this->InputDescription = source->description();
  this->InputFrameCount = source->frameCount();
  this->InputFrameSize = source->frameSize();
  this->Modified();
  return true;
}

bool vtkTissueMosaicReconstructionLogic::OpenFrameFolders(const std::string& leftFolder,
                                                          const std::string& rightFolder, double fps) {
  return this->SetFrameSourceFactory(
      [=] { return StereoFrameSource::openFrameFolders(leftFolder, rightFolder, fps); });
}

bool vtkTissueMosaicReconstructionLogic::OpenVideoPair(const std::string& leftVideo, const std::string& rightVideo) {
  return this->SetFrameSourceFactory([=] { return StereoFrameSource::openVideoPair(leftVideo, rightVideo); });
}

bool vtkTissueMosaicReconstructionLogic::OpenSideBySideVideo(const std::string& video) {
  return this->OpenStereoVideo(video, tissuemosaic::VideoLayout::SideBySide);
}

bool vtkTissueMosaicReconstructionLogic::OpenStereoVideo(const std::string& video, tissuemosaic::VideoLayout layout) {
  return this->SetFrameSourceFactory([=] { return StereoFrameSource::openStereoVideo(video, layout); });
}

bool vtkTissueMosaicReconstructionLogic::LoadCalibration(const std::string& path) {
  return this->LoadCalibrationFiles({path});
}

bool vtkTissueMosaicReconstructionLogic::LoadCalibrationFiles(const std::vector<std::string>& paths) {
  tissuemosaic::StereoCalibration calibration;
  const bool loaded = runCatching(
      [&] {
        calibration = tissuemosaic::readCalibrationFiles(paths).calibration;
        // Refuses rigs that cannot be rectified, now; a file without image size is checked with the frames.
        if (!calibration.imageSize.empty()) const tissuemosaic::StereoRectifier check(calibration);
      },
      this->LastErrorText);
  if (!loaded) return this->Fail(this->LastErrorText);
  this->SetCalibration(calibration);
  return true;
}

void vtkTissueMosaicReconstructionLogic::SetCalibration(const tissuemosaic::StereoCalibration& calibration) {
  this->Reset();
  this->Calibration = std::make_unique<tissuemosaic::StereoCalibration>(calibration);
  this->CalibrationGeometry.reset();
  std::string ignored;  // a rig that cannot be rectified fails at Start(), with the reason
  runCatching(
      [&] {
        this->CalibrationGeometry =
            std::make_unique<tissuemosaic::RectifiedGeometry>(tissuemosaic::StereoRectifier(calibration).geometry());
      },
      ignored);
  this->Geometry.reset();
  this->Modified();
}

void vtkTissueMosaicReconstructionLogic::SetRectifiedGeometry(const tissuemosaic::RectifiedGeometry& geometry) {
  this->Reset();
  this->Geometry = std::make_unique<tissuemosaic::RectifiedGeometry>(geometry);
  this->Calibration.reset();
  this->CalibrationGeometry.reset();
  this->Modified();
}

bool vtkTissueMosaicReconstructionLogic::GetRectifiedGeometry(tissuemosaic::RectifiedGeometry& geometry) const {
  const tissuemosaic::RectifiedGeometry* known = this->Geometry ? this->Geometry.get() : this->CalibrationGeometry.get();
  if (!known) return false;
  geometry = *known;
  return true;
}

void vtkTissueMosaicReconstructionLogic::SetInputRectified(bool rectified) {
  if (rectified == this->InputRectified) return;
  this->Reset();
  this->InputRectified = rectified;
  this->Modified();
}

bool vtkTissueMosaicReconstructionLogic::HasInput() const { return static_cast<bool>(this->SourceFactory); }

bool vtkTissueMosaicReconstructionLogic::HasCalibration() const { return this->Calibration || this->Geometry; }

std::string vtkTissueMosaicReconstructionLogic::GetInputDescription() const { return this->InputDescription; }

int vtkTissueMosaicReconstructionLogic::GetInputFrameCount() const { return this->InputFrameCount; }

std::string vtkTissueMosaicReconstructionLogic::GetStartProblem() const {
  if (this->Current) return std::string();  // Start() resumes or says why it cannot
  if (!this->HasInput()) return "no input: open a video, two frame folders or the demo";
  if (!this->HasCalibration()) return "no calibration: load the stereo calibration of the video";
  const cv::Size expected = this->Geometry ? this->Geometry->imageSize : this->Calibration->imageSize;
  if (this->InputFrameSize.area() > 0 && this->InputFrameSize != expected) {
    return "the calibration is for " + std::to_string(expected.width) + "x" + std::to_string(expected.height) +
           " px but the frames are " + std::to_string(this->InputFrameSize.width) + "x" +
           std::to_string(this->InputFrameSize.height) + " px: load the calibration of this video";
  }
  return std::string();
}

const tissuemosaic::RectifiedGeometry* vtkTissueMosaicReconstructionLogic::GetScanGeometry() const {
  return this->Owned->geometry ? &*this->Owned->geometry : nullptr;
}

bool vtkTissueMosaicReconstructionLogic::CheckFrameSize(StereoFrameSource& source) {
  const cv::Size expected = this->Geometry ? this->Geometry->imageSize : this->Calibration->imageSize;
  const cv::Size frames = source.frameSize();
  if (frames == expected || expected.empty()) return true;
  return this->Fail("the frames are " + std::to_string(frames.width) + "x" + std::to_string(frames.height) +
                    " px but the calibration is for " + std::to_string(expected.width) + "x" +
                    std::to_string(expected.height) + " px");
}

//----------------------------------------------------------------------------------------------------------------------
// Scan control

const char* vtkTissueMosaicReconstructionLogic::GetScanStateAsString(int state) {
  switch (state) {
    case StateRunning: return "running";
    case StatePaused: return "paused";
    case StateFinished: return "finished";
    case StateStopped: return "stopped";
    case StateFailed: return "failed";
    default: return "idle";
  }
}

int vtkTissueMosaicReconstructionLogic::GetScanState() const {
  return this->Current ? this->Current->state.load() : StateIdle;
}

bool vtkTissueMosaicReconstructionLogic::Start() {
  if (this->Current) {
    const int state = this->GetScanState();
    if (state == StateRunning) return true;
    if (state == StatePaused) {
      {
        const std::lock_guard<std::mutex> lock(this->Current->mutex);
        this->Current->paused = false;
        if (!this->Current->ended) this->Current->state = StateRunning;
      }
      this->Current->wake.notify_all();
      this->Modified();
      return true;
    }
    return this->Fail(std::string("the scan has ") + GetScanStateAsString(state) +
                      ": reset it to start again from the first frame");
  }
  if (!this->HasInput()) return this->Fail("no input: open a video, two frame folders or the demo first");
  if (!this->HasCalibration()) return this->Fail("no calibration: load the stereo calibration of the video first");

  auto session = std::make_unique<Session>();
  const bool prepared = runCatching(
      [&] {
        session->device = tissuemosaic::parseDevice(GetDeviceChoiceAsString(this->DeviceChoice));
        session->source = this->SourceFactory();
        tissuemosaic::require(session->source != nullptr, "the input could not be opened");
        if (this->Geometry) {
          session->geometry = *this->Geometry;
        } else {
          tissuemosaic::StereoCalibration calibration = *this->Calibration;  // the frames give a missing size
          calibration.adoptFrameSize(session->source->frameSize(), session->source->description());
          if (this->InputRectified) {
            session->geometry = tissuemosaic::StereoRectifier(calibration).geometry();
          } else {
            session->calibration = calibration;
          }
        }
      },
      this->LastErrorText);
  if (!prepared || !this->CheckFrameSize(*session->source)) return false;
  session->parameters = this->Parameters;
  session->maximumFrames = this->MaximumFrames;
  session->observer = this->Observer;
  session->workerNiceIncrement = this->WorkerNiceIncrement;
  session->published.status.state = StateRunning;
  session->published.status.framesInInput = this->InputFrameCount;

  this->ClearOutputs();
  Session* worker = session.get();
  session->thread = std::thread([worker] { worker->run(); });
  this->Current = std::move(session);
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

void vtkTissueMosaicReconstructionLogic::Pause() {
  if (!this->Current) return;
  {
    const std::lock_guard<std::mutex> lock(this->Current->mutex);
    if (this->Current->ended) return;
    this->Current->paused = true;
    this->Current->state = StatePaused;
  }
  this->Modified();
}

void vtkTissueMosaicReconstructionLogic::Stop() {
  if (!this->Current) return;
  {
    const std::lock_guard<std::mutex> lock(this->Current->mutex);
    this->Current->stopRequested = true;
  }
  this->Current->wake.notify_all();
  // A live source may be waiting for its next frame: end the wait (the source is thread-safe for this).
  if (this->Current->source) this->Current->source->interrupt();
  this->Modified();
}

void vtkTissueMosaicReconstructionLogic::EndSession() {
  if (!this->Current) return;
  this->Stop();
  this->Retiring.push_back(std::move(this->Current));
}

void vtkTissueMosaicReconstructionLogic::Reset() {
  this->EndSession();
  this->ClearOutputs();
  this->Modified();
}

bool vtkTissueMosaicReconstructionLogic::WaitForScanEnd(double timeoutS) {
  if (!this->Current) return true;
  std::unique_lock<std::mutex> lock(this->Current->mutex);
  return this->Current->wake.wait_for(lock, std::chrono::duration<double>(timeoutS),
                                      [this] { return this->Current->ended; });
}

//----------------------------------------------------------------------------------------------------------------------
// Outputs

void vtkTissueMosaicReconstructionLogic::ClearOutputs() {
  *this->Owned = Results();
  this->Owned->status.framesInInput = this->InputFrameCount;
  this->Model->Initialize();
  this->KeyFrameFrusta->Initialize();
  this->CurrentFrustum->Initialize();
  this->Trajectory->Initialize();
  tissuemosaic::updateGrowingModel(this->Model, tissuemosaic::ColoredPointCloud());
  this->LeftFrame = cv::Mat();
  this->RightFrame = cv::Mat();
  this->DisparityPx = cv::Mat();
  this->Status = ScanStatus();
  this->Status.framesInInput = this->InputFrameCount;
}

bool vtkTissueMosaicReconstructionLogic::UpdateOutputs() {
  // Sessions ended by Reset are joined once their worker has finished its frame (never waited for here).
  for (auto it = this->Retiring.begin(); it != this->Retiring.end();) {
    bool ended;
    {
      const std::lock_guard<std::mutex> lock((*it)->mutex);
      ended = (*it)->ended;
    }
    if (ended) {
      (*it)->thread.join();
      it = this->Retiring.erase(it);
    } else {
      ++it;
    }
  }
  if (!this->Current) return false;

  Results taken;
  {
    // Only moves and small copies under the lock: the worker is never held up for long.
    const std::lock_guard<std::mutex> lock(this->Current->mutex);
    Results& published = this->Current->published;
    taken.model = std::move(published.model);
    published.model.reset();
    taken.modelArrays = std::move(published.modelArrays);
    published.modelArrays.reset();
    taken.keyFrames = std::move(published.keyFrames);
    published.keyFrames.reset();
    taken.frames.swap(published.frames);
    taken.left = published.left;
    taken.right = published.right;
    taken.disparityPx = published.disparityPx;
    if (!this->Owned->geometry) taken.geometry = published.geometry;
    taken.status = published.status;
    taken.status.state = this->Current->state.load();  // under the lock: consistent with what was taken
  }
  const bool stateChanged = taken.status.state != this->Status.state;
  const bool changed = stateChanged || taken.model || taken.keyFrames || !taken.frames.empty() ||
                       taken.status.errorText != this->Status.errorText;
  this->Status = taken.status;
  if (!changed) return false;

  Results& owned = *this->Owned;
  if (taken.geometry) owned.geometry = taken.geometry;
  if (!taken.left.empty()) {
    this->LeftFrame = taken.left;
    this->RightFrame = taken.right;
    this->DisparityPx = taken.disparityPx;
  }
  if (taken.model) {
    owned.model = std::move(taken.model);
    if (taken.modelArrays) {
      // Constant time; the arrays replaced go back to the worker, which frees them.
      tissuemosaic::ModelArrays replaced = tissuemosaic::swapModelArrays(this->Model, std::move(*taken.modelArrays));
      const std::lock_guard<std::mutex> lock(this->Current->mutex);
      this->Current->retired.push_back(std::move(replaced));
    } else {
      tissuemosaic::updateGrowingModel(this->Model, owned.model->cloud);
    }
  }
  const bool newKeyFrames = static_cast<bool>(taken.keyFrames);
  if (newKeyFrames) owned.keyFrames = std::move(taken.keyFrames);
  for (FrameRecord& frame : taken.frames) {
    owned.timing.add(frame.timesMs, frame.keyFrame);
    owned.frames.push_back(std::move(frame));
  }

  if (owned.geometry && (newKeyFrames || !taken.frames.empty())) {
    // Key frames at their refined poses: in the frusta, and in the path in place of their tracked pose.
    std::map<int, const KeyFramePose*> refined;
    tissuemosaic::CameraPoses keyFrameCameras;
    if (owned.keyFrames) {
      for (const KeyFramePose& keyFrame : *owned.keyFrames) {
        refined[keyFrame.frameIndex] = &keyFrame;
        tissuemosaic::CameraPose camera;
        camera.frameIndex = keyFrame.frameIndex;
        camera.T_world_camera = keyFrame.T_world_camera;
        keyFrameCameras.push_back(camera);
      }
    }
    if (newKeyFrames) {
      tissuemosaic::updateCameraFrusta(this->KeyFrameFrusta, keyFrameCameras, *owned.geometry, this->FrustumDepthMm);
    }
    tissuemosaic::CameraPoses path;
    for (const FrameRecord& frame : owned.frames) {
      if (!frame.tracked) continue;
      tissuemosaic::CameraPose camera;
      camera.frameIndex = frame.frameIndex;
      const auto keyFrame = refined.find(frame.frameIndex);
      camera.T_world_camera = keyFrame != refined.end() ? keyFrame->second->T_world_camera : frame.T_world_camera;
      path.push_back(camera);
    }
    tissuemosaic::updateCameraPath(this->Trajectory, path);
    const tissuemosaic::CameraPoses current(path.empty() ? path.end() : path.end() - 1, path.end());
    tissuemosaic::updateCameraFrusta(this->CurrentFrustum, current, *owned.geometry, this->FrustumDepthMm);
  }
  this->Modified();
  return true;
}

vtkPolyData* vtkTissueMosaicReconstructionLogic::GetModel() { return this->Model; }
vtkPolyData* vtkTissueMosaicReconstructionLogic::GetKeyFrameFrusta() { return this->KeyFrameFrusta; }
vtkPolyData* vtkTissueMosaicReconstructionLogic::GetCurrentFrustum() { return this->CurrentFrustum; }
vtkPolyData* vtkTissueMosaicReconstructionLogic::GetTrajectory() { return this->Trajectory; }

cv::Mat vtkTissueMosaicReconstructionLogic::GetDisparityColorImage() const {
  // Colours spread over this frame's disparities (the search range is usually much wider than the scene's).
  tissuemosaic::DisparityColouring colouring;
  tissuemosaic::colourDisparity(this->DisparityPx, this->Parameters.stereo.minDisparityPx,
                                this->Parameters.stereo.maxDisparityPx, colouring);
  return colouring.bgr;
}

std::string vtkTissueMosaicReconstructionLogic::GetTrackingStateText() const {
  const ScanStatus& status = this->Status;
  switch (status.state) {
    case StateIdle: return this->HasInput() ? "Ready" : "No input";
    case StateFailed: return "Failed: " + status.errorText;
    default: break;
  }
  if (status.framesProcessed == 0) return status.state == StateRunning ? "Starting" : GetScanStateAsString(status.state);
  std::string text;
  if (!status.tracked) {
    text = "Lost: move the camera back over the scanned tissue";
    if (!status.trackingMessage.empty()) text += " (" + status.trackingMessage + ")";
  } else if (status.lastRelocalisedFrame >= 0 &&
             status.lastFrameIndex - status.lastRelocalisedFrame < RelocalisedNoticeFrames) {
    text = "Relocalised";
  } else {
    text = "Tracking";
  }
  if (status.state != StateRunning) text += std::string(", ") + GetScanStateAsString(status.state);
  return text;
}

std::string vtkTissueMosaicReconstructionLogic::GetAgreementText() const {
  const tissuemosaic::ModelAgreement& a = this->Status.agreement;
  if (this->Status.framesProcessed == 0 || !this->Status.tracked || !a.measured) return "model agreement: not measured";
  char text[128];
  std::snprintf(text, sizeof text, "model agreement: %.0f%% within 1 mm, median %.2f mm", 100 * a.shareWithin1mm,
                a.medianDepthDifferenceMm);
  return text;
}

std::string vtkTissueMosaicReconstructionLogic::GetSceneMotionText() const {
  if (this->Status.framesProcessed == 0 || !this->Status.tracked) return "";
  switch (static_cast<tissuemosaic::SceneMotion>(this->Status.sceneMotion)) {
    case tissuemosaic::SceneMotion::Still: return "Moving: nothing (camera and tissue still)";
    case tissuemosaic::SceneMotion::Camera: return "Moving: the camera";
    case tissuemosaic::SceneMotion::Tissue: return "Moving: the tissue (the camera still)";
    case tissuemosaic::SceneMotion::Both: return "Moving: the camera and the tissue";
    default: return "";
  }
}

std::string vtkTissueMosaicReconstructionLogic::GetDisparityRangeText() const {
  if (!this->Status.disparityRangeText.empty()) return this->Status.disparityRangeText;
  const tissuemosaic::StereoParameters& stereo = this->Parameters.stereo;
  switch (stereo.disparityRangeMode) {
    case tissuemosaic::DisparityRangeMode::Automatic: return "auto: from the first frame's feature matches";
    case tissuemosaic::DisparityRangeMode::Fixed:
      return "fixed: " + tissuemosaic::DisparityRange{stereo.minDisparityPx, stereo.maxDisparityPx}.text();
    default: break;
  }
  std::string text = cv::format("working distance %g..%g mm: ", stereo.workingDistanceNearMm, stereo.workingDistanceFarMm);
  tissuemosaic::RectifiedGeometry geometry;
  if (!this->GetRectifiedGeometry(geometry)) return text + "disparities once a calibration is loaded";
  std::string errorText;
  tissuemosaic::DisparityRange range;
  if (!runCatching([&] {
        range = tissuemosaic::disparityRangeForDepthMm(geometry, stereo.workingDistanceNearMm, stereo.workingDistanceFarMm);
      },
                   errorText)) {
    return text + errorText;
  }
  return text + range.text();
}

std::vector<vtkTissueMosaicReconstructionLogic::TimingRow> vtkTissueMosaicReconstructionLogic::GetTimingTable() const {
  const tissuemosaic::TimingTable& timing = this->Owned->timing;
  tissuemosaic::TimingTable last;  // the same stage order for the last frame's numbers
  if (!this->Owned->frames.empty()) last.add(this->Owned->frames.back().timesMs, this->Owned->frames.back().keyFrame);
  const bool lastIsKeyFrame = !this->Owned->frames.empty() && this->Owned->frames.back().keyFrame;
  const std::vector<double> lastMs = last.means(lastIsKeyFrame);
  const std::vector<double> keyMedians = timing.medians(true), keyMeans = timing.means(true);
  const std::vector<double> otherMedians = timing.medians(false);
  std::vector<TimingRow> rows;
  const std::vector<std::string>& stages = tissuemosaic::TimingTable::stageNames();
  for (std::size_t i = 0; i < stages.size(); ++i) {
    if (!timing.stageShown(i)) continue;
    TimingRow row;
    row.stage = stages[i];
    row.lastMs = lastMs[i];
    row.keyFrameMedianMs = keyMedians[i];
    row.keyFrameMeanMs = keyMeans[i];
    row.otherFrameMedianMs = otherMedians[i];
    rows.push_back(row);
  }
  return rows;
}

//----------------------------------------------------------------------------------------------------------------------
// Export

bool vtkTissueMosaicReconstructionLogic::ExportModel(const std::string& path) {
  this->UpdateOutputs();
  if (!this->Owned->model || this->Owned->model->cloud.size() == 0) {
    return this->Fail("there is no model to export yet: run a scan until its first key frame");
  }
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  const char* const frameNote =
      "frame: world = first left rectified camera (x right, y down, z forward), millimetres (not LPS)";
  if (extension == ".ply") {
    return runCatching(
        [&] { tissuemosaic::writePly(path, this->Owned->model->cloud, std::string("TissueMosaic model\n") + frameNote); },
        this->LastErrorText);
  }
  if (extension == ".vtp") {
    return runCatching(
        [&] {
          tissuemosaic::writeFileAtomically(path, "model file", [&](const std::string& temporaryPath) {
            vtkNew<vtkXMLPolyDataWriter> writer;
            writer->SetFileName(temporaryPath.c_str());
            writer->SetInputData(this->Model);
            writer->SetDataModeToBinary();
            return writer->Write() == 1;
          });
        },
        this->LastErrorText);
  }
  return this->Fail("unknown model file type '" + extension + "' of " + path + ": use .ply or .vtp");
}

bool vtkTissueMosaicReconstructionLogic::ExportTrajectory(const std::string& path) {
  this->UpdateOutputs();
  const FrameRecords& frames = this->Owned->frames;
  if (frames.empty()) return this->Fail("there is no trajectory to export yet: start a scan first");
  std::map<int, Eigen::Matrix4d> refined;
  if (this->Owned->keyFrames) {
    for (const KeyFramePose& keyFrame : *this->Owned->keyFrames) refined[keyFrame.frameIndex] = keyFrame.T_world_camera;
  }
  tissuemosaic::Trajectory trajectory;
  std::string header = "TissueMosaic camera trajectory: T_world_camera of the left rectified camera, mm; world = "
                       "first left rectified camera; key frames at their refined poses";
  for (const FrameRecord& frame : frames) {
    if (!frame.tracked) {
      header += "\nframe " + std::to_string(frame.frameIndex) + " lost: " + frame.message;
      continue;
    }
    tissuemosaic::TimedPose pose;
    pose.timeS = frame.timeS;
    const auto keyFrame = refined.find(frame.frameIndex);
    pose.T_world_camera = keyFrame != refined.end() ? keyFrame->second : frame.T_world_camera;
    trajectory.push_back(pose);
  }
  return runCatching([&] { tissuemosaic::writeTumTrajectory(path, trajectory, header); }, this->LastErrorText);
}
