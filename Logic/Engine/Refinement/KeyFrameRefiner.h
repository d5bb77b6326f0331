#pragma once
/// @file KeyFrameRefiner.h
/// @brief Key-frame refinement of paper section III.D. At each key frame T the refiner
///  1. picks the stored earlier key frames whose points project into T's view (tracked pose), matches their ORB
///     descriptors with T's and keeps DynamicR1PPnP's inliers: those feature points are fixed at the earlier key
///     frame's world position (the paper fixes the last key frame and its points against scale drift);
///  2. matches T's features with the intermediate frames since the last key frame (DynamicR1PPnP inliers), on the
///     refiner's own worker thread beside step 1, which it does not need;
///  3. minimises f_BA + beta f_ICP by Levenberg-Marquardt (RefinementSolver.h), alternating the free feature points
///     (one 3x3 LM per point) and the poses (one 6x6 LM per frame; only T's pose has the point-to-plane ICP term
///     with Tukey's penalty, q_i re-found at the pixel where each model point p_i projects at every evaluation);
///     the free points of T start where T's tracked pose lifts its stereo points, the intermediate frames'
///     observations come from their DynamicR1PPnP inliers refined to sub-pixel accuracy as the tracker does;
///  4. stores T compactly (pixels, descriptors, world points, pose; no images) for later key frames.
/// The per-point updates and the per-residual Jacobian rows run through parallelFor on the chosen device, from one
/// source (RefinementKernels.h).
///
/// Never a worse pose: when the cost does not fall, or the pose would move more than the parameters allow, the
/// tracked pose is kept and the result says why (refined = false).
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "Core/SurfaceMeasurement.h"
#include "Refinement/RefinementParameters.h"
#include "Tracking/StereoFeatures.h"
#include "Tracking/TrackingParameters.h"

#include <Eigen/Core>
#include <Eigen/StdVector>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace tissuemosaic {

class SubPixelMatcher;

/// A frame's pose: left rectified camera to world, mm.
struct FramePose {
  int frameIndex = 0;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

struct RefinementResult {
  /// The refined key-frame pose when refined is true, else the tracked pose unchanged.
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  bool refined = false;
  int matchedKeyFrames = 0;    ///< earlier key frames with enough DynamicR1PPnP inliers
  /// Earlier key frames whose DynamicR1PPnP ran on the matches found near the projections of their points (the rest:
  /// on all descriptor matches; RefinementParameters::guidedSearchRadiusPx).
  int guidedKeyFrames = 0;
  int intermediateFrames = 0;  ///< intermediate frames in the bundle adjustment
  /// Intermediate frames matched near the projections of the key frame's features (the rest: all descriptors and
  /// DynamicR1PPnP; RefinementParameters::guidedSearchRadiusPx).
  int guidedFrames = 0;
  int baObservations = 0;      ///< reprojection residuals (2D observations of feature points)
  int fixedPoints = 0;         ///< feature points fixed at an earlier key frame's position
  int freePoints = 0;          ///< feature points optimised
  int icpPoints = 0;           ///< model points p_i in the ICP term
  int pnpHypotheses = 0;       ///< DynamicR1PPnP hypotheses tried over all its solves (key frames, intermediates)
  double beta = 0;             ///< weight of f_ICP
  double initialCost = 0, finalCost = 0;  ///< f_BA + beta f_ICP (robust) before and after
  int iterations = 0;          ///< pose LM iterations run
  double milliseconds = 0;     ///< the whole refineKeyFrame call
  /// Parts of it: matching and solving against the earlier key frames, against the intermediate frames, and LM.
  double keyFrameMatchingMs = 0, intermediateMatchingMs = 0, solveMs = 0;
  std::string message;         ///< what happened (why not refined)
  /// Refined poses of the intermediate frames in the bundle adjustment (empty when not refined).
  std::vector<FramePose, Eigen::aligned_allocator<FramePose>> intermediatePoses;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The first half of a key frame's refinement (KeyFrameRefiner::matchKeyFrame): its matches with the earlier key
/// frames and the intermediate frames. It needs no surface, so the surface can be measured meanwhile.
class KeyFrameMatches {
public:
  KeyFrameMatches();
  ~KeyFrameMatches();
  KeyFrameMatches(KeyFrameMatches&&) noexcept;
  KeyFrameMatches& operator=(KeyFrameMatches&&) noexcept;

private:
  friend class KeyFrameRefiner;
  struct Data;
  std::unique_ptr<Data> data_;
};

/// The model points p_i of a key frame's ICP term (KeyFrameRefiner::selectIcpModelPoints), for the pose they were
/// selected at.
struct IcpModelPoints {
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();  ///< the key frame's tracked pose
  std::vector<Eigen::Vector3f> pointsWorldMm;                     ///< empty: no ICP term
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// A stored key frame as others read it (relocalisation): its pose, and its features with depth (pixels,
/// descriptors, world points). The references stay valid until the refiner next stores or forgets a key frame.
struct StoredKeyFrameView {
  int frameIndex = 0;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  const std::vector<cv::Point2f>* pixelsPx = nullptr;
  const cv::Mat* descriptors = nullptr;  ///< CV_8U, one row per pixel
  const std::vector<Eigen::Vector3f>* pointsWorldMm = nullptr;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Omega's frames: the intermediate frames since the last key frame, the current key frame, and the earlier key
/// frames it overlaps. Not thread-safe.
class KeyFrameRefiner {
public:
  /// geometry: of the rectified frames the features come from. tracking: DynamicR1PPnP parameters for the matches;
  /// features: matching (Hamming distance, candidates, voting bins, sub-pixel refinement). Throws Error for invalid
  /// parameters, or for Device::Cuda in a build or on a machine without CUDA.
  /// subPixelMatcher: the sub-pixel matcher to use (on `device`), e.g. the tracker's, whose device copies of the
  /// frames the refiner then reuses; null: the refiner makes its own.
  KeyFrameRefiner(const RectifiedGeometry& geometry, const RefinementParameters& parameters,
                  const TrackingParameters& tracking, const FeatureParameters& features, Device device,
                  std::shared_ptr<SubPixelMatcher> subPixelMatcher = nullptr);
  ~KeyFrameRefiner();
  KeyFrameRefiner(const KeyFrameRefiner&) = delete;
  KeyFrameRefiner& operator=(const KeyFrameRefiner&) = delete;

