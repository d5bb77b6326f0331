#pragma once
/// @file TrajectoryError.h
/// @brief Errors of an estimated camera trajectory against a reference one (TUM RGB-D benchmark conventions, Sturm
/// et al. 2012): poses associated by time stamp, an optional rigid alignment of the estimate onto the reference
/// (Umeyama without scale, on positions), the absolute trajectory error (ATE) and the translational relative pose
/// error (RPE) between consecutive associated poses. Millimetres and seconds; poses are T_world_camera.
/// The one place that computes these: `tissuemosaic track --groundtruth` and `tissuemosaic eval` both use it.
#include "IO/TrajectoryTum.h"

#include <Eigen/Core>

#include <cstddef>

namespace tissuemosaic {

/// Poses of two trajectories paired by time: estimate[i] goes with reference[i], in increasing estimate time.
struct AssociatedPoses {
  Trajectory estimate;
  Trajectory reference;
  std::size_t size() const { return estimate.size(); }
};

/// Pairs poses whose time stamps differ by at most toleranceS, one to one, closest pairs first (greedy, as the TUM
/// benchmark's associate.py). Neither trajectory needs to be sorted. Throws Error for a negative or non-finite
/// tolerance. The result may be empty: callers decide whether that is an error.
AssociatedPoses associateByTime(const Trajectory& estimate, const Trajectory& reference, double toleranceS);

enum class TrajectoryAlignment {
  None,  ///< both trajectories are taken to be in the same world frame
  Rigid  ///< the estimate's positions are first mapped onto the reference's by the least-squares rigid transform
};

struct TrajectoryErrors {
  std::size_t poses = 0;  ///< associated poses used
  /// The alignment applied: reference world <- estimate world (identity for TrajectoryAlignment::None). Apply it to
  /// anything else in the estimate's world (e.g. the reconstructed model) to bring it into the reference's.
  Eigen::Matrix4d T_reference_estimate = Eigen::Matrix4d::Identity();
  /// Rigid: standard deviation of the alignment's rotation about its least determined axis, estimated from the
  /// residuals (sigma^2 = sum |r_i|^2 / (3n - 6)) and the spread of the positions (sigma / sqrt(smallest eigenvalue of
  /// sum |p_i|^2 I - p_i p_i^T), p_i centred). Multiplied by the distance of something from the trajectory (the
  /// model, ~90 mm below a scope) it says how well the alignment places that: large for short or straight paths.
  double alignmentRotationSdDeg = 0;
  double ateRmseMm = 0;  ///< RMS of |T * p_estimate_i - p_reference_i| over the associated poses
  double ateMeanMm = 0;
  double ateMaxMm = 0;
  /// RMS over consecutive associated pairs (i, i+1) of the translation of
  /// (Q_i^-1 Q_i+1)^-1 (P_i^-1 P_i+1), Q reference and P estimate poses: the drift per step, independent of any
  /// global alignment. 0 with fewer than two poses (rpePairs = 0).
  double rpeRmseMm = 0;
  std::size_t rpePairs = 0;
};

/// ATE and RPE of associated poses. Throws Error when there is no pose, a pose is not finite, or (Rigid) when
/// fewer than 3 poses are given or the positions of either trajectory are (nearly) collinear, where the rotation
/// about their line is undetermined.
TrajectoryErrors trajectoryErrors(const AssociatedPoses& poses, TrajectoryAlignment alignment);

}  // namespace tissuemosaic
