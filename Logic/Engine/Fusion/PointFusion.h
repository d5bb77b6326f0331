#pragma once
/// @file PointFusion.h
/// @brief Point-based TSDF fusion (paper III.E): the model is a growing set of points (position, colour, normal,
/// weights) in device memory, no voxel grid. Each key frame's surface measurement is merged into the model points
/// it sees, and its uncovered pixels are appended as new points, up to a point budget.
///
/// integrate(): every model point is projected into the key frame; the measurement at its pixel "agrees" when the
/// measured surface (the tangent plane of the measured point) crosses the point's viewing ray within truncationMm
/// and the normals differ by less than maxNormalAngleDeg. An agreeing point merges (running averages of its position
/// along its viewing ray, its normal and its colour, the colour weighted by the centre-to-edge weight; weights
/// capped at maxWeight) and marks the agreeing pixels within coverageRadiusPx as covered. Merging is per model point,
/// so every point that agrees merges, not only the z-buffer's nearest (a model denser than the pixels, seen again
/// from farther away, is averaged whole), and an occluded point fails the depth test by itself. Measured pixels
/// (with a normal) left uncovered are appended in pixel order while the budget lasts.
#include "Core/Device.h"
#include "Core/Image.h"
#include "Core/StereoRig.h"
#include "Core/SurfaceMeasurement.h"
#include "FusionParameters.h"
#include "ModelAgreement.h"
#include "PointModel.h"

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <vector>

namespace tissuemosaic {

/// What one integrate() call did.
struct FusionStats {
  int merged = 0;            ///< model points updated by a measurement
  int added = 0;             ///< new points appended
  int refusedForBudget = 0;  ///< new points not appended because the budget was reached
  double milliseconds = 0;   ///< wall time of the call (device synchronised)
};

namespace fusion {
struct FusionModel;  // device-resident state (FusionPipeline.h)
}

/// A model point's rigid motion from where its tissue rests to where it is now: live = rotation * rest +
/// translationMm (world frame, mm).
struct PointMotion {
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();
  Eigen::Vector3f translationMm = Eigen::Vector3f::Zero();
};

/// What the fusion needs of a deformation field to fuse a deforming tissue (Deformation/ModelWarp.h implements it
/// over the deformation graph): the model then holds the tissue at rest (the canonical model), and each frame meets
/// it where the field says it is now.
class ModelDeformation {
public:
  virtual ~ModelDeformation() = default;
  /// The motions of the model's points, given where they rest (world mm), index for index. The model's indices are
  /// stable (points are only appended), so an implementation may keep per-index state.
  virtual void motionsOf(const std::vector<Eigen::Vector3f>& restMm, std::vector<PointMotion>& motions) = 0;
  /// Where points measured now rest (the inverse of the field), with their motions.
  virtual void restOf(const std::vector<Eigen::Vector3f>& liveMm, std::vector<Eigen::Vector3f>& restMm,
                      std::vector<PointMotion>& motions) = 0;
  /// How far from the frame's depth the field may leave tissue that it follows (mm): motion evidence, which takes
  /// out of the model what moved, counts only depths farther than this from a moved point (what the field cannot
  /// explain: tissue cut or torn, a fold it cannot follow).
  virtual double explainedWithinMm() const = 0;
};

/// The disparities whose depth lies inside the fusion's working range [minDepthMm, maxDepthMm] (the rest count as
/// missing): what fusion, the refinement's ICP term and the model agreement measure with.
DisparityRangePx workingDisparityRange(const RectifiedGeometry& geometry, const FusionParameters& fusion);

class PointFusion {
public:
  /// Throws Error on invalid parameters or geometry, or when `device` is Cuda in a build/machine without CUDA.
  PointFusion(const RectifiedGeometry& geometry, const FusionParameters& parameters, Device device);
  ~PointFusion();
  PointFusion(PointFusion&&) noexcept;
  PointFusion& operator=(PointFusion&&) noexcept;
  PointFusion(const PointFusion&) = delete;
  PointFusion& operator=(const PointFusion&) = delete;

