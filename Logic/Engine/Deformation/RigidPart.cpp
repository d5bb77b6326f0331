#include "Deformation/RigidPart.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>

namespace tissuemosaic {

Eigen::Matrix4d robustRigidMotion(const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& from,
                                  const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& to,
                                  const std::vector<double>& weights, double toleranceMm, int rounds) {
  Eigen::Matrix4d motion = Eigen::Matrix4d::Identity();
  const std::size_t n = std::min({from.size(), to.size(), weights.size()});
  if (n < 3) return motion;
  std::vector<double> robust(n, 1.0);
  for (int round = 0; round < rounds; ++round) {
    double total = 0;
    Eigen::Vector3d meanFrom = Eigen::Vector3d::Zero(), meanTo = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const double w = weights[i] * robust[i];
      total += w;
      meanFrom += w * from[i];
      meanTo += w * to[i];
    }
    if (!(total > 0)) return Eigen::Matrix4d::Identity();
    meanFrom /= total;
    meanTo /= total;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      covariance += weights[i] * robust[i] * (to[i] - meanTo) * (from[i] - meanFrom).transpose();
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
    if (!(svd.singularValues()(1) > 1e-9 * std::max(1.0, svd.singularValues()(0)))) {
      return Eigen::Matrix4d::Identity();  // the points lie on a line: no rotation is determined
    }
    Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
    if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) flip(2, 2) = -1;  // a rotation, not a reflection
    const Eigen::Matrix3d rotation = svd.matrixU() * flip * svd.matrixV().transpose();
    motion.setIdentity();
    motion.topLeftCorner<3, 3>() = rotation;
    motion.topRightCorner<3, 1>() = meanTo - rotation * meanFrom;
    for (std::size_t i = 0; i < n; ++i) {
      const double residual = (rotation * from[i] + motion.topRightCorner<3, 1>() - to[i]).norm();
      const double u = residual / toleranceMm;
      robust[i] = u < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    }
  }
  return motion;
}

}  // namespace tissuemosaic
