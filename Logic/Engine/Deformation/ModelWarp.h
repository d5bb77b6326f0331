#pragma once
/// @file ModelWarp.h
/// @brief The deformation graph's field as the point fusion asks for it (ModelDeformation, Fusion/PointFusion.h):
/// each model point's motion from rest to now, and where the points a key frame adds rest. The points' nearest
/// nodes are kept between frames (InfluenceCache.h). World frame, millimetres.
#include "Deformation/DeformationGraph.h"
#include "Deformation/InfluenceCache.h"
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
  PointMotion motionAt(const Eigen::Vector3d& restMm, const NodeInfluence& influence,
                       const std::vector<Eigen::Quaterniond>& nodeRotations) const;

  const DeformationGraph& graph_;
  double explainedWithinMm_;
  InfluenceCache influences_;  ///< per model point
  int lastInfluencesFound_ = 0;
};

}  // namespace tissuemosaic
