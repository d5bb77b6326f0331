#pragma once
/// @class vtkTissueMosaicReconstructionLogic
/// @brief The whole reconstruction of the paper (sections II-III) for the application: wraps the engine's
/// ReconstructionPipeline, runs it on a worker thread, and exposes the growing model and the camera poses as VTK
/// data, the latest video frames and disparity, the tracking state and the timing table.
///
/// Threads. Every method is called from one thread, the owner (the GUI thread in the application), and never
/// blocks on the engine: Start() launches a worker std::thread that reads the frames and runs the pipeline; the
/// worker publishes its results into a mutex-protected hand-over area (moves, no VTK), and UpdateOutputs(), called
/// by the owner (e.g. from a 30 Hz timer), takes them over and updates the VTK outputs in place. The model's
/// vtkPolyData grows in place (new points appended, see vtkTissueMosaicGrowingModel.h), so mappers holding the
/// outputs see every update. Only the destructor may wait for the worker (to finish its current frame).
///
/// Frames. The world frame is the first left rectified camera (x right, y down, z forward), in millimetres;
/// poses are T_world_camera of the left rectified camera.
///
/// Errors. Methods that can fail return false and leave a message in GetLastErrorText(); they never throw. A
/// failure on the worker (an unreadable frame, CUDA errors) ends the scan in StateFailed with the message in
/// GetStatus().errorText.
#include "Core/StereoRig.h"
#include "IO/StereoVideoLayout.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/DisparityRange.h"

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include <opencv2/core.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkPolyData;

namespace tissuemosaic {
class StereoFrameSource;
class ReconstructionPipeline;
struct FrameResult;
struct ModelPoints;
}

