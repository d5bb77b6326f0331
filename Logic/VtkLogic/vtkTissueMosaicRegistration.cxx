#include "vtkTissueMosaicRegistration.h"

#include "Core/Error.h"
#include "vtkTissueMosaicSurfaceDistance.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

namespace tissuemosaic {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Throws when the points lie (nearly) on a line: their spread across the best-fitting line must be at least 1%
/// of their spread along it.
void requireNotCollinear(const Eigen::Matrix3Xd& points, const char* side) {
  const Eigen::Matrix3Xd centred = points.colwise() - points.rowwise().mean();
  const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  const double across = std::hypot(singular(1), singular(2));
  if (!(singular(0) > 1e-9) || across < 0.01 * singular(0)) {
    throw Error(std::string("the ") + side +
                " landmarks are (nearly) collinear or coincident: the rotation about their line is undetermined; "
                "pick at least 3 landmarks that span a triangle");
  }
}

}  // namespace

LandmarkRegistration registerLandmarks(const std::vector<Eigen::Vector3d>& modelLps,
                                       const std::vector<Eigen::Vector3d>& targetLps, bool withScale) {
  require(modelLps.size() == targetLps.size(), "the model and target landmark lists differ in length (" +
                                                   std::to_string(modelLps.size()) + " and " +
                                                   std::to_string(targetLps.size()) + ")");
  require(modelLps.size() >= 3, "registration needs at least 3 landmark pairs, got " + std::to_string(modelLps.size()));
  const auto n = static_cast<Eigen::Index>(modelLps.size());
  Eigen::Matrix3Xd model(3, n), target(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    model.col(i) = modelLps[static_cast<std::size_t>(i)];
    target.col(i) = targetLps[static_cast<std::size_t>(i)];
  }
  require(model.allFinite() && target.allFinite(), "a landmark position is not a finite number");
  requireNotCollinear(model, "model");
  requireNotCollinear(target, "target");

  LandmarkRegistration result;
  result.targetFromModel = Eigen::umeyama(model, target, withScale);
  result.scale = result.targetFromModel.topLeftCorner<3, 3>().col(0).norm();
  const Eigen::Matrix3Xd mapped =
      (result.targetFromModel.topLeftCorner<3, 3>() * model).colwise() + result.targetFromModel.topRightCorner<3, 1>();
  double sumSquares = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double residual = (mapped.col(i) - target.col(i)).norm();
    result.residualsMm.push_back(residual);
    sumSquares += residual * residual;
  }
  result.rmseMm = std::sqrt(sumSquares / static_cast<double>(n));
  return result;
}

