#pragma once
/// @file DeformationGraph.h
/// @brief An embedded deformation graph over the model (Sumner et al. 2007, as used by DynamicFusion-style
/// non-rigid reconstruction): nodes every few millimetres over the canonical tissue, each carrying a rigid motion;
/// a canonical point follows the blend of its nearest nodes' motions,
///   warp(p) = sum_j w_j(p) (R_j (p - g_j) + g_j + t_j),
/// with w_j falling to 0 at the (k+1)-th nearest node's distance. Every frame's fit (DeformationFit.h) moves the
/// nodes; the canonical points never move. World frame, millimetres throughout.
///
/// The graph grows with the model: cover() adds nodes where canonical points lie farther than the node spacing from
/// every node, and recomputes the node neighbourhoods (the as-rigid-as-possible term's pairs). Nodes are never
/// removed, so a node's index is stable for the research output (DeformationRecord.h).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/StdVector>

#include <unordered_map>
#include <utility>
#include <vector>

namespace tissuemosaic {

struct DeformationGraphParameters {
  double nodeSpacingMm = 4.0;  ///< one node per cell of this size that holds canonical points
  int influenceNodes = 4;      ///< k: nodes blended per point
  int neighbourNodes = 6;      ///< nodes each node is kept rigid with (the regularisation's pairs)

  /// Throws Error naming the first parameter out of range.
  void validate() const;
};

struct DeformationNode {
  Eigen::Vector3d positionMm = Eigen::Vector3d::Zero();           ///< g: where the node rests (canonical)
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();         ///< R: its rotation about g
  Eigen::Vector3d translationMm = Eigen::Vector3d::Zero();        ///< t: its motion
  /// The surface's unit normal at the node at rest (of the point that made it), zero when not known: the fit's rest
  /// term then holds the node only along the surface, where the depth does not see its motion.
  Eigen::Vector3d restNormal = Eigen::Vector3d::Zero();
  /// Where the node is now: g + t.
  Eigen::Vector3d livePositionMm() const { return positionMm + translationMm; }
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The nodes that move one canonical point, and how much each (weights sum to 1). count 0: no node near.
struct NodeInfluence {
  static constexpr int kMaxNodes = 8;
  int count = 0;
  int node[kMaxNodes] = {};
  double weight[kMaxNodes] = {};
};

class DeformationGraph {
public:
  /// Throws Error for invalid parameters.
  explicit DeformationGraph(const DeformationGraphParameters& parameters = {});

  /// Adds a node (at rest: identity motion) in each spacing-sized cell of canonical points that no node within the
  /// spacing covers yet, at the first such point of the cell (in the input's order, so the graph is the same for the
  /// same points). Returns the number of nodes added; the neighbourhoods are recomputed when it is not 0.
  /// normals (optional: empty or one per point): the surface's unit normals there, kept as the nodes' restNormal.
  int cover(const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& canonicalPointsMm,
            const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& normals = {});

  /// The k nearest nodes of a canonical point with their blending weights; none when the graph is empty or no node
  /// lies within 2 node spacings.
  NodeInfluence influence(const Eigen::Vector3d& canonicalMm) const;
  /// Where the canonical point is now, given its influence.
  Eigen::Vector3d warp(const Eigen::Vector3d& canonicalMm, const NodeInfluence& influence) const;
  Eigen::Vector3d warp(const Eigen::Vector3d& canonicalMm) const { return warp(canonicalMm, influence(canonicalMm)); }
  /// The rotation a point turns by: the nodes' rotations blended as unit quaternions (normalised weighted sum, signs
  /// aligned with the first node's), the identity for no influence. Close to the warp's local turn while
  /// neighbouring nodes turn alike (as the regularisation keeps them), and always a rotation, so that it inverts by
  /// its transpose.
  Eigen::Matrix3d blendedRotation(const NodeInfluence& influence) const;
  /// The same with the nodes' rotations given as unit quaternions (nodeQuaternions()), for many points at once.
  static Eigen::Matrix3d blendedRotation(const NodeInfluence& influence,
                                         const std::vector<Eigen::Quaterniond>& nodeRotations);
  /// Every node's rotation as a unit quaternion, index for index.
  std::vector<Eigen::Quaterniond> nodeQuaternions() const;
  /// Where a live point rests: the canonical point whose warp lands on it, by fixed-point iteration
  /// (p <- q - (warp(p) - p), `iterations` times; exact where the field is a translation), with the nodes found at q
  /// and found again at p before the last step. influence: the rest point's, on return.
  Eigen::Vector3d inverseWarp(const Eigen::Vector3d& liveMm, NodeInfluence& influence, int iterations = 4) const;
  /// The canonical normal turned by the blend of the nodes' rotations (normalised).
  Eigen::Vector3d warpNormal(const Eigen::Vector3d& canonicalNormal, const NodeInfluence& influence) const;

  int nodeCount() const { return static_cast<int>(nodes_.size()); }
  const std::vector<DeformationNode, Eigen::aligned_allocator<DeformationNode>>& nodes() const { return nodes_; }
  /// The fit writes the nodes' motions here; positions must not change.
  std::vector<DeformationNode, Eigen::aligned_allocator<DeformationNode>>& nodes() { return nodes_; }
  /// neighbours()[i]: the nearest nodes of node i (up to neighbourNodes, nearest first).
  const std::vector<std::vector<int>>& neighbours() const { return neighbours_; }
  const DeformationGraphParameters& parameters() const { return parameters_; }
  /// Every node back at rest (identity motions).
  void reset();

private:
  /// The n nearest nodes of p within kSearchRingsOfCells node spacings (squared distance, index), nearest first
  /// (ties by index); skip: a node left out. Found through the nodes' grid (cells of the node spacing).
  std::vector<std::pair<double, int>> nearestNodes(const Eigen::Vector3d& p, int n, int skip = -1) const;
  void updateNeighbours();
  DeformationGraphParameters parameters_;
  std::vector<DeformationNode, Eigen::aligned_allocator<DeformationNode>> nodes_;
  std::vector<std::vector<int>> neighbours_;
  std::unordered_map<long long, std::vector<int>> cells_;  ///< node indices per cell of the node spacing
};

}  // namespace tissuemosaic