  /// Fuses one key frame seen from T_world_camera (left rectified camera -> world, mm). The measurement must have
  /// the geometry's image size (Error otherwise). While the model follows a deformation (followDeformation), the
  /// frame meets every point where the field puts it, merges there and takes the merged point back to rest; the
  /// points it adds are stored where the field says they rest.
  FusionStats integrate(const SurfaceMeasurement& measurement, const Eigen::Matrix4d& T_world_camera);
  /// Moves the model to where `field` says the tissue is now: every later call (integrate, sampleVisible,
  /// measureAgreement, updateMotion, downloadLive) sees the points there, until the next call. The model itself
  /// stays at rest (download()). `field` must outlive the next integrate (which asks it where new points rest).
  /// Without a call, the model is rigid and every step is the rigid fusion's, bit for bit.
  void followDeformation(ModelDeformation& field);
  /// True once followDeformation was called (until reset()).
  bool deforming() const;
  /// Points in the model (those that left it through motion evidence not counted).
  std::size_t pointCount() const;
  /// Points that left the model by motion evidence and stay as moved-tissue markers (FusionParameters).
  std::size_t movedTissueMarkerCount() const;
  /// Markers retired: their tissue came to rest elsewhere (FusionParameters::markerRestFrames), or they were points
  /// fused once that frames saw through (FusionParameters::seenThroughFrames).
  std::size_t retiredMarkerCount() const;
  /// True once new points were refused for the budget (until reset()).
  bool budgetReached() const;
  /// Host copy of the whole model (where the tissue rests, when it deforms: the canonical model).
  ModelPoints download() const;
  /// Host copy of the model where the tissue is now (the live surface): download() moved by the last
  /// followDeformation's field; download() itself when the model does not deform.
  ModelPoints downloadLive() const;
  /// The model seen from a camera: up to maxPoints model points (world mm) and their normals (world) that project
  /// inside the image in front of the camera and pass the z-buffer (nearest per pixel), spread evenly over the
  /// image; not those that recent frames contradicted (motion evidence, kMaxSampledMotionEvidence). For the refinement's ICP term (p_i of the paper's eq. ICPterm). The samples are the z-buffer's pixels
  /// on a regular grid whose stride is the smallest that keeps them within maxPoints. Uses the fusion's scratch
  /// buffers: do not call concurrently with other members.
  void sampleVisible(const Eigen::Matrix4d& T_world_camera, int maxPoints,
                     std::vector<Eigen::Vector3f>& pointsWorldMm, std::vector<Eigen::Vector3f>& normalsWorld) const;
  /// The model agreement of a frame seen from T_world_camera (ModelAgreement.h): disparityPx is the frame's
  /// left-view disparity (NaN = none) in memory of the fusion's device (e.g. StereoMatcher::lastDisparity()), of the
  /// geometry's size; one pixel in sampleStridePx x sampleStridePx is compared. Uses the fusion's scratch buffers
  /// (not at the same time as other members). Throws Error for a disparity of another size.
  ModelAgreement measureAgreement(ImageView<const float> disparityPx, const Eigen::Matrix4d& T_world_camera,
                                  int sampleStridePx) const;
  /// The same with the disparity on the host (CV_32F), uploaded first where the fusion runs on CUDA.
  ModelAgreement measureAgreement(const cv::Mat& disparityPx, const Eigen::Matrix4d& T_world_camera,
                                  int sampleStridePx) const;
  /// Motion evidence of a tracked frame (FusionParameters' motion parameters): the model points its depth
  /// contradicts by more than the threshold lose weight; those at 0 leave the model. `agreement` is the frame's
  /// (measureAgreement at the same pose): a frame that agrees less than motionMinAgreementShare gives no evidence.
  /// Returns the points that left. disparityPx as for measureAgreement.
  int updateMotion(ImageView<const float> disparityPx, const Eigen::Matrix4d& T_world_camera,
                   const ModelAgreement& agreement);
  int updateMotion(const cv::Mat& disparityPx, const Eigen::Matrix4d& T_world_camera, const ModelAgreement& agreement);
  /// The depth difference beyond which a frame with this agreement contradicts a model point (mm); at least the
  /// field's explainedWithinMm while the model follows a deformation.
  double motionThresholdMm(const ModelAgreement& agreement) const;

  /// Bytes held on the device (0 on the CPU).
  std::size_t deviceBytes() const;
  /// Empties the model (keeps the parameters and the device).
  void reset();

  Device device() const { return device_; }
  const FusionParameters& parameters() const { return parameters_; }

private:
  ModelPoints downloadPoints(bool whereNow) const;
  /// Stores the points integrate appended (from index `first`) where the field says they rest, with their motions.
  void restNewPoints(std::size_t first);
  void uploadWarps();

  RectifiedGeometry geometry_;
  FusionParameters parameters_;
  Device device_;
  std::unique_ptr<fusion::FusionModel> model_;
  ModelDeformation* deformation_ = nullptr;  ///< the field the model follows (followDeformation), not owned
  std::vector<PointMotion> motions_;         ///< per model point, the last field's motion
};

}  // namespace tissuemosaic
