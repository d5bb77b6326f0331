#pragma once
/// @file DeformationFit.h
/// @brief One frame's deformation: the graph's node motions (DeformationGraph.h) fitted so that the warped canonical
/// points lie on the surface the frame measured, by Gauss-Newton on
///   E = sum_c rho(n_c . (warp(p_c) - q_c))                 (point-to-plane, Huber's rho; feature matches: each axis)
///     + w_reg sum_i sum_{j in N(i)} |R_i (g_j - g_i) + g_i + t_i - (g_j + t_j)|^2   (as rigid as possible)
///     + w_rest sum_i |P_i t_i|^2 + w_rest,n sum_i (n_i . t_i)^2   (rest: P_i projects on the node's tangent plane)
///     + w_rest,R sum_i |log R_i|^2                                  (rotations at rest)
/// over every node's rotation (updated as R <- exp(theta) R) and translation, the sparse normal equations solved by
/// a sparse Cholesky factorisation. The correspondences come from the caller (the pipeline associates the live model
/// with the frame's depth through the camera pose); the fit starts from the graph's current motions (the last
/// frame's), so a caller iterates association and fit as ICP does.
///
/// World frame, millimetres. The camera's pose is the caller's: the field describes the tissue's motion in the world.
#include "Deformation/DeformationGraph.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace tissuemosaic {

/// A canonical model point and where the frame says its surface is now: a dense depth sample (point to plane: only
/// the motion along the normal is seen) or a feature match (point to point: the same tissue point, so the motion
/// along the surface is seen too).
struct DeformationCorrespondence {
  Eigen::Vector3d canonicalMm = Eigen::Vector3d::Zero();  ///< p: on the canonical model
  Eigen::Vector3d targetMm = Eigen::Vector3d::Zero();     ///< q: a measured surface point (world)
  Eigen::Vector3d targetNormal = Eigen::Vector3d::UnitZ(); ///< n: the measured surface's unit normal at q
  bool pointToPoint = false;  ///< q is p's own tissue point (a feature match): all three axes are residuals
  /// p's nodes and weights when the caller has them (graph.influence(p)); otherwise the fit finds them.
  std::optional<NodeInfluence> influence;
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};
using DeformationCorrespondences =
    std::vector<DeformationCorrespondence, Eigen::aligned_allocator<DeformationCorrespondence>>;

struct DeformationFitParameters {
  int iterations = 4;                 ///< Gauss-Newton steps per call
  double regularisationWeight = 1;    ///< w_reg: per neighbour pair and mm, against one data residual per mm
  /// w_rest: pulls each node toward rest along the surface (its restNormal's tangent plane), where the depth does not
  /// see its motion and it would slide; in every direction for a node without a rest normal.
  double restWeight = 1;
  /// ... and along its rest normal, where the depth measures it. As restWeight by default: smaller let samples drift
  /// along their normals where an instrument hid the tissue (hard-mode scan: 2.18 mm RMS from the rest surface at
  /// 0.001, 1.98 at 1).
  double restNormalWeight = 1;
  /// w_rest,R: pulls each node's rotation toward the identity, per rad^2 (16: as restWeight on a 4 mm arm, the node
  /// spacing). Without it a node that little depth reaches (at the edge of the view) turned freely from frame to
  /// frame, and the tissue it carries leaned: on the hard-mode scan the model at rest leaned by 1 mm at the sides.
  double restRotationWeight = 16;
  double huberMm = 1.0;               ///< data residuals beyond this count linearly (outliers, wrong associations)

  /// Throws Error naming the first parameter out of range.
  void validate() const;
};

struct DeformationFitResult {
  int correspondences = 0;     ///< used (with at least one node near)
  int iterations = 0;
  double dataRmsMm = 0;        ///< RMS residual after the fit (distances to the planes, feature matches per axis)
  double meanNodeMotionMm = 0; ///< |t| over the nodes the data reached
  double maxNodeMotionMm = 0;
};

/// Fits graph's node motions to the correspondences (see the file comment). Nodes the data does not reach follow
/// their neighbours. Throws Error for invalid parameters; an empty graph or no correspondences leave it unchanged.
DeformationFitResult fitDeformation(DeformationGraph& graph, const DeformationCorrespondences& correspondences,
                                    const DeformationFitParameters& parameters = {});

}  // namespace tissuemosaic
