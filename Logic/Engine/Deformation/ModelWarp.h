#pragma once
/// @file ModelWarp.h
/// @brief The deformation graph's field as the point fusion asks for it (ModelDeformation, Fusion/PointFusion.h):
/// each model point's motion from rest to now, and where the points a key frame adds rest. Each point's nearest
/// nodes and weights are kept between frames (the graph's nodes never move at rest): they are found again only for
/// new points, for points near nodes the graph added since, and for points a merge moved by a quarter of the node
/// spacing or more. World frame, millimetres.
#include "Deformation/DeformationGraph.h"
#include "Fusion/PointFusion.h"

#include <vector>

namespace tissuemosaic {

class ModelWarp final : public ModelDeformation {
public:
  /// `graph` must outlive this object; its fit moves the nodes between calls. explainedWithinMm: how far from the
  /// frame's depth the field may leave tissue it follows (ModelDeformation::explainedWithinMm).
  ModelWarp(const DeformationGraph& graph, double explainedWithinMm)
      : graph_(graph), explainedWithinMm_(explainedWithinMm) {}

  /// Per point: its position is warp(p) exactly (DeformationGraph::warp); its rotation is the blended rotation of its
  /// nodes (DeformationGraph::blendedRotation), so that its normal turns with the tissue and a change made where
  /// the point is now goes back to rest by the transpose.
  void motionsOf(const std::vector<Eigen::Vector3f>& restMm, std::vector<PointMotion>& motions) override;
  /// DeformationGraph::inverseWarp per point, and the motion there.
  void restOf(const std::vector<Eigen::Vector3f>& liveMm, std::vector<Eigen::Vector3f>& restMm,
              std::vector<PointMotion>& motions) override;

  double explainedWithinMm() const override { return explainedWithinMm_; }

  /// Points whose nodes were found again by the last motionsOf (new, near new nodes, or moved).
  int lastInfluencesFound() const { return lastInfluencesFound_; }

private:
  PointMotion motionAt(const Eigen::Vector3d& restMm, const NodeInfluence& influence) const;

  const DeformationGraph& graph_;
  double explainedWithinMm_;
  std::vector<NodeInfluence> influences_;   ///< per model point
  std::vector<Eigen::Vector3f> foundAtMm_;  ///< where each point rested when its nodes were found
  int nodesSeen_ = 0;                       ///< the graph's node count when the influences were last brought up to date
  int lastInfluencesFound_ = 0;
};

}  // namespace tissuemosaic
