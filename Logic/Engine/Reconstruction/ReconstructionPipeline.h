#pragma once
/// @file ReconstructionPipeline.h
/// @brief The whole per-frame reconstruction of the paper: rectification (when calibrated), stereo (section II),
/// tracking (III.A-C), and at key frames the refinement (III.D) and the point-based TSDF fusion (III.E).
///
/// Within process(), stages that need not wait for each other run on helper threads (docs/RECONSTRUCTION.md,
/// "Stages side by side"): stereo beside tracking, the surface and the model sample beside the key frame's
/// matching. All of a frame's work is done when process() returns, and the result is the same as one stage after
/// another.
///
/// Not thread-safe: one thread calls process(); the logic layer runs it off the GUI thread and reads results
/// through the FrameResult it returns and modelSnapshot().
#include "Core/Device.h"
#include "Core/PixelFormat.h"
#include "Core/StereoRig.h"
#include "Deformation/DeformationTracker.h"
#include "Fusion/ModelAgreement.h"
#include "Fusion/PointModel.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/DisparityRangeFollower.h"
#include "Stereo/StereoMatcher.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tissuemosaic {

/// Milliseconds per stage of one frame, named as the paper's runtime table. Stages that did not run are 0.
struct StageTimesMs {
  double videoReading = 0;  ///< decoding and rectification (filled by the caller that reads the video)
  double stereo = 0;
  double orbVoting = 0;
  double pnp = 0;           ///< DynamicR1PPnP
  double agreement = 0;     ///< the model agreement and the motion evidence (not in the paper; tracked frames)
  double refinement = 0;    ///< key frames only
  double tsdf = 0;          ///< key frames only
  double deformation = 0;   ///< the deformation graph's fit (not in the paper; fusion.deformation on, tracked frames)
  double total = 0;
};

/// The refinement stage of a key frame in parts (milliseconds): the stereo surface measurement, the model points
/// seen from the tracked pose (sampled beside the surface), the choice of the ICP term's among them, the matching
/// with earlier key frames and with intermediate frames, and the LM solve. Some run side by side, so the stage's own
/// timeline follows: the matching call on the calling thread (both matchings inside it), the wait for the surface
/// and the ICP points after it, and the call that assembles the problem, solves it and stores the key frame.
struct RefinementPartsMs {
  double surface = 0, modelSample = 0, icpSelection = 0, keyFrameMatching = 0, intermediateMatching = 0, solve = 0;
  double matchingCall = 0, surfaceWait = 0, solveCall = 0;
};

/// The ORB + voting stage's parts (FrameTracker's TrackResult): extraction (grey conversion, ORB, and the lift of
/// the features, not counting the wait for the disparity before it), Hamming matching, sub-pixel refinement, voting.
struct TrackingPartsMs {
  double extract = 0, match = 0, subPixel = 0, vote = 0;
};

/// How a frame's pose came about.
enum class FrameStatus {
  Tracked,      ///< tracked against the last key frame
  Lost,         ///< no pose (too few matches, no solution, an implausible jump, or the model agreement collapsed)
  Relocalised,  ///< the first pose after lost frames (against the last key frame or a stored one)
};
const char* frameStatusName(FrameStatus status);  ///< "tracked", "lost", "relocalised"

/// What moved at a tracked frame (docs/SCENE_MOTION.md, "What moved"): the camera (its pose moved more than
/// kCameraStillMmPerFrame or kCameraStillDegPerFrame since the last tracked frame), the tissue (at least
/// kTissueMovingShare of the key frame's matches moved with the scene, or the model disagreed with a pose that
/// continues the scope's motion), both, or neither. Unknown for a lost or first frame.
enum class SceneMotion { Unknown, Still, Camera, Tissue, Both };
const char* sceneMotionName(SceneMotion motion);  ///< "unknown", "still", "camera", "tissue", "both"
constexpr double kCameraStillMmPerFrame = 0.1, kCameraStillDegPerFrame = 0.1;
constexpr double kTissueMovingShare = 0.2;

