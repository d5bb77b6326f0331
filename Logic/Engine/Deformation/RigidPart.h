#pragma once
/// @file RigidPart.h
/// @brief The rigid part of a deformation field: the one rigid motion that best explains where the nodes moved, by
/// weighted least squares (Kabsch, no scale) made robust by iterated reweighting with Tukey's biweight, so that a
/// breathing patch among still tissue does not pull it. What the camera takes from the field (DeformationTracker).
#include <Eigen/Core>
#include <Eigen/StdVector>

#include <vector>

namespace tissuemosaic {

/// The rigid motion D (4x4, world mm) minimising sum_i w_i rho(|D from_i - to_i|), rho Tukey's biweight (points
/// farther than toleranceMm from D do not count), by `rounds` reweighted Kabsch fits from the plain weighted one.
/// Identity for fewer than three points, a degenerate spread, or no point left within the tolerance.
Eigen::Matrix4d robustRigidMotion(const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& from,
                                  const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& to,
                                  const std::vector<double>& weights, double toleranceMm, int rounds = 5);

}  // namespace tissuemosaic
