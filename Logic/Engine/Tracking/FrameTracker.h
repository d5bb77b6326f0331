#pragma once
/// @file FrameTracker.h
/// @brief Camera tracking of paper section III.A-C: ORB features of the rectified left image lifted to 3D with the
/// stereo disparity, brute-force Hamming matching (best match plus the next-best ones as DynamicR1PPnP candidates),
/// histogram voting on the 2D displacements (the control-point order), DynamicR1PPnP for the pose, and the key-frame
/// decision.
///
/// Not in the paper: every frame is matched with the LAST KEY FRAME (its features at its refined pose), not with
/// the previous frame, so that errors do not pile up frame by frame between key frames; and the scene's own motion
/// is kept out of the pose: a key-frame feature whose match lands off its projection (TrackingParameters::
/// dynamicResidualPx) moved with the scene, and features that moved recently neither steer the pose nor reach the
/// refinement (their 3D points are cleared in lastFeatures()). The pose is polished last on the matches within
/// dynamicResidualPx.
///
/// Lost tracking is a state, never a guessed pose: when there are too few matches, the solver fails, the pose jumps
/// implausibly far, or the caller's check refuses it (the model agreement), track() reports tracked = false with a
/// reason, and the next frame is matched against the last key frame again. The first frame tracked after lost ones
/// is `relocalised`; so is a frame whose pose the caller found otherwise (acceptRelocalisation).
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "Tracking/StereoFeatures.h"
#include "Tracking/TrackingParameters.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <functional>
#include <memory>
#include <string>

namespace tissuemosaic {

class SubPixelMatcher;

/// Which ORB implementation finds and matches the features.
enum class FeatureExtractor {
  OpenCvOrb,        ///< cv::ORB and cv::BFMatcher (CPU only)
  TissueMosaicOrb,  ///< OrbExtractor and HammingMatcher (Tracking/OrbFeatures.h) on featureDevice: CPU or CUDA
};

struct FrameTrackerOptions {
  TrackingParameters tracking;  ///< DynamicR1PPnP and key-frame parameters (the paper's)
  FeatureParameters features;   ///< ORB, matching and voting
  FeatureExtractor extractor = FeatureExtractor::OpenCvOrb;
  Device featureDevice = Device::Cpu;  ///< where TissueMosaicOrb runs
  double maxStepMm = 30.0;      ///< a camera moving farther than this per frame since the reference is lost, not fast
  double maxStepDeg = 20.0;     ///< ... and the same for rotation per frame
  /// The sub-pixel matcher to use (on featureDevice), e.g. one shared with the key-frame refiner so that the frames
  /// this tracker uploads are on the device when the refiner needs them; null: the tracker makes its own.
  std::shared_ptr<SubPixelMatcher> subPixelMatcher;

  void validate() const;
};

/// Where a track() call's time went (ms); one struct, so that a result that replaces another (a relocalisation
/// after a failed track) carries the failed attempt's times over whole.
struct TrackTimesMs {
  double orbVoting = 0;  ///< ORB detection, description, lifting, matching and histogram voting (not the disparity wait)
  double pnp = 0;        ///< DynamicR1PPnP
  /// orbVoting in parts: ORB and lifting, descriptor matching, sub-pixel refinement of the matches, voting.
  double extract = 0, match = 0, subPixel = 0, vote = 0;
};

struct TrackResult {
  int frameIndex = 0;
  bool tracked = false;          ///< false: lost (see failureReason); T_world_camera is then not valid
  bool keyFrame = false;
  bool initial = false;          ///< the first frame: pose = the start pose, no solve
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();  ///< left rectified camera to world (mm)
  int features = 0;              ///< ORB features in this frame
  int featuresWithDepth = 0;
  int matches = 0;               ///< reference features (with depth) that found a descriptor match here
  int inliers = 0;               ///< DynamicR1PPnP inliers (within dynamicResidualPx after the last polish)
  int movingMatches = 0;         ///< matches of key-frame features that moved recently: kept out of the pose
  bool relocalised = false;      ///< tracked again after lost frames
  double rmsErrorPx = 0;         ///< inliers' reprojection error
  /// Tracked against the last key frame: how far the pose moved per frame since the last tracked frame (the
  /// implausible-jump check's figures); 0 for the first and relocalised frames.
  double stepMmPerFrame = 0, stepDegPerFrame = 0;
  TrackTimesMs timesMs;
  std::string failureReason;     ///< empty when tracked
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

class FrameTracker {
public:
  /// geometry: of the rectified pair whose disparities track() receives. T_world_startCamera: pose of the first
  /// frame (identity: the world frame is the first left rectified camera). Throws Error for invalid options.
  FrameTracker(const RectifiedGeometry& geometry, const FrameTrackerOptions& options = {},
               const Eigen::Matrix4d& T_world_startCamera = Eigen::Matrix4d::Identity());
  ~FrameTracker();
  FrameTracker(const FrameTracker&) = delete;
  FrameTracker& operator=(const FrameTracker&) = delete;

