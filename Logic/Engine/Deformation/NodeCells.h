#pragma once
/// @file NodeCells.h
/// @brief The grid of cells of the node spacing that the deformation graph finds nodes through, and that the
/// influence cache uses to tell which points new nodes may reach: one definition of a cell and its key.
#include <Eigen/Core>

#include <cmath>

namespace tissuemosaic::node_cells {

/// The cell (integer coordinates) holding a point, for cells of spacingMm.
inline Eigen::Vector3i cellOf(const Eigen::Vector3d& pointMm, double spacingMm) {
  return {static_cast<int>(std::floor(pointMm.x() / spacingMm)), static_cast<int>(std::floor(pointMm.y() / spacingMm)),
          static_cast<int>(std::floor(pointMm.z() / spacingMm))};
}

/// A cell keyed for a hash map or a sorted list (21 bits per axis: +-1e6 cells, kilometres at 1 mm).
inline long long cellKey(const Eigen::Vector3i& cell) {
  const auto bits = [](int v) { return static_cast<long long>(v) & 0x1FFFFF; };
  return (bits(cell.x()) << 42) | (bits(cell.y()) << 21) | bits(cell.z());
}

}  // namespace tissuemosaic::node_cells
