#pragma once
/// @file PnpSolver.h
/// @brief Camera pose from 3D-2D matches with many outliers (paper III.B): R1PPnP (Zhou et al., TPAMI 2018) and the
/// paper's DynamicR1PPnP, which also weighs candidate 2D matches per 3D point while the pose converges.
///
/// Both are 1-point RANSAC: a control point o (taken in vote order) pins the camera centre onto o's viewing ray;
/// R, the scale mu = 1/depth(o) and every depth lambda_i are then updated in turn to minimise
/// sum_i w_i ||lambda_i x_i - x_o - mu R (X_i - X_o)||^2, re-weighting w_i = min(1, H / e_i) from the reprojection
/// error e_i (px). The hypothesis with the most inliers (e_i <= H) wins and is polished by Gauss-Newton on the
/// reprojection error of its inliers.
///
/// Failure is a result, not an exception: degenerate input (fewer than 4 matches, non-finite values, coincident or
/// collinear 3D points, too few inliers) gives success = false and a reason, never a pose. Only misuse (arrays of
/// different lengths, vote indices out of range, invalid parameters) throws tissuemosaic::Error.
#include "Core/PinholeIntrinsics.h"
#include "Tracking/TrackingParameters.h"

#include <Eigen/Core>
#include <Eigen/StdVector>

#include <string>
#include <vector>

namespace tissuemosaic {

/// One candidate 2D match of a 3D point (DynamicR1PPnP), e.g. a further descriptor match in the current frame.
struct CandidateMatch {
  Eigen::Vector2d pixelPx = Eigen::Vector2d::Zero();
  double score = 1.0;  ///< in (0, 1]: scales the candidate's weight (1 = as trusted as geometry alone says)
};

using Points3d = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;
using Pixels2d = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;

struct PnpResult {
  bool success = false;
  /// World (object) frame to camera frame: X_camera = R X_world + t with R = block<3,3>(0,0), t = block<3,1>(0,3).
  /// The inverse is the pipeline's T_world_camera. Identity when success is false.
  Eigen::Matrix4d T_camera_world = Eigen::Matrix4d::Identity();
  /// Indices (into the 3D points) of the inliers, ascending: their chosen 2D match reprojects within H px.
  std::vector<int> inlierIndices;
  /// Parallel to inlierIndices: which 2D match is the inlier, -1 for the primary match, j >= 0 for candidate j.
  /// R1PPnP gives -1 throughout.
  std::vector<int> inlierMatch;
  int hypotheses = 0;          ///< control points tried (1-point RANSAC iterations)
  int innerIterations = 0;     ///< re-weighting iterations summed over all hypotheses
  double rmsInlierErrorPx = 0; ///< after polishing
  std::string failureReason;   ///< empty on success

  Eigen::Matrix3d rotation() const { return T_camera_world.block<3, 3>(0, 0); }
  Eigen::Vector3d translationMm() const { return T_camera_world.block<3, 1>(0, 3); }
};

/// R1PPnP. pointsMm[i] (world frame, mm) is seen at pixelsPx[i]. voteOrder: indices of the matches in the order they
/// should be tried as control points (histogram voting, best first); empty = input order. Indices not listed are
/// still tried after the listed ones.
PnpResult solveR1Ppnp(const Points3d& pointsMm, const Pixels2d& pixelsPx, const PinholeIntrinsics& intrinsics,
                      const TrackingParameters& parameters, const std::vector<int>& voteOrder = {});

/// DynamicR1PPnP. As solveR1Ppnp, plus candidates[i]: further 2D matches of point i (any number, typically up to
/// k = 2..4; candidates.size() must equal pointsMm.size() or be 0). A candidate whose error is < eta * H joins the
/// cost with weight min(H / e, 1) * score, normalised by the point's total (candidates + primary) and ramped in by
/// min((k - k0) / T, 1) from the iteration k0 it was first seen. Only primary matches serve as control points.
///
/// T_camera_world_guess (optional): a predicted pose, e.g. the previous frame's. The first control point's
/// hypothesis then starts from the depths and weights this pose implies instead of the weak-perspective start:
/// the same re-weighting iteration, entered near its end (tracking adjacent frames: about 4x fewer iterations).
/// The other hypotheses start as the paper's, so a wrong guess costs time, not robustness.
///
/// hypothesesAtOnce > 1: after the first hypothesis, the control points are tried that many at a time on the CPU
/// pool, each wave against the best pose before it (merged in order, so the answer does not depend on the thread
/// count). For sets that may need many hypotheses on a latency-critical path (the refinement's matches with earlier
/// key frames after tracking drifted); 1 is the paper's sequential loop.
PnpResult solveDynamicR1Ppnp(const Points3d& pointsMm, const Pixels2d& pixelsPx,
                             const std::vector<std::vector<CandidateMatch>>& candidates,
                             const PinholeIntrinsics& intrinsics, const TrackingParameters& parameters,
                             const std::vector<int>& voteOrder = {},
                             const Eigen::Matrix4d* T_camera_world_guess = nullptr, int hypothesesAtOnce = 1);

/// A solved pose polished again on the matches within thresholdPx of it (primary or candidate, re-selected until
/// the set settles, as the solvers' own last step): a tighter final fit that leaves out matches a little off, e.g.
/// points that moved with the scene. Failure (no pose) when fewer than max(minInliers, 4) matches remain or they do
/// not fix a pose. Throws Error for arrays of different lengths or a non-positive threshold.
PnpResult polishPnpPose(const Points3d& pointsMm, const Pixels2d& pixelsPx,
                        const std::vector<std::vector<CandidateMatch>>& candidates, const PinholeIntrinsics& intrinsics,
                        const Eigen::Matrix4d& T_camera_world, double thresholdPx, int minInliers);

/// The final fit that keeps scene motion out of a pose (not in the paper): `solved`'s pose polished again
/// (polishPnpPose) on the matches within a bound that follows the set's own matching noise: kFitMedianFactor times
/// the median reprojection error of solved's inliers, at least kFitMinPx, at most maxPx. Matches a little off
/// (points the scene moved, still within H) would otherwise bend the pose toward their motion. Returns `solved`
/// unchanged when it failed, the polish leaves too few matches, or maxPx is 0 (off). fitPx (optional): the bound used (maxPx when none).
PnpResult polishOnFittingMatches(const Points3d& pointsMm, const Pixels2d& pixelsPx,
                                 const std::vector<std::vector<CandidateMatch>>& candidates,
                                 const PinholeIntrinsics& intrinsics, const PnpResult& solved, double maxPx,
                                 int minInliers, double* fitPx = nullptr);
/// Rayleigh-distributed matching noise exceeds 3 medians about once in 200; sub-pixel matches are good to ~0.2 px.
constexpr double kFitMedianFactor = 3.0;
constexpr double kFitMinPx = 0.5;

/// Rotation angle (degrees) and camera-centre distance (mm) between two T_camera_world poses; for tests and benches.
void poseDifference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double& rotationDeg, double& centreMm);

}  // namespace tissuemosaic
