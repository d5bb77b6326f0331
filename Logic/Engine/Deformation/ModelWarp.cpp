#include "Deformation/ModelWarp.h"

#include "Core/ParallelFor.h"

#include <cmath>
#include <unordered_set>

namespace tissuemosaic {
namespace {

/// Cells of the node spacing, keyed for a hash set.
long long cellKey(long long x, long long y, long long z) {
  return ((x & 0x1FFFFF) << 42) | ((y & 0x1FFFFF) << 21) | (z & 0x1FFFFF);
}
long long cellOf(double v, double spacingMm) { return static_cast<long long>(std::floor(v / spacingMm)); }

}  // namespace

PointMotion ModelWarp::motionAt(const Eigen::Vector3d& restMm, const NodeInfluence& influence) const {
  PointMotion motion;
  if (influence.count == 0) return motion;  // no node near: the point stays where it rests
  const Eigen::Matrix3d rotation = graph_.blendedRotation(influence);
  const Eigen::Vector3d live = graph_.warp(restMm, influence);
  motion.rotation = rotation.cast<float>();
  motion.translationMm = (live - rotation * restMm).cast<float>();
  return motion;
}

void ModelWarp::motionsOf(const std::vector<Eigen::Vector3f>& restMm, std::vector<PointMotion>& motions) {
  const std::size_t n = restMm.size();
  const double spacing = graph_.parameters().nodeSpacingMm;
  // Cells within 2 spacings of a node added since the last call: the points there may have new nearest nodes.
  std::unordered_set<long long> changedCells;
  const auto& nodes = graph_.nodes();
  for (int j = nodesSeen_; j < graph_.nodeCount(); ++j) {
    const Eigen::Vector3d& g = nodes[static_cast<std::size_t>(j)].positionMm;
    const long long cx = cellOf(g.x(), spacing), cy = cellOf(g.y(), spacing), cz = cellOf(g.z(), spacing);
    for (long long dz = -3; dz <= 3; ++dz)
      for (long long dy = -3; dy <= 3; ++dy)
        for (long long dx = -3; dx <= 3; ++dx) changedCells.insert(cellKey(cx + dx, cy + dy, cz + dz));
  }
  nodesSeen_ = graph_.nodeCount();
  const std::size_t known = std::min(influences_.size(), n);
  influences_.resize(n);
  foundAtMm_.resize(n);
  const float moveLimitMm = static_cast<float>(0.25 * spacing);
  std::vector<char> findAgain(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = restMm[i];
    findAgain[i] = i >= known || (p - foundAtMm_[i]).norm() >= moveLimitMm ||
                   (!changedCells.empty() &&
                    changedCells.count(cellKey(cellOf(p.x(), spacing), cellOf(p.y(), spacing), cellOf(p.z(), spacing))));
  }
  motions.resize(n);
  parallelFor<CpuBackend>(static_cast<int64_t>(n), [&](int64_t i) {
    const Eigen::Vector3d p = restMm[static_cast<std::size_t>(i)].cast<double>();
    if (!p.allFinite()) {
      motions[static_cast<std::size_t>(i)] = PointMotion{};
      return;
    }
    if (findAgain[static_cast<std::size_t>(i)]) {
      influences_[static_cast<std::size_t>(i)] = graph_.influence(p);
      foundAtMm_[static_cast<std::size_t>(i)] = restMm[static_cast<std::size_t>(i)];
    }
    motions[static_cast<std::size_t>(i)] = motionAt(p, influences_[static_cast<std::size_t>(i)]);
  }, 256);
  lastInfluencesFound_ = static_cast<int>(std::count(findAgain.begin(), findAgain.end(), 1));
}

void ModelWarp::restOf(const std::vector<Eigen::Vector3f>& liveMm, std::vector<Eigen::Vector3f>& restMm,
                       std::vector<PointMotion>& motions) {
  const std::size_t n = liveMm.size();
  restMm.resize(n);
  motions.resize(n);
  parallelFor<CpuBackend>(static_cast<int64_t>(n), [&](int64_t i) {
    NodeInfluence influence;
    const Eigen::Vector3d rest = graph_.inverseWarp(liveMm[static_cast<std::size_t>(i)].cast<double>(), influence);
    restMm[static_cast<std::size_t>(i)] = rest.cast<float>();
    motions[static_cast<std::size_t>(i)] = motionAt(rest, influence);
  }, 256);
}

}  // namespace tissuemosaic
