#include "Deformation/ModelWarp.h"

#include "Core/ParallelFor.h"

namespace tissuemosaic {

PointMotion ModelWarp::motionAt(const Eigen::Vector3d& restMm, const NodeInfluence& influence,
                                const std::vector<Eigen::Quaterniond>& nodeRotations) const {
  PointMotion motion;
  if (influence.count == 0) return motion;  // no node near: the point stays where it rests
  const Eigen::Matrix3d rotation = DeformationGraph::blendedRotation(influence, nodeRotations);
  const Eigen::Vector3d live = graph_.warp(restMm, influence);
  motion.rotation = rotation.cast<float>();
  motion.translationMm = (live - rotation * restMm).cast<float>();
  return motion;
}

void ModelWarp::motionsOf(const std::vector<Eigen::Vector3f>& restMm, std::vector<PointMotion>& motions) {
  lastInfluencesFound_ = influences_.update(graph_, restMm);
  const std::vector<Eigen::Quaterniond> rotations = graph_.nodeQuaternions();
  motions.resize(restMm.size());
  parallelFor<CpuBackend>(static_cast<int64_t>(restMm.size()), [&](int64_t i) {
    const std::size_t k = static_cast<std::size_t>(i);
    motions[k] = restMm[k].allFinite() ? motionAt(restMm[k].cast<double>(), influences_[k], rotations) : PointMotion{};
  }, 1024);
}

void ModelWarp::restOf(const std::vector<Eigen::Vector3f>& liveMm, std::vector<Eigen::Vector3f>& restMm,
                       std::vector<PointMotion>& motions) {
  const std::vector<Eigen::Quaterniond> rotations = graph_.nodeQuaternions();
  restMm.resize(liveMm.size());
  motions.resize(liveMm.size());
  parallelFor<CpuBackend>(static_cast<int64_t>(liveMm.size()), [&](int64_t i) {
    const std::size_t k = static_cast<std::size_t>(i);
    NodeInfluence influence;
    const Eigen::Vector3d rest = graph_.inverseWarp(liveMm[k].cast<double>(), influence);
    restMm[k] = rest.cast<float>();
    motions[k] = motionAt(rest, influence, rotations);
  }, 256);
}

}  // namespace tissuemosaic
