#pragma once
/// @file vtkTissueMosaicModelEvaluation.h
/// @brief A reconstructed model scored against a reference surface with known geometry (a synthetic scan's
/// groundtruth/surface.ply, a CT/MR segmentation): placement (trajectory alignment and/or ICP), the distance of
/// every model point to the surface, the share of the surface the model covers, and the trajectory errors.
/// Definitions: docs/EVALUATION.md. Millimetres; all inputs in one frame convention (coordinates as stored).
#include "IO/TrajectoryError.h"
#include "IO/TrajectoryTum.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceDistance.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace tissuemosaic {

struct SurfaceCoverage {
  double radiusMm = 0;
  double surfaceAreaMm2 = 0;  ///< area of the whole reference surface
  double coveredAreaMm2 = 0;  ///< area lying within radiusMm of some point
  /// coveredAreaMm2 / surfaceAreaMm2 (0 for a surface of no area).
  double share() const { return surfaceAreaMm2 > 0 ? coveredAreaMm2 / surfaceAreaMm2 : 0.0; }
};

/// The area of `surface` lying within radiusMm of some point. A triangle is decided whole where the distance of
/// its vertices to the nearest point settles it (a vertex at d from the nearest point: every point of a triangle
/// with longest edge L is within d + L of it and farther than d - L); the others are split into n x n equal
/// sub-triangles (edges at most radiusMm / 4, n <= 512), each counted by its centroid. Runs in parallel. Throws
/// Error for a radius that is not a positive number or no points.
SurfaceCoverage surfaceCoverage(const TargetSurface& surface, const std::vector<Eigen::Vector3d>& points,
                                double radiusMm);

/// The model's and the reference's camera trajectories (T_world_camera, TUM files).
struct EvaluationTrajectories {
  Trajectory model;
  Trajectory reference;
};

struct EvaluationOptions {
  /// 0: no coverage (e.g. against a reference of what must not be in the model, whose area would take long to cover).
  double coverageRadiusMm = 1.0;
  double timeToleranceS = 0.02;  ///< largest time-stamp difference of associated poses
  /// Largest accepted TrajectoryErrors::alignmentRotationSdDeg: beyond it the trajectory alignment cannot place the
  /// model (1 degree moves a point 90 mm from the path by 1.6 mm). Meant to stop short or straight paths (10 frames:
  /// ~16 degrees), not noisy long ones (30 key frames of a 10 s scan with 0.9 mm ATE: 0.6 degrees).
  double maxAlignmentRotationSdDeg = 1.0;
  /// False: the model and its trajectory are already in the reference's frame (e.g. a reconstruction started at the
  /// true first pose): the ATE is measured without alignment and the model is not moved.
  bool alignTrajectories = true;
  /// Leave out of the distances the model points whose closest reference point lies on the reference's edge
  /// (TargetSurface::onSurfaceEdge): points beyond a partial reference's outline or over a hole in it (a
  /// synthetic scan's static_surface.ply has one where the tissue breathes), where the distance measures the gap,
  /// not the model's error. They are counted in ModelEvaluation::pointsBeyondReferenceEdge.
  bool excludeBeyondReferenceEdge = false;
  bool icp = false;              ///< refine the placement by ICP before measuring
  IcpParameters icpParameters;

  /// Throws Error naming the first invalid value (ICP parameters are checked by refineIcp).
  void validate() const;
};

struct ModelEvaluation {
  /// How the model was placed: "none" (taken in the reference frame), "trajectory" (rigid alignment of the
  /// trajectories), "icp", or "trajectory+icp".
  std::string alignment = "none";
  Eigen::Matrix4d T_reference_model = Eigen::Matrix4d::Identity();  ///< the final placement
  std::optional<TrajectoryErrors> trajectory;  ///< given trajectories: ATE after their rigid alignment, RPE
  std::optional<IcpResult> icp;                ///< with options.icp
  DistanceStatistics distances;                ///< every (scored) model point's distance to the reference surface
  std::size_t pointsBeyondReferenceEdge = 0;   ///< left out by options.excludeBeyondReferenceEdge
  SurfaceCoverage coverage;                    ///< of the reference surface by the placed model (radius 0: none)
};

/// Places the model (trajectories given: the rigid alignment of the model trajectory's positions onto the
/// reference's, poses associated by time; then ICP from there when asked), then measures. Throws Error for an
/// empty model, invalid options, trajectories without a pose or without common time stamps (the message gives
/// both time ranges), an alignment less certain than options.maxAlignmentRotationSdDeg, and the errors of
/// trajectoryErrors and refineIcp.
ModelEvaluation evaluateModel(const std::vector<Eigen::Vector3d>& modelPoints, const TargetSurface& reference,
                              const EvaluationTrajectories* trajectories, const EvaluationOptions& options = {});

}  // namespace tissuemosaic