class vtkTissueMosaicReconstructionLogic : public vtkObject {
public:
  static vtkTissueMosaicReconstructionLogic* New();
  vtkTypeMacro(vtkTissueMosaicReconstructionLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkTissueMosaicReconstructionLogic(const vtkTissueMosaicReconstructionLogic&) = delete;
  void operator=(const vtkTissueMosaicReconstructionLogic&) = delete;

  /// @name Parameters: one tissuemosaic::ReconstructionParameters object, the one the engine takes
  /// SetParameters validates first (ReconstructionParameters::validate, the one source of the limits): invalid
  /// parameters are refused (false, error text) and the current ones are kept. Parameters are fixed while a scan
  /// exists (running, paused, or ended but not reset): SetParameters then refuses with the reason.
  ///@{
  const tissuemosaic::ReconstructionParameters& GetParameters() const;
  bool SetParameters(const tissuemosaic::ReconstructionParameters& parameters);
  bool CanChangeParameters() const;
  /// Parameter files: OpenCV YAML/XML, one node per stage (ReconstructionParameters::readFile).
  bool ReadParametersFile(const std::string& path);
  bool WriteParametersFile(const std::string& path);
  static bool ReadReconstructionParametersFile(const std::string& path,
                                               tissuemosaic::ReconstructionParameters& parameters,
                                               std::string& errorText);
  /// The same from YAML text in memory (e.g. a preset compiled in as a Qt resource).
  static bool ParseReconstructionParameters(const std::string& yamlText,
                                            tissuemosaic::ReconstructionParameters& parameters,
                                            std::string& errorText);
  static bool WriteReconstructionParametersFile(const std::string& path,
                                                const tissuemosaic::ReconstructionParameters& parameters,
                                                std::string& errorText);
  ///@}

  /// @name Device
  /// Auto: CUDA when this build and machine have it, else the CPU. Cuda where there is none makes Start() fail
  /// with the reason; never a silent fallback. Used when the next scan starts.
  ///@{
  enum DeviceChoiceType { DeviceAuto = 0, DeviceCpu, DeviceCuda };
  vtkSetClampMacro(DeviceChoice, int, DeviceAuto, DeviceCuda);
  vtkGetMacro(DeviceChoice, int);
  static const char* GetDeviceChoiceAsString(int choice);
  ///@}

  /// @name Input: the stereo video and its calibration
  /// Opening an input (or a calibration) resets the scan. The Open* methods check that the input can be opened.
  ///@{
  bool OpenFrameFolders(const std::string& leftFolder, const std::string& rightFolder, double fps = 30.0);
  bool OpenVideoPair(const std::string& leftVideo, const std::string& rightVideo);
  bool OpenSideBySideVideo(const std::string& video);
  /// One 3D video in any layout (sbs, sbs-half, tb, tb-half, rows). Videos here and above may be files, V4L2
  /// devices (/dev/videoN) or GStreamer pipelines ending in appsink (live: newest frame first, Stop ends a wait).
  bool OpenStereoVideo(const std::string& video, tissuemosaic::VideoLayout layout);
  /// Any source (e.g. frames rendered in memory): the factory is called now (to check it) and again at every
  /// start from the first frame. `description` is shown to the user.
  using FrameSourceFactory = std::function<std::unique_ptr<tissuemosaic::StereoFrameSource>()>;
  bool SetFrameSourceFactory(const FrameSourceFactory& factory);
  /// Stereo calibration of the raw rig, in any layout of docs/CALIBRATION.md: frames are rectified with it, unless
  /// InputRectified says they already are (as `tissuemosaic synth scan` writes them). A file without image size
  /// takes the frames'. LoadCalibrationFiles takes one or two files in any order (intrinsics + extrinsics, or the
  /// ROS camera_info of each eye).
  bool LoadCalibration(const std::string& path);
  bool LoadCalibrationFiles(const std::vector<std::string>& paths);
  void SetCalibration(const tissuemosaic::StereoCalibration& calibration);
  /// Frames already rectified, with exactly this geometry (no calibration needed).
  void SetRectifiedGeometry(const tissuemosaic::RectifiedGeometry& geometry);
  void SetInputRectified(bool rectified);
  bool GetInputRectified() const { return this->InputRectified; }
  bool HasInput() const;
  bool HasCalibration() const;
  /// The rectified geometry the scan will use (set directly, or what the calibration's rectification gives), e.g.
  /// to show what a working distance means in disparities. False without a calibration.
  bool GetRectifiedGeometry(tissuemosaic::RectifiedGeometry& geometry) const;
  /// "frames in DIR and DIR", "video FILE", ... (empty without an input).
  std::string GetInputDescription() const;
  /// Frames in the input (-1 when the container does not say, 0 without an input).
  int GetInputFrameCount() const;
  /// Size of the input's frames (empty without an input).
  cv::Size GetInputFrameSize() const { return this->InputFrameSize; }
  /// Why Start() would refuse now, in plain words (no input, no calibration, frames of another size than the
  /// calibration's), or empty. Opens nothing: cheap enough for every refresh of a Start button.
  std::string GetStartProblem() const;
  /// The rectified geometry of the scan (focal length, baseline: depth from disparity); null before a scan starts.
  const tissuemosaic::RectifiedGeometry* GetScanGeometry() const;
  ///@}

  /// @name Scan control
  ///@{
  enum ScanStateType { StateIdle = 0, StateRunning, StatePaused, StateFinished, StateStopped, StateFailed };
  static const char* GetScanStateAsString(int state);
  /// Starts a scan from the first frame (Idle) or resumes a paused one. False with the reason when there is no
  /// input or calibration, the frame size differs from the calibration's, the device cannot be used, or the scan
  /// has ended (Reset first: the model of an ended scan stays until then, for export).
  bool Start();
  /// The worker stops before its next frame; Start() resumes.
  void Pause();
  /// Ends the scan after the current frame; the results stay (export them, or Reset).
  void Stop();
  /// Ends the scan (without waiting for the worker) and clears every result; the input and calibration stay.
  void Reset();
  /// The worker's state now (Running until the worker has really ended). It can be ahead of the outputs: wait for
  /// GetStatus().state, which UpdateOutputs() takes together with the model, to know the final model is here.
  int GetScanState() const;
  /// Stop after this many frames (-1: the whole input). For tests and previews.
  vtkSetMacro(MaximumFrames, int);
  vtkGetMacro(MaximumFrames, int);
  /// The worker thread runs at this much lower priority (Linux nice increment; 0: as the caller), so that the
  /// GUI thread wins the CPU when both want it. Default 5. Used when the next scan starts.
  vtkSetClampMacro(WorkerNiceIncrement, int, 0, 19);
  vtkGetMacro(WorkerNiceIncrement, int);
  /// Lowers the calling thread's priority by this nice increment (Linux; no-op elsewhere). Threads it starts
  /// later inherit it. For background work that must not take the CPU from the GUI thread.
  static void LowerCurrentThreadPriority(int niceIncrement);
  /// Streams the scan out while it runs (the OpenIGTLink link): called on the worker thread, so each call must only
  /// queue and return. frameProcessed after every frame (the pipeline is there for a model snapshot at key
  /// frames); scanEnded once with the final model (nullptr when no frame was processed) and how it ended
  /// ("finished", "stopped", "failed: ..."). Used from the next Start().
  struct ScanObserver {
    std::function<void(const tissuemosaic::FrameResult&, double timeS, const tissuemosaic::ReconstructionPipeline&)>
        frameProcessed;
    std::function<void(const tissuemosaic::ModelPoints* finalModel, double lastTimeS, const std::string& how)>
        scanEnded;
  };
  void SetScanObserver(const ScanObserver& observer) { this->Observer = observer; }
  /// Blocks until the worker has ended (finished, stopped or failed) or timeoutS passed; true when it has ended.
  /// For the command line and tests only: the GUI polls instead.
  bool WaitForScanEnd(double timeoutS);
  ///@}

  /// @name Outputs, brought up to date by UpdateOutputs() (owner thread only)
  ///@{
  /// Takes over what the worker published since the last call and updates the outputs below. Cheap when nothing
  /// is new; a new model (after each key frame) costs one copy of its arrays. True when anything changed.
  bool UpdateOutputs();
  /// The fused model: points (float, mm, world frame), one vertex cell per point, "RGB" colours, "Normals".
  vtkPolyData* GetModel();
  /// One frustum per key frame (vtkTissueMosaicFrusta.h: 5 points and 8 lines each, cell array "FrameIndex"),
  /// at the key frames' refined poses.
  vtkPolyData* GetKeyFrameFrusta();
  /// The frustum of the last tracked frame (empty before the first).
  vtkPolyData* GetCurrentFrustum();
  /// The optical centres of every tracked frame, in order, as one polyline.
  vtkPolyData* GetTrajectory();
  /// Depth of the drawn frusta (mm in front of the camera).
  vtkSetMacro(FrustumDepthMm, double);
  vtkGetMacro(FrustumDepthMm, double);
  /// The latest frame the worker processed: rectified left and right (8-bit BGR) and the left-view disparity
  /// (CV_32F px, NaN = none). Empty before the first frame.
  const cv::Mat& GetLeftFrame() const { return this->LeftFrame; }
  const cv::Mat& GetRightFrame() const { return this->RightFrame; }
  const cv::Mat& GetDisparityPx() const { return this->DisparityPx; }
  /// The disparity as a false-colour BGR picture (turbo colour map from the frame's smallest to its largest
  /// disparity, blue = far, red = near; black = no estimate). Empty before the first frame.
  cv::Mat GetDisparityColorImage() const;

  struct ScanStatus {
    int state = StateIdle;
    int framesProcessed = 0;
    int framesInInput = 0;        ///< -1: unknown (some video containers)
    int lastFrameIndex = -1;
    int keyFrames = 0;
    long long modelPoints = 0;
    bool pointBudgetReached = false;
    bool tracked = false;         ///< the last frame was tracked
    int lostFrames = 0;           ///< frames where tracking was lost so far
    int inliers = 0;              ///< DynamicR1PPnP inliers of the last frame
    std::string trackingMessage;  ///< why the last frame was lost (empty when tracked)
    /// tissuemosaic::FrameStatus of the last frame: tracked, lost, or relocalised (tracking resumed after lost frames).
    int frameStatus = 0;
    int relocalisations = 0;      ///< times tracking resumed after lost frames so far
    int lastRelocalisedFrame = -1;  ///< the frame where it last resumed (-1: never)
    /// The last frame's model agreement (the quality signal, Fusion/ModelAgreement.h) and its traffic light
    /// (tissuemosaic::AgreementLevel as int, by the parameters' thresholds).
    tissuemosaic::ModelAgreement agreement;
    int agreementLevel = 0;
    /// What moved at the last frame (tissuemosaic::SceneMotion as int: camera, tissue, both, still; docs/SCENE_MOTION.md).
    int sceneMotion = 0;
    double framesPerSecond = 0;   ///< over the last frames (wall clock); once ended, the scan's average
    double elapsedS = 0;          ///< since the scan started, pauses excluded
    tissuemosaic::DisparityRange disparityRange;  ///< the last frame's
    std::string disparityRangeText;  ///< how the ranges were chosen (ReconstructionPipeline::disparityRangeDescription)
    /// Right row minus left row of a point, as the first frame found it: not 0, the pair is not rectified (the text
    /// says so; DisparityRangeHistory::rowOffsetPx).
    double rowOffsetPx = 0;
    std::string device;           ///< where the pipeline runs ("cpu", "cuda")
    std::string errorText;        ///< StateFailed: why
  };
  /// As of the last UpdateOutputs().
  const ScanStatus& GetStatus() const { return this->Status; }
  /// One line for a status bar: "Tracking", "Lost: move the camera back over the scanned tissue (why)", and for a
  /// second after tracking resumed "Relocalised", with the scan's state when it is not running.
  std::string GetTrackingStateText() const;
  /// The last frame's model agreement for the user, e.g. "model agreement: 96% within 1 mm, median 0.21 mm"
  /// ("not measured" where there is none: lost, or no model in view yet).
  std::string GetAgreementText() const;
  /// What moved at the last frame (docs/SCENE_MOTION.md, "What moved"), e.g. "Moving: the tissue (the camera still)";
  /// empty before the first frame, for a lost frame and where it is not known.
  std::string GetSceneMotionText() const;
  /// Frames (at 30 fps, a second) that the state text keeps saying "Relocalised" after tracking resumed.
  static constexpr int RelocalisedNoticeFrames = 30;
  /// The stereo disparity range: as chosen in the scan so far ("auto: 64..95 px (from 412 left-right feature
  /// matches)"), or before the first frame what the parameters ask for ("auto: from the first frame's feature
  /// matches", "fixed: -20..80 px", "working distance 30..150 mm: 28..143 px").
  std::string GetDisparityRangeText() const;

  /// The paper's runtime table (ms, tissuemosaic::TimingTable's stages in the paper's order): per stage the last
  /// frame, and the median and mean over the key frames (the paper averages over key frames) and the median over
  /// the other frames.
  struct TimingRow {
    std::string stage;
    double lastMs = 0, keyFrameMedianMs = 0, keyFrameMeanMs = 0, otherFrameMedianMs = 0;
  };
  std::vector<TimingRow> GetTimingTable() const;
  ///@}

  /// @name Export (the model and poses as of the last UpdateOutputs, which the exports call first)
  ///@{
  /// .ply (binary, xyz rgb normals) or .vtp (the GetModel() polydata); world frame = first left rectified camera,
  /// mm, said in the file.
  bool ExportModel(const std::string& path);
  /// TUM lines "t tx ty tz qx qy qz qw" of every tracked frame (T_world_camera, mm), key frames at their refined
  /// poses; frames where tracking was lost are listed in the header comment ("# frame N lost: reason").
  bool ExportTrajectory(const std::string& path);
  ///@}

  /// Message of the last failure, empty after a success.
  const std::string& GetLastErrorText() const { return this->LastErrorText; }

protected:
  vtkTissueMosaicReconstructionLogic();
  ~vtkTissueMosaicReconstructionLogic() override;

private:
  struct Session;
  struct Results;
  bool Fail(const std::string& message);
  void ClearOutputs();
  void EndSession();
  bool CheckFrameSize(tissuemosaic::StereoFrameSource& source);

  tissuemosaic::ReconstructionParameters Parameters;
  ScanObserver Observer;
  int DeviceChoice = DeviceAuto;
  int MaximumFrames = -1;
  int WorkerNiceIncrement = 5;
  double FrustumDepthMm = 12.0;

  FrameSourceFactory SourceFactory;
  std::string InputDescription;
  int InputFrameCount = 0;
  cv::Size InputFrameSize;
  std::unique_ptr<tissuemosaic::StereoCalibration> Calibration;
  std::unique_ptr<tissuemosaic::RectifiedGeometry> Geometry;  ///< set directly (rectified input)
  std::unique_ptr<tissuemosaic::RectifiedGeometry> CalibrationGeometry;  ///< what Calibration's rectification gives
  bool InputRectified = false;

  std::unique_ptr<Session> Current;
  std::vector<std::unique_ptr<Session>> Retiring;  ///< reset sessions whose worker is still finishing a frame
  std::unique_ptr<Results> Owned;                  ///< what UpdateOutputs took over (owner thread)

  vtkSmartPointer<vtkPolyData> Model;
  vtkSmartPointer<vtkPolyData> KeyFrameFrusta;
  vtkSmartPointer<vtkPolyData> CurrentFrustum;
  vtkSmartPointer<vtkPolyData> Trajectory;
  cv::Mat LeftFrame, RightFrame, DisparityPx;
  ScanStatus Status;
  std::string LastErrorText;
};
