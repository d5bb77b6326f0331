#include "IO/TrajectoryError.h"

#include "Core/Error.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

namespace tissuemosaic {

namespace {

Eigen::Matrix3Xd positions(const Trajectory& trajectory) {
  Eigen::Matrix3Xd result(3, static_cast<Eigen::Index>(trajectory.size()));
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    result.col(static_cast<Eigen::Index>(i)) = trajectory[i].T_world_camera.topRightCorner<3, 1>();
  }
  return result;
}

/// The rotation about a line through the positions is undetermined: require a spread across the best-fitting line
/// of at least 1% of the spread along it (the criterion registerLandmarks uses for landmarks).
void requireNotCollinear(const Eigen::Matrix3Xd& points, const char* which) {
  const Eigen::Matrix3Xd centred = points.colwise() - points.rowwise().mean();
  const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  if (!(singular(0) > 1e-9) || std::hypot(singular(1), singular(2)) < 0.01 * singular(0)) {
    throw Error(std::string("the associated positions of the ") + which +
                " trajectory are (nearly) collinear or coincident: the rotation of the rigid alignment about their "
                "line is undetermined");
  }
}

/// Inverse of a rigid 4x4 transform.
Eigen::Matrix4d rigidInverse(const Eigen::Matrix4d& T) {
  Eigen::Matrix4d inverse = Eigen::Matrix4d::Identity();
  inverse.topLeftCorner<3, 3>() = T.topLeftCorner<3, 3>().transpose();
  inverse.topRightCorner<3, 1>() = -T.topLeftCorner<3, 3>().transpose() * T.topRightCorner<3, 1>();
  return inverse;
}

}  // namespace

AssociatedPoses associateByTime(const Trajectory& estimate, const Trajectory& reference, double toleranceS) {
  require(std::isfinite(toleranceS) && toleranceS >= 0, "the time-stamp tolerance must be a non-negative number of s");
  // Reference indices in time order, so that the candidates of each estimate pose are found by binary search.
  std::vector<std::size_t> byTime(reference.size());
  std::iota(byTime.begin(), byTime.end(), std::size_t{0});
  std::sort(byTime.begin(), byTime.end(),
            [&](std::size_t a, std::size_t b) { return reference[a].timeS < reference[b].timeS; });
  std::vector<double> times(byTime.size());
  for (std::size_t k = 0; k < byTime.size(); ++k) times[k] = reference[byTime[k]].timeS;

  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;  // |dt|, estimate index, reference index
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double t = estimate[i].timeS;
    auto k = static_cast<std::size_t>(std::lower_bound(times.begin(), times.end(), t - toleranceS) - times.begin());
    for (; k < times.size() && times[k] <= t + toleranceS; ++k) {
      candidates.emplace_back(std::abs(times[k] - t), i, byTime[k]);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> estimateUsed(estimate.size(), false), referenceUsed(reference.size(), false);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& [dt, i, j] : candidates) {
    if (estimateUsed[i] || referenceUsed[j]) continue;
    estimateUsed[i] = referenceUsed[j] = true;
    pairs.emplace_back(i, j);
  }
  std::sort(pairs.begin(), pairs.end(), [&](const auto& a, const auto& b) {
    return estimate[a.first].timeS < estimate[b.first].timeS;
  });
  AssociatedPoses result;
  for (const auto& [i, j] : pairs) {
    result.estimate.push_back(estimate[i]);
    result.reference.push_back(reference[j]);
  }
  return result;
}

TrajectoryErrors trajectoryErrors(const AssociatedPoses& poses, TrajectoryAlignment alignment) {
  require(poses.estimate.size() == poses.reference.size(), "trajectory errors: the associated lists differ in length");
  require(poses.size() > 0, "trajectory errors: no associated poses");
  for (std::size_t i = 0; i < poses.size(); ++i) {
    require(poses.estimate[i].T_world_camera.allFinite() && poses.reference[i].T_world_camera.allFinite(),
            "trajectory errors: a pose is not finite");
  }
  const Eigen::Matrix3Xd estimated = positions(poses.estimate), reference = positions(poses.reference);
  TrajectoryErrors errors;
  errors.poses = poses.size();
  if (alignment == TrajectoryAlignment::Rigid) {
    require(poses.size() >= 3, "the rigid trajectory alignment needs at least 3 associated poses, got " +
                                   std::to_string(poses.size()));
    requireNotCollinear(estimated, "estimated");
    requireNotCollinear(reference, "reference");
    errors.T_reference_estimate = Eigen::umeyama(estimated, reference, false);
  }
  const Eigen::Matrix3Xd aligned =
      (errors.T_reference_estimate.topLeftCorner<3, 3>() * estimated).colwise() +
      errors.T_reference_estimate.topRightCorner<3, 1>();
  const Eigen::VectorXd ate = (aligned - reference).colwise().norm();
  errors.ateRmseMm = std::sqrt(ate.squaredNorm() / static_cast<double>(ate.size()));
  if (alignment == TrajectoryAlignment::Rigid) {
    // Linearised least squares: the rotation's information matrix is sum [p_i]x^T [p_i]x / sigma^2 (p_i centred).
    const Eigen::Matrix3Xd centred = estimated.colwise() - estimated.rowwise().mean();
    const Eigen::Matrix3d inertia =
        centred.colwise().squaredNorm().sum() * Eigen::Matrix3d::Identity() - centred * centred.transpose();
    const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia).eigenvalues()(0);
    const double sigma = std::sqrt(ate.squaredNorm() / (3.0 * static_cast<double>(poses.size()) - 6.0));
    constexpr double degreesPerRadian = 180 / 3.14159265358979323846;
    errors.alignmentRotationSdDeg =
        smallest > 0 ? sigma / std::sqrt(smallest) * degreesPerRadian : std::numeric_limits<double>::infinity();
  }
  errors.ateMeanMm = ate.mean();
  errors.ateMaxMm = ate.maxCoeff();

  // A global alignment cancels in P_i^-1 P_i+1, so the RPE is computed on the poses as given.
  double sumSquares = 0;
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) {
    const Eigen::Matrix4d referenceStep =
        rigidInverse(poses.reference[i].T_world_camera) * poses.reference[i + 1].T_world_camera;
    const Eigen::Matrix4d estimateStep =
        rigidInverse(poses.estimate[i].T_world_camera) * poses.estimate[i + 1].T_world_camera;
    const Eigen::Matrix4d error = rigidInverse(referenceStep) * estimateStep;
    sumSquares += error.topRightCorner<3, 1>().squaredNorm();
    ++errors.rpePairs;
  }
  errors.rpeRmseMm = errors.rpePairs ? std::sqrt(sumSquares / static_cast<double>(errors.rpePairs)) : 0.0;
  return errors;
}

}  // namespace tissuemosaic
