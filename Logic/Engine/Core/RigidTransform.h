#pragma once
/// @file RigidTransform.h
/// @brief 4x4 rigid transforms (rotation and translation, e.g. T_world_camera): the check and the inverse that
/// the tracker, the refiner and the fusion share.
#include <Eigen/Core>
#include <Eigen/LU>

namespace tissuemosaic {

/// True for a finite proper rigid transform: orthonormal rotation (to 1e-6), determinant > 0, last row 0 0 0 1.
inline bool isRigidTransform(const Eigen::Matrix4d& T) {
  const Eigen::Matrix3d R = T.block<3, 3>(0, 0);
  return T.allFinite() && (R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0 &&
         T.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1));
}

/// The inverse of a rigid transform: [R^T, -R^T t].
inline Eigen::Matrix4d inverseRigid(const Eigen::Matrix4d& T) {
  Eigen::Matrix4d inverse = Eigen::Matrix4d::Identity();
  inverse.block<3, 3>(0, 0) = T.block<3, 3>(0, 0).transpose();
  inverse.block<3, 1>(0, 3) = -T.block<3, 3>(0, 0).transpose() * T.block<3, 1>(0, 3);
  return inverse;
}

}  // namespace tissuemosaic
