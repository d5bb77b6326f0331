#pragma once
/// @file DeformationTracker.h
/// @brief The tissue's deformation frame by frame (docs/DEFORMATION.md), on a canonical surface of its own: surface
/// samples every few pixels of the frames' stereo depth, each stored where the field says it rests (the inverse
/// warp), so the canonical surface is the tissue at the first frame's state wherever the field explains the motion.
/// Every frame, the samples in view are warped by the graph (DeformationGraph.h), associated with the frame's depth
/// along the camera's rays (point to plane on their turned normals) and the graph refitted (DeformationFit.h);
/// each sample then takes in its measurement through the inverse warp (a running average along its normal, as the
/// TSDF fusion does, up to maxSampleWeight frames), and pixels that no sample covers add new samples. The fused model (PointFusion) is not touched: its motion
/// evidence keeps moving tissue out of it, while these samples keep following it.
///
/// The camera pose is the caller's: the field is the tissue's motion in the world beyond the camera's. On the CPU for
/// both backends (a few thousand samples a frame); the caller passes the disparity on the host.
#include "Core/StereoRig.h"
#include "Deformation/DeformationFit.h"
#include "Deformation/DeformationGraph.h"
#include "Deformation/InfluenceCache.h"

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <opencv2/core.hpp>

#include <vector>

namespace tissuemosaic {

struct DeformationTrackerParameters {
  DeformationGraphParameters graph;
  DeformationFitParameters fit;
  int sampleStridePx = 8;             ///< one canonical sample per this many pixels in x and y where none is in view
  int maxFitSamples = 4000;           ///< samples in view used per fit (evenly thinned beyond)
  int associationRounds = 2;          ///< association + fit rounds per frame
  double maxAssociationMm = 5.0;      ///< a depth farther than this from the live sample (along its normal) is not its surface
  double agreementMm = 1.0;           ///< "within" for the live and rigid agreement shares
  double maxDepthJumpMm = 2.0;        ///< no sample (no normal) where a neighbour's depth differs by more than this
  double maxSampleWeight = 32;        ///< a sample's running average counts at most this many frames
  /// The camera takes the field's rigid part over the tissue the frame sees (RigidPart.h), so that the field holds
  /// only what moves against the rest: a camera error is then corrected, not taken on by the field as tissue motion
  /// (and fused as such). Where most of the view moves as one (breathing under a still scope), the camera takes that
  /// motion, as the rigid pipeline's does. Off: it made the model at rest better but the camera worse (hard-mode
  /// scan, largest frame error 2.43 mm against 0.78; docs/DEFORMATION.md).
  bool cameraTakesRigidPart = false;
  double rigidPartToleranceMm = 1.0;  ///< nodes moving farther than this from the rigid part do not count (Tukey)

  void validate() const;
};

/// What one frame's deformation did.
struct DeformationFrame {
  bool fitted = false;             ///< false: lost frame, or no depth met the samples
  int nodes = 0;
  int samples = 0;                 ///< canonical samples in all
  int samplesAdded = 0;            ///< ... added from this frame
  int correspondences = 0;         ///< samples in view associated with the frame's depth
  double meanNodeMotionMm = 0;     ///< |t| over the nodes the data reached (from rest)
  double maxNodeMotionMm = 0;
  double dataRmsMm = 0;            ///< point to plane after the fit
  /// Share of the samples in view (with a depth on their ray) within agreementMm of the frame's depth along their
  /// normal: warped (the live surface) and not warped (the canonical surface taken as rigid).
  double liveShareWithin1mm = 0;
  double rigidShareWithin1mm = 0;
  double milliseconds = 0;
  /// The correction the camera takes (cameraTakesRigidPart): the frame's pose is cameraCorrection * T_world_camera
  /// (world frame, mm). Identity otherwise.
  Eigen::Matrix4d cameraCorrection = Eigen::Matrix4d::Identity();
};

class DeformationTracker {
public:
  using Points = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;

  /// Throws Error for invalid parameters or a geometry without focal length or baseline.
  DeformationTracker(const RectifiedGeometry& geometry, const DeformationTrackerParameters& parameters = {});

  /// One tracked frame: its left disparity (CV_32F, NaN = none, the geometry's size) and the camera's pose. Throws
  /// Error for a disparity of another size or type.
  DeformationFrame update(const cv::Mat& disparityPx, const Eigen::Matrix4d& T_world_camera);

  const DeformationGraph& graph() const { return graph_; }
  /// The canonical surface samples (world mm) and their normals.
  const Points& canonicalPoints() const { return canonical_; }
  const Points& canonicalNormals() const { return normals_; }
  /// The samples where the tissue is now (the live surface), in the order of canonicalPoints().
  Points livePoints() const;
  const DeformationTrackerParameters& parameters() const { return parameters_; }

private:
  /// Finds the field's rigid part D over the nodes the correspondences reach, undoes it on them, returns D^-1.
  Eigen::Matrix4d takeRigidPart(const DeformationCorrespondences& correspondences);

  RectifiedGeometry geometry_;
  DeformationTrackerParameters parameters_;
  DeformationGraph graph_;
  Points canonical_, normals_;
  std::vector<float> weights_;  ///< per sample: the frames its running average holds
  InfluenceCache influences_;   ///< per sample: its nodes
};

}  // namespace tissuemosaic
