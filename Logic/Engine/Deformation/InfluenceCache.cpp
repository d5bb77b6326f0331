#include "Deformation/InfluenceCache.h"

#include "Core/ParallelFor.h"
#include "Deformation/NodeCells.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuemosaic {
namespace {

/// A node added within 2 spacings of a point (the reach of its weights) lies at most 3 cells from the point's cell.
constexpr int kChangedCellReach = 3;

}  // namespace

void InfluenceCache::clear() {
  influences_.clear();
  foundAtMm_.clear();
  changedCells_.clear();
  nodesSeen_ = 0;
}

void InfluenceCache::collectChangedCells(const DeformationGraph& graph) {
  changedCells_.clear();
  const auto& nodes = graph.nodes();
  for (int j = nodesSeen_; j < graph.nodeCount(); ++j) {
    const Eigen::Vector3i cell = node_cells::cellOf(nodes[static_cast<std::size_t>(j)].positionMm, spacingMm_);
    for (int dz = -kChangedCellReach; dz <= kChangedCellReach; ++dz)
      for (int dy = -kChangedCellReach; dy <= kChangedCellReach; ++dy)
        for (int dx = -kChangedCellReach; dx <= kChangedCellReach; ++dx)
          changedCells_.push_back(node_cells::cellKey(cell + Eigen::Vector3i(dx, dy, dz)));
  }
  std::sort(changedCells_.begin(), changedCells_.end());
  changedCells_.erase(std::unique(changedCells_.begin(), changedCells_.end()), changedCells_.end());
  nodesSeen_ = graph.nodeCount();
}

bool InfluenceCache::inChangedCell(const Eigen::Vector3d& p) const {
  if (changedCells_.empty()) return false;
  return std::binary_search(changedCells_.begin(), changedCells_.end(),
                            node_cells::cellKey(node_cells::cellOf(p, spacingMm_)));
}

int InfluenceCache::refresh(const DeformationGraph& graph, const std::vector<Eigen::Vector3d>& points) {
  spacingMm_ = graph.parameters().nodeSpacingMm;
  collectChangedCells(graph);
  const std::size_t n = points.size(), known = std::min(influences_.size(), n);
  influences_.resize(n);
  foundAtMm_.resize(n, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  const double moveLimitMm = 0.25 * spacingMm_;
  std::vector<int> findAgain;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = points[i];
    if (i >= known || !((p - foundAtMm_[i]).norm() < moveLimitMm) || inChangedCell(p))
      findAgain.push_back(static_cast<int>(i));
  }
  parallelFor<CpuBackend>(static_cast<int64_t>(findAgain.size()), [&](int64_t k) {
    const std::size_t i = static_cast<std::size_t>(findAgain[static_cast<std::size_t>(k)]);
    influences_[i] = points[i].allFinite() ? graph.influence(points[i]) : NodeInfluence{};
    foundAtMm_[i] = points[i];
  }, 64);
  return static_cast<int>(findAgain.size());
}

}  // namespace tissuemosaic