  /// A tracked non-key frame since the last key frame (kept until the next key frame; thinned evenly to
  /// maxIntermediateFrames). Throws Error when the pose is not rigid.
  void addIntermediateFrame(int frameIndex, const StereoFeatures& features, const Eigen::Matrix4d& T_world_camera);

  /// Refines the key frame: matches its features with the intermediate frames and with the earlier key frames that
  /// overlap it (DynamicR1PPnP on the matches), minimises f_BA + beta f_ICP by LM alternating points and poses (the
  /// earlier key frames and the points they observe are fixed), stores the key frame for later matching (with the
  /// returned pose), clears the intermediate frames, and returns the refined pose.
  /// measurement: the key frame's stereo surface (q_i, n_i); may be empty when there are no model points.
  /// modelPointsWorldMm / modelNormalsWorld: the fused model seen from the tracked pose (empty for the first key
  /// frame: then BA only; the normals may be empty, they are not used: the ICP term takes n_i from the measurement).
  /// Without a matched earlier key frame nothing anchors the bundle adjustment: only the ICP term refines the pose,
  /// and without that either the tracked pose is returned (refined = false).
  RefinementResult refineKeyFrame(int frameIndex, const StereoFeatures& features, const Eigen::Matrix4d& T_world_camera,
                                  const SurfaceMeasurement& measurement,
                                  const std::vector<Eigen::Vector3f>& modelPointsWorldMm,
                                  const std::vector<Eigen::Vector3f>& modelNormalsWorld);

  /// refineKeyFrame in three parts, so that other work (measuring the surface, sampling the model, choosing the ICP
  /// points) can run between or beside them. matchKeyFrame and selectIcpModelPoints only read the refiner and may
  /// run at the same time on different threads; features must stay alive and unchanged until
  /// refineMatchedKeyFrame, and no frame may be added in between (Error). icp must be selected at the pose the
  /// matches were made at (Error).
  KeyFrameMatches matchKeyFrame(int frameIndex, const StereoFeatures& features, const Eigen::Matrix4d& T_world_camera);
  RefinementResult refineMatchedKeyFrame(KeyFrameMatches matches, const SurfaceMeasurement& measurement,
                                         const IcpModelPoints& icp);

  /// The ICP term's model points for a key frame at its tracked pose T_world_camera: those of modelPointsWorldMm
  /// that project onto a pixel where the measurement has a point and a normal, evenly subsampled to
  /// RefinementParameters::icpSamples; none when fewer than minIcpPoints land there or either input is empty.
  /// Throws Error for a measurement without usable maps.
  IcpModelPoints selectIcpModelPoints(const SurfaceMeasurement& measurement,
                                      const std::vector<Eigen::Vector3f>& modelPointsWorldMm,
                                      const Eigen::Matrix4d& T_world_camera) const;

  /// Key frames stored for matching.
  int keyFrameCount() const;
  /// Stored key frame i (0 = the oldest kept), 0 <= i < keyFrameCount() (Error otherwise).
  StoredKeyFrameView storedKeyFrame(int i) const;
  /// The stored key frames whose points fall into the view at T_world_camera (at least minKeyFrameOverlap of them),
  /// the most overlapping first: the refinement's candidates before its maxMatchedKeyFrames cap.
  std::vector<int> keyFramesInView(const Eigen::Matrix4d& T_world_camera) const;
  /// Forgets the intermediate frames held for the next key frame (e.g. when tracking was lost since them).
  void clearIntermediateFrames();
  /// Intermediate frames held for the next key frame.
  int intermediateFrameCount() const;
  /// Bytes held by the stored key frames (pixels, descriptors, world points).
  std::size_t storedBytes() const;
  /// Forgets every key frame and intermediate frame.
  void reset();

  Device device() const;
  const RefinementParameters& parameters() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
