#include "Deformation/DeformationGraph.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

namespace tissuemosaic {
namespace {

/// Cells of the node spacing, keyed for a hash set (21 bits per axis: +-1e6 cells, kilometres at 1 mm).
long long cellKey(const Eigen::Vector3d& pointMm, double spacingMm) {
  const auto cell = [spacingMm](double v) { return static_cast<long long>(std::floor(v / spacingMm)) & 0x1FFFFF; };
  return (cell(pointMm.x()) << 42) | (cell(pointMm.y()) << 21) | cell(pointMm.z());
}

/// The n nearest of `nodes` to p (by squared distance, ties by index), nearest first; skip: an index left out.
std::vector<std::pair<double, int>> nearestNodes(
    const std::vector<DeformationNode, Eigen::aligned_allocator<DeformationNode>>& nodes, const Eigen::Vector3d& p,
    int n, int skip = -1) {
  std::vector<std::pair<double, int>> found;
  found.reserve(static_cast<std::size_t>(n) + 1);
  for (int j = 0; j < static_cast<int>(nodes.size()); ++j) {
    if (j == skip) continue;
    const std::pair<double, int> candidate((nodes[static_cast<std::size_t>(j)].positionMm - p).squaredNorm(), j);
    if (static_cast<int>(found.size()) == n && !(candidate < found.back())) continue;
    found.insert(std::upper_bound(found.begin(), found.end(), candidate), candidate);
    if (static_cast<int>(found.size()) > n) found.pop_back();
  }
  return found;
}

}  // namespace

void DeformationGraphParameters::validate() const {
  const parameters::Group check{"deformation"};
  check.requireRange("nodeSpacingMm", nodeSpacingMm, 0.5, 100.0);
  check.requireRange("influenceNodes", influenceNodes, 1, NodeInfluence::kMaxNodes - 1);
  check.requireRange("neighbourNodes", neighbourNodes, 1, 32);
}

DeformationGraph::DeformationGraph(const DeformationGraphParameters& parameters) : parameters_(parameters) {
  parameters_.validate();
}

int DeformationGraph::cover(
    const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& canonicalPointsMm,
    const std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>& normals) {
  require(normals.empty() || normals.size() == canonicalPointsMm.size(),
          "deformation graph: the points and their normals differ in number");
  const double spacing = parameters_.nodeSpacingMm;
  std::unordered_set<long long> visited;
  int added = 0;
  for (std::size_t i = 0; i < canonicalPointsMm.size(); ++i) {
    const Eigen::Vector3d& p = canonicalPointsMm[i];
    if (!p.allFinite() || !visited.insert(cellKey(p, spacing)).second) continue;
    const auto nearest = nearestNodes(nodes_, p, 1);
    if (!nearest.empty() && nearest.front().first <= spacing * spacing) continue;
    DeformationNode node;
    node.positionMm = p;
    if (!normals.empty() && normals[i].allFinite() && normals[i].norm() > 0) node.restNormal = normals[i].normalized();
    nodes_.push_back(node);
    ++added;
  }
  if (added > 0) updateNeighbours();
  return added;
}

void DeformationGraph::updateNeighbours() {
  neighbours_.assign(nodes_.size(), {});
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    for (const auto& [distance2, j] : nearestNodes(nodes_, nodes_[i].positionMm, parameters_.neighbourNodes,
                                                   static_cast<int>(i))) {
      (void)distance2;
      neighbours_[i].push_back(j);
    }
  }
}

NodeInfluence DeformationGraph::influence(const Eigen::Vector3d& canonicalMm) const {
  NodeInfluence result;
  const int k = parameters_.influenceNodes;
  const auto nearest = nearestNodes(nodes_, canonicalMm, k + 1);
  if (nearest.empty()) return result;
  const double reach = 2.0 * parameters_.nodeSpacingMm;
  if (nearest.front().first > reach * reach) return result;
  // Weights fall to 0 at the (k+1)-th node (or at 2 spacings when there is none): the blend changes continuously as
  // the set of nearest nodes changes.
  const double limit = static_cast<int>(nearest.size()) > k ? std::sqrt(nearest[static_cast<std::size_t>(k)].first) : reach;
  double sum = 0;
  for (int n = 0; n < std::min<int>(k, static_cast<int>(nearest.size())); ++n) {
    const double d = std::sqrt(nearest[static_cast<std::size_t>(n)].first);
    const double w = std::pow(std::max(0.0, 1.0 - d / std::max(limit, 1e-9)), 2);
    if (!(w > 0)) continue;
    result.node[result.count] = nearest[static_cast<std::size_t>(n)].second;
    result.weight[result.count] = w;
    ++result.count;
    sum += w;
  }
  if (result.count == 0) {  // the point is as far from its nearest node as from the (k+1)-th: follow the nearest
    result.count = 1;
    result.node[0] = nearest.front().second;
    result.weight[0] = 1.0;
    return result;
  }
  for (int n = 0; n < result.count; ++n) result.weight[n] /= sum;
  return result;
}

Eigen::Vector3d DeformationGraph::warp(const Eigen::Vector3d& canonicalMm, const NodeInfluence& influence) const {
  if (influence.count == 0) return canonicalMm;
  Eigen::Vector3d warped = Eigen::Vector3d::Zero();
  for (int n = 0; n < influence.count; ++n) {
    const DeformationNode& node = nodes_[static_cast<std::size_t>(influence.node[n])];
    warped += influence.weight[n] *
              (node.rotation * (canonicalMm - node.positionMm) + node.positionMm + node.translationMm);
  }
  return warped;
}

Eigen::Vector3d DeformationGraph::warpNormal(const Eigen::Vector3d& canonicalNormal, const NodeInfluence& influence) const {
  if (influence.count == 0) return canonicalNormal;
  Eigen::Vector3d turned = Eigen::Vector3d::Zero();
  for (int n = 0; n < influence.count; ++n) {
    turned += influence.weight[n] * (nodes_[static_cast<std::size_t>(influence.node[n])].rotation * canonicalNormal);
  }
  const double norm = turned.norm();
  return norm > 0 ? Eigen::Vector3d(turned / norm) : canonicalNormal;
}

void DeformationGraph::reset() {
  for (DeformationNode& node : nodes_) {
    node.rotation.setIdentity();
    node.translationMm.setZero();
  }
}

}  // namespace tissuemosaic
