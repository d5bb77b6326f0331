#pragma once
/// @file R1PpnpCore.h
/// @brief Internal to PnpSolver: one R1PPnP hypothesis (a fixed control point) solved by alternating weighted
/// Procrustes (R, mu), depth projection (lambda_i) and re-weighting, over structure-of-arrays data so that Eigen
/// vectorises the per-match work. Candidate matches (DynamicR1PPnP) ride along in a second set of arrays.
#include "Tracking/TrackingParameters.h"

#include <Eigen/Core>

#include <vector>

namespace tissuemosaic::detail {

/// The matches in normalised camera coordinates (x = (u - cx) / fx, y = (v - cy) / fy). Single precision: the
/// hypotheses only need to sort inliers from outliers (8 SIMD lanes); the winner is polished in double.
struct PnpProblem {
  Eigen::Vector3d originMm = Eigen::Vector3d::Zero();  ///< world points are stored relative to this (their mean)
  Eigen::ArrayXf X, Y, Z;             ///< world points minus originMm, mm
  Eigen::ArrayXf xn, yn, invNorm2;    ///< primary matches; invNorm2 = 1 / (xn^2 + yn^2 + 1)
  Eigen::ArrayXf cX, cY, cZ;          ///< candidates: copies of their owner's world point
  Eigen::ArrayXf cxn, cyn, cInvNorm2, cScore;
  std::vector<int> cOwner;            ///< candidate -> index of its 3D point
  std::vector<int> cSlot;             ///< candidate -> its index within the owner's candidate list
  float fxPx = 1, fyPx = 1;

  int size() const { return static_cast<int>(X.size()); }
  int candidateCount() const { return static_cast<int>(cX.size()); }
};

struct Hypothesis {
  bool valid = false;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d tMm = Eigen::Vector3d::Zero();
  int inliers = 0;     ///< 3D points with a match (primary or candidate) within H px
  int iterations = 0;
};

class HypothesisSolver {
public:
  HypothesisSolver(const PnpProblem& problem, const TrackingParameters& parameters);
  /// Runs the re-weighting iterations with control point `controlIndex`. A hypothesis that still has fewer than
  /// abortBelowInliers inliers after the check iteration is abandoned early (returned invalid): that is what keeps
  /// 1-point RANSAC fast at 90 % outliers. guess (optional, T_camera_world): start the iterations from this pose's
  /// depths and weights instead of the weak-perspective start (all depths equal, all weights 1): the same iteration,
  /// but from near its end when the guess is close (e.g. the previous frame's pose): several times fewer iterations.
  Hypothesis solve(int controlIndex, int abortBelowInliers, const Eigen::Matrix4d* guess = nullptr);

private:
  void procrustes(float xo, float yo, Eigen::Matrix3d& M, double& denominator);
  int evaluate(const Eigen::Matrix3d& R, double mu, float xo, float yo, int iteration);

  const PnpProblem& p_;
  const TrackingParameters& params_;
  bool dynamic_;
  bool candidatesActive_ = false;
  // primary arrays
  Eigen::ArrayXf sx_, sy_, sz_, s2_, lam_, w_, e2_, a_, b_, c_;
  // candidate arrays
  Eigen::ArrayXf csx_, csy_, csz_, cs2_, clam_, cw_, ce2_, ca_, cb_, cc_, ownerSum_;
  std::vector<int> firstSeen_;
  double pNorm2_ = 0;
  Eigen::ArrayXf inv_;  ///< scratch: 1 / Y_z
  std::vector<unsigned char> inlierFlag_;
};

}  // namespace tissuemosaic::detail
