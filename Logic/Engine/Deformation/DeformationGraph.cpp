#include "Deformation/DeformationGraph.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Deformation/NodeCells.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include <Eigen/Geometry>

namespace tissuemosaic {
namespace {

using node_cells::cellKey;
using node_cells::cellOf;

/// The search for the nearest nodes stops this many node spacings out: farther nodes move no point (a point's
/// weights reach 0 at 2 spacings at most) and no node's regularisation pairs them.
constexpr int kSearchRingsOfCells = 4;

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
    if (!p.allFinite() || !visited.insert(cellKey(cellOf(p, spacing))).second) continue;
    const auto nearest = nearestNodes(p, 1);
    if (!nearest.empty() && nearest.front().first <= spacing * spacing) continue;
    DeformationNode node;
    node.positionMm = p;
    if (!normals.empty() && normals[i].allFinite() && normals[i].norm() > 0) node.restNormal = normals[i].normalized();
    cells_[cellKey(cellOf(p, spacing))].push_back(static_cast<int>(nodes_.size()));
    nodes_.push_back(node);
    ++added;
  }
  if (added > 0) updateNeighbours();
  return added;
}

std::vector<std::pair<double, int>> DeformationGraph::nearestNodes(const Eigen::Vector3d& p, int n, int skip) const {
  std::vector<std::pair<double, int>> found;
  found.reserve(static_cast<std::size_t>(n) + 1);
  const auto consider = [&](int j) {
    if (j == skip) return;
    const std::pair<double, int> candidate((nodes_[static_cast<std::size_t>(j)].positionMm - p).squaredNorm(), j);
    if (static_cast<int>(found.size()) == n && !(candidate < found.back())) return;
    found.insert(std::upper_bound(found.begin(), found.end(), candidate), candidate);
    if (static_cast<int>(found.size()) > n) found.pop_back();
  };
  const double spacing = parameters_.nodeSpacingMm;
  const Eigen::Vector3i centre = cellOf(p, spacing);
  // Rings of cells outward: a node outside rings 0..r lies at least r spacings away, so once the n-th found is
  // nearer than that, no farther ring can change the answer (ties by index, as a search over all nodes).
  for (int ring = 0; ring <= kSearchRingsOfCells; ++ring) {
    for (int dz = -ring; dz <= ring; ++dz) {
      for (int dy = -ring; dy <= ring; ++dy) {
        for (int dx = -ring; dx <= ring; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;  // this ring's shell only
          const auto cell = cells_.find(cellKey(centre + Eigen::Vector3i(dx, dy, dz)));
          if (cell == cells_.end()) continue;
          for (const int j : cell->second) consider(j);
        }
      }
    }
    const double reached = ring * spacing;
    if (static_cast<int>(found.size()) == n && found.back().first < reached * reached) break;
  }
  return found;
}

void DeformationGraph::updateNeighbours() {
  neighbours_.assign(nodes_.size(), {});
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    for (const auto& [distance2, j] : nearestNodes(nodes_[i].positionMm, parameters_.neighbourNodes,
                                                   static_cast<int>(i))) {
      (void)distance2;
      neighbours_[i].push_back(j);
    }
  }
}

NodeInfluence DeformationGraph::influence(const Eigen::Vector3d& canonicalMm) const {
  NodeInfluence result;
  const int k = parameters_.influenceNodes;
  const auto nearest = nearestNodes(canonicalMm, k + 1);
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

Eigen::Matrix3d DeformationGraph::blendedRotation(const NodeInfluence& influence,
                                                  const std::vector<Eigen::Quaterniond>& nodeRotations) {
  if (influence.count == 0) return Eigen::Matrix3d::Identity();
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  Eigen::Vector4d first = Eigen::Vector4d::Zero();
  for (int n = 0; n < influence.count; ++n) {
    Eigen::Vector4d c = nodeRotations[static_cast<std::size_t>(influence.node[n])].coeffs();
    if (n == 0) first = c;
    else if (c.dot(first) < 0) c = -c;  // q and -q are one rotation: blend on one hemisphere
    sum += influence.weight[n] * c;
  }
  const double norm = sum.norm();
  if (!(norm > 0)) return Eigen::Matrix3d::Identity();
  return Eigen::Quaterniond(sum / norm).toRotationMatrix();
}

Eigen::Matrix3d DeformationGraph::blendedRotation(const NodeInfluence& influence) const {
  NodeInfluence local = influence;  // the same weights, over the influence's own nodes numbered 0..count-1
  std::vector<Eigen::Quaterniond> rotations;
  for (int n = 0; n < influence.count; ++n) {
    rotations.emplace_back(nodes_[static_cast<std::size_t>(influence.node[n])].rotation);
    local.node[n] = n;
  }
  return blendedRotation(local, rotations);
}

std::vector<Eigen::Quaterniond> DeformationGraph::nodeQuaternions() const {
  std::vector<Eigen::Quaterniond> rotations;
  rotations.reserve(nodes_.size());
  for (const DeformationNode& node : nodes_) rotations.emplace_back(node.rotation);
  return rotations;
}

Eigen::Vector3d DeformationGraph::inverseWarp(const Eigen::Vector3d& liveMm, NodeInfluence& influence,
                                              int iterations) const {
  Eigen::Vector3d rest = liveMm;
  influence = this->influence(liveMm);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    // The nodes move little between the live point and its rest: found at q, then again before the last step.
    if (iteration == iterations - 1 && iteration > 0) influence = this->influence(rest);
    rest = liveMm - (warp(rest, influence) - rest);
  }
  return rest;
}

void DeformationGraph::reset() {
  for (DeformationNode& node : nodes_) {
    node.rotation.setIdentity();
    node.translationMm.setZero();
  }
}

}  // namespace tissuemosaic