IcpResult refineIcp(const std::vector<Eigen::Vector3d>& modelPointsLps, const TargetSurface& target,
                    const Eigen::Matrix4d& initialTargetFromModel, const IcpParameters& parameters) {
  require(parameters.maxIterations >= 0, "ICP: the maximum number of iterations must not be negative");
  require(parameters.inlierFraction > 0 && parameters.inlierFraction <= 1, "ICP: the inlier fraction must be in (0, 1]");
  require(parameters.maxDistanceMm > 0, "ICP: the maximum correspondence distance must be positive");
  require(parameters.tukeyCutoff > 0 && parameters.minSigmaMm > 0, "ICP: the Tukey cut-off and sigma floor must be positive");
  require(parameters.maxPoints >= 6, "ICP: at least 6 points are needed per step");
  require(!modelPointsLps.empty(), "ICP: the model has no points");
  require(initialTargetFromModel.allFinite(), "ICP: the initial transform is not finite");

  // An even subsample keeps a step's cost bounded on multi-million-point scans.
  std::vector<Eigen::Vector3d> points;
  const std::size_t stride =
      (modelPointsLps.size() + static_cast<std::size_t>(parameters.maxPoints) - 1) / static_cast<std::size_t>(parameters.maxPoints);
  for (std::size_t i = 0; i < modelPointsLps.size(); i += stride) points.push_back(modelPointsLps[i]);
  const std::size_t n = points.size();

  IcpResult result;
  result.targetFromModel = initialTargetFromModel;
  std::vector<Eigen::Vector3d> moved(n), normals(n);
  std::vector<double> residuals(n), distances(n), sorted;
  std::vector<char> kept(n);
  for (int iteration = 0; iteration < parameters.maxIterations; ++iteration) {
    const Eigen::Matrix3d linear = result.targetFromModel.topLeftCorner<3, 3>();
    const Eigen::Vector3d translation = result.targetFromModel.topRightCorner<3, 1>();
    for (std::size_t i = 0; i < n; ++i) {
      moved[i] = linear * points[i] + translation;
      const auto closest = target.closest(moved[i]);
      normals[i] = closest.normal;
      residuals[i] = closest.normal.dot(moved[i] - closest.pointLps);
      distances[i] = closest.distanceMm;
    }
    // Trimming: the closest inlierFraction of the correspondences, within maxDistanceMm.
    sorted = distances;
    const auto keep = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(parameters.inlierFraction * n))) - 1;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(keep), sorted.end());
    const double trimDistance = std::min(sorted[keep], parameters.maxDistanceMm);
    std::vector<double> absolute;
    for (std::size_t i = 0; i < n; ++i) {
      kept[i] = distances[i] <= trimDistance;
      if (kept[i]) absolute.push_back(std::abs(residuals[i]));
    }
    require(absolute.size() >= 6, "ICP: fewer than 6 model points lie within the correspondence distance of the "
                                  "target; start from a better landmark registration");
    const double sigma = std::max(parameters.minSigmaMm, 1.4826 * percentile(absolute, 50));
    const double cutoff = parameters.tukeyCutoff * sigma;

    // Linearised point-to-plane step about the kept points' centroid: r' = r + ((x - c) x n) . w + n . t.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    std::size_t keptCount = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (kept[i]) {
        centroid += moved[i];
        ++keptCount;
      }
    }
    centroid /= static_cast<double>(keptCount);
    Eigen::Matrix<double, 6, 6> normalMatrix = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> rightSide = Eigen::Matrix<double, 6, 1>::Zero();
    double weightedSquares = 0, weightSum = 0;
    std::size_t weighted = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!kept[i] || std::abs(residuals[i]) >= cutoff) continue;
      const double u = residuals[i] / cutoff;
      const double weight = (1 - u * u) * (1 - u * u);
      Eigen::Matrix<double, 6, 1> jacobian;
      jacobian << (moved[i] - centroid).cross(normals[i]), normals[i];
      normalMatrix += weight * jacobian * jacobian.transpose();
      rightSide -= weight * residuals[i] * jacobian;
      weightedSquares += residuals[i] * residuals[i];
      weightSum += 1;
      ++weighted;
    }
    require(weighted >= 6, "ICP: fewer than 6 correspondences survived the robust kernel");
    result.inlierRmseMm = std::sqrt(weightedSquares / weightSum);
    result.inlierFraction = static_cast<double>(weighted) / static_cast<double>(n);
    // A tiny damping keeps a degenerate geometry (a plane, a cylinder) from producing NaN; it does not bias a
    // well-constrained step measurably.
    normalMatrix.diagonal().array() += 1e-12 * normalMatrix.trace();
    const Eigen::Matrix<double, 6, 1> step = normalMatrix.ldlt().solve(rightSide);
    require(step.allFinite(), "ICP: the point-to-plane step is not finite (degenerate target geometry)");

    const Eigen::Vector3d omega = step.head<3>();
    const double angle = omega.norm();
    const Eigen::Matrix3d rotation =
        angle > 0 ? Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    Eigen::Matrix4d delta = Eigen::Matrix4d::Identity();
    delta.topLeftCorner<3, 3>() = rotation;
    delta.topRightCorner<3, 1>() = centroid - rotation * centroid + step.tail<3>();
    result.targetFromModel = delta * result.targetFromModel;
    result.iterations = iteration + 1;
    require(!parameters.progress || parameters.progress(result.iterations), "ICP was cancelled");
    if (angle * 180.0 / kPi < parameters.convergenceRotationDeg &&
        step.tail<3>().norm() < parameters.convergenceTranslationMm) {
      result.converged = true;
      break;
    }
  }
  return result;
}

std::vector<Eigen::Vector3d> transformedPoints(const std::vector<Eigen::Vector3d>& points, const Eigen::Matrix4d& transform) {
  std::vector<Eigen::Vector3d> mapped(points.size());
  const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
  const Eigen::Vector3d translation = transform.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < points.size(); ++i) mapped[i] = linear * points[i] + translation;
  return mapped;
}

double rotationAngleDeg(const Eigen::Matrix4d& transform) {
  Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
  linear /= std::cbrt(linear.determinant());
  const double cosine = std::clamp((linear.trace() - 1) / 2, -1.0, 1.0);
  return std::acos(cosine) * 180.0 / kPi;
}

}  // namespace tissuemosaic
