#pragma once
/// @file InfluenceCache.h
/// @brief Each point's nearest nodes and weights (DeformationGraph::influence), kept between frames for a set of
/// canonical points indexed stably (points are only appended): the graph's nodes never move at rest, so a point's
/// influence changes only when it is new, when nodes were added within reach of it, or when the point itself moved
/// (a merge or a running average) by a quarter of the node spacing or more. Finding a point's nodes is the costly
/// part of warping it; the deformation tracker's samples and the fused model's points each keep one cache.
#include "Deformation/DeformationGraph.h"

#include <Eigen/Core>

#include <vector>

namespace tissuemosaic {

class InfluenceCache {
public:
  /// Brings the influences of `points` (index for index with earlier calls; more may have been appended) up to date
  /// with `graph`; returns how many were found again. Point type: Eigen::Vector3f or Vector3d. Non-finite points get
  /// no influence.
  template <class Points>
  int update(const DeformationGraph& graph, const Points& points);

  const NodeInfluence& operator[](std::size_t i) const { return influences_[i]; }
  std::size_t size() const { return influences_.size(); }
  void clear();

private:
  /// Marks the cells within reach of the nodes added since the last update (graph.nodeCount() > nodesSeen_).
  void collectChangedCells(const DeformationGraph& graph);
  bool inChangedCell(const Eigen::Vector3d& p) const;
  int refresh(const DeformationGraph& graph, const std::vector<Eigen::Vector3d>& points);

  std::vector<NodeInfluence> influences_;
  std::vector<Eigen::Vector3d> foundAtMm_;  ///< where each point was when its nodes were found
  std::vector<long long> changedCells_;     ///< sorted cell keys near new nodes (this update)
  int nodesSeen_ = 0;
  double spacingMm_ = 0;
};

template <class Points>
int InfluenceCache::update(const DeformationGraph& graph, const Points& points) {
  std::vector<Eigen::Vector3d> asDouble(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) asDouble[i] = points[i].template cast<double>();
  return refresh(graph, asDouble);
}

}  // namespace tissuemosaic