  /// Tracks the next frame: the rectified left image (8-bit grey or BGR) and its left-view disparity (CV_32F,
  /// NaN = none). Throws Error only for misuse (empty or mismatched images).
  TrackResult track(const cv::Mat& leftRectified, const cv::Mat& disparityPx);
  /// Supplies the frame's disparity at the given left-image points (its features; DisparitySampling.h's rule, NaN =
  /// none) when the tracker needs it; it may block (e.g. on the stereo stage running on another thread), and it may
  /// sample the map where it lies (the GPU) instead of taking it to the host.
  using DisparitySource = std::function<std::vector<float>(const std::vector<cv::Point2f>& pointsPx)>;
  /// A check of a solved pose before it is taken (e.g. the model agreement): an empty string accepts it, a reason
  /// refuses it (the frame is then lost with that reason). Called after the frame's disparity was taken.
  using PoseCheck = std::function<std::string(const Eigen::Matrix4d& T_world_camera)>;
  /// The same, with the disparity asked for only after the features are matched and the pose is solved, so that the
  /// stereo stage can compute it meanwhile. `disparityPx` is called exactly once, on every path that returns.
  /// `check` (optional) may refuse the pose.
  TrackResult track(const cv::Mat& leftRectified, const DisparitySource& disparityPx, const PoseCheck& check = {});
  /// Takes a pose found for the last frame some other way (relocalisation against stored key frames) after track()
  /// reported it lost: the frame becomes the key frame later frames are tracked against. Returns the frame's result
  /// as tracked, relocalised key frame. Throws Error when the last frame was tracked or the pose is not rigid.
  TrackResult acceptRelocalisation(const Eigen::Matrix4d& T_world_camera, int inliers);
  /// True while the frames since the last tracked one are lost.
  bool isLost() const;
  /// The pose of the last tracked frame (the start pose before any) and its index (-1 before any).
  const Eigen::Matrix4d& lastTrackedPose() const;
  int lastTrackedFrame() const;

  /// The scope's motion prior for the frame last given to track(): the pose predicted from the last two tracked
  /// frames (constant velocity when they and this frame are consecutive, else the last tracked pose).
  Eigen::Matrix4d predictedPose() const;
  /// True when T_world_camera lies within the prior's step (TrackingParameters::priorStepMm, priorStepDeg) of
  /// predictedPose(): a pose that continues the scope's smooth motion.
  bool continuesMotion(const Eigen::Matrix4d& T_world_camera) const;

  /// Frames given to track() so far.
  int frameCount() const;
  /// The features of the frame last given to track() (empty before the first call), for key-frame refinement:
  /// features that moved with the scene have no 3D point (NaN).
  const StereoFeatures& lastFeatures() const;
  /// Replaces the pose of the last tracked frame (e.g. after key-frame refinement): later frames are tracked
  /// relative to the corrected pose, and a corrected key frame is the new reference of the key-frame decision and
  /// of tracking. Throws Error when the last frame was not tracked or the pose is not rigid.
  void correctLastPose(const Eigen::Matrix4d& T_world_camera);
  const FrameTrackerOptions& options() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