struct FrameResult {
  int frameIndex = 0;
  bool tracked = false;         ///< status != Lost
  FrameStatus status = FrameStatus::Lost;
  bool keyFrame = false;
  /// Why tracking was lost (empty when tracked); for a relocalised frame, against which key frame.
  std::string trackingMessage;
  /// The quality signal: the model seen from the tracked pose against the frame's stereo depth (ModelAgreement.h);
  /// not measured for a lost frame or before the model has points.
  ModelAgreement agreement;
  AgreementLevel agreementLevel = AgreementLevel::None;
  int movingMatches = 0;        ///< key-frame feature matches kept out of the pose (they moved with the scene)
  /// The model's deformation at this frame (fusion.deformation on, tracked frames; DeformationTracker.h).
  DeformationFrame deformation;
  int pointsRemoved = 0;        ///< model points that left the model on this frame's motion evidence
  /// The model disagreed with the frame's depth at a pose that continues the scope's motion
  /// (FrameTracker::continuesMotion): the pose was kept, the tissue moved.
  bool tissueMoved = false;
  SceneMotion sceneMotion = SceneMotion::Unknown;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();  ///< left rectified camera to world, mm; refined at key frames
  int inliers = 0;
  bool refined = false;         ///< key frame: the refinement improved the tracked pose
  int matchedKeyFrames = 0;     ///< key frame: earlier key frames matched for the refinement
  int guidedKeyFrames = 0;      ///< ... of them matched near their projections (RefinementResult::guidedKeyFrames)
  int intermediateFrames = 0;   ///< key frame: intermediate frames in the refinement's bundle adjustment
  int guidedIntermediateFrames = 0;  ///< ... of them matched near the projections (RefinementResult::guidedFrames)
  int fusedMerged = 0, fusedAdded = 0;  ///< key frame: model points merged with / added from this frame
  std::size_t modelPoints = 0;
  bool pointBudgetReached = false;
  StageTimesMs timesMs;
  RefinementPartsMs refinementPartsMs;  ///< key frames only
  StereoTimingsMs stereoPartsMs;        ///< the stereo stage's parts (its GPU stages in device time)
  TrackingPartsMs trackingPartsMs;
  /// 8-bit, 3 channels in `channelOrder` (BGR unless process() was given RGB frames); the right view moved onto the
  /// left's rows where the first frame found the pair out of rectification (DisparityRangeFollower::alignedRight)
  cv::Mat leftRectified, rightRectified;
  ChannelOrder channelOrder = ChannelOrder::Bgr;
  cv::Mat disparityPx;                    ///< CV_32F, NaN = none; empty when the pipeline keeps none (setFrameDisparityKept)
  DisparityRange disparityRange;          ///< the range this frame was matched over
  RangeEndCounts disparityRangeEnds;      ///< its winners on the range's ends (rangeTooNarrowWarning)
  /// Automatic range: milliseconds of the sparse left-right matching: the first frame's, before its stereo on the
  /// calling thread; later, every DisparityRangeEstimatorOptions::sampleEveryFrames-th frame is measured on a thread
  /// of its own beside the frames after it, and its time is given on the frame that applies it. 0 otherwise.
  double disparityRangeMs = 0;
  /// How long this frame waited for that measurement to end before it could apply it (0: it had ended).
  double disparityRangeWaitMs = 0;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

struct KeyFramePose {
  int frameIndex = 0;
  double timeS = 0;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

class ReconstructionPipeline {
public:
  /// geometry: of the rectified frames process() receives, or computed from `calibration` (then process() rectifies
  /// the raw frames). T_world_startCamera: the first frame's pose (identity: the world is the first left rectified
  /// camera). Throws Error for invalid parameters or geometry, or CUDA asked for where there is none.
  ReconstructionPipeline(const RectifiedGeometry& geometry, const ReconstructionParameters& parameters, Device device,
                         const Eigen::Matrix4d& T_world_startCamera = Eigen::Matrix4d::Identity());
  ReconstructionPipeline(const StereoCalibration& calibration, const ReconstructionParameters& parameters, Device device,
                         const Eigen::Matrix4d& T_world_startCamera = Eigen::Matrix4d::Identity());
  ~ReconstructionPipeline();
  ReconstructionPipeline(const ReconstructionPipeline&) = delete;
  ReconstructionPipeline& operator=(const ReconstructionPipeline&) = delete;

  /// Processes the next stereo frame (8-bit grey or BGR, both the rig's size). timeS: its time stamp (TUM output).
  /// order: the frames' channel order. RGB frames (Python, Pillow, PyTorch) are taken as they are, without a copy:
  /// the stages that work in grey get them converted with the same weights, and the model's colours are read in
  /// that order, so the result is the BGR twin's bit for bit.
  /// Throws Error for misuse (empty or mismatched frames), and, with the automatic disparity range, when the first
  /// frame has too few left-right feature matches to choose it (the message says what was found); lost tracking is
  /// reported in the result.
  FrameResult process(const cv::Mat& left, const cv::Mat& right, double timeS,
                      ChannelOrder order = ChannelOrder::Bgr);

  const RectifiedGeometry& geometry() const;
  const ReconstructionParameters& parameters() const;
  Device device() const;
  int frameCount() const;
  /// Key frames so far with their refined poses, in order.
  const std::vector<KeyFramePose>& keyFrames() const;
  /// A host copy of the fused model (world frame = the first left rectified camera, mm).
  ModelPoints modelSnapshot() const;
  /// The fused model where the tissue is now (the live surface, fusion.deformation on): modelSnapshot() moved by
  /// the last frame's deformation; modelSnapshot() itself when the deformation is off.
  ModelPoints liveModelSnapshot() const;
  std::size_t modelPointCount() const;
  /// Peak device memory in use, sampled after every frame (cudaMemGetInfo: includes the CUDA context; 0 on the CPU).
  std::size_t peakDeviceBytes() const;
  /// The disparity ranges used so far (StereoParameters::disparityRangeMode; DisparityRangeFollower.h).
  const DisparityRangeHistory& disparityRangeHistory() const;
  /// One line, e.g. "auto: 64..95 px (first frame: 412 left-right matches)".
  std::string disparityRangeDescription() const;
  /// Whether process() downloads the frame's disparity into FrameResult::disparityPx (default: yes). Callers that
  /// neither show nor write it switch it off: on CUDA the map stays on the device (8 MB a frame at 1920x1080, 0.65 ms
  /// of the stereo thread on an H100 host). downloadLastDisparity() still gives the last frame's on demand.
  void setFrameDisparityKept(bool kept);
  /// A host copy (CV_32F, NaN = none) of the last processed frame's disparity. Throws Error before the first frame.
  cv::Mat downloadLastDisparity() const;
  /// The deformation graph over the model (fusion.deformation on), null when off.
  const DeformationGraph* deformationGraph() const;
  /// The deformation with its canonical and live surface samples (fusion.deformation on), null when off.
  const DeformationTracker* deformation() const;
  /// What the last key frame's refinement did (for logs and the GUI).
  const std::string& lastRefinementMessage() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
