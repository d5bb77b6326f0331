#include "Deformation/DeformationFit.h"

#include "Core/ParameterChecks.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace tissuemosaic {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// J^T W J and J^T W r of the normal equations, in 6x6 blocks per node pair (unknowns: theta_i, then delta_i). The
/// blocks' pattern is the same in every Gauss-Newton step of one fit: reset() keeps it, and the sparse Cholesky
/// factorisation's ordering is computed once.
class NormalEquations {
public:
  explicit NormalEquations(int nodes) : nodes_(nodes), gradient_(Eigen::VectorXd::Zero(6 * nodes)) {}

  void reset() {
    for (Matrix6d& m : blocks_) m.setZero();
    gradient_.setZero();
  }
  /// One scalar residual r with weight w whose Jacobian row has the given 6-blocks at the given nodes.
  void addRow(int count, const int* node, const Vector6d* jacobian, double residual, double weight) {
    for (int a = 0; a < count; ++a) {
      gradient_.segment<6>(6 * node[a]) += weight * residual * jacobian[a];
      for (int b = 0; b < count; ++b) {
        if (node[b] > node[a]) continue;  // the lower triangle is all the factorisation reads
        block(node[a], node[b]).noalias() += (weight * jacobian[a]) * jacobian[b].transpose();
      }
    }
  }
  void addDiagonal(int node, const Vector6d& diagonal) { block(node, node).diagonal() += diagonal; }

  /// The step x solving (J^T W J) x = -J^T W r; false when the factorisation fails.
  bool solve(Eigen::VectorXd& step) {
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(blocks_.size() * 36);
    for (const auto& [key, index] : index_) {
      const int i = static_cast<int>(key / nodes_), j = static_cast<int>(key % nodes_);
      const Matrix6d& m = blocks_[index];
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c)
          if (6 * i + r >= 6 * j + c) triplets.emplace_back(6 * i + r, 6 * j + c, m(r, c));
    }
    Eigen::SparseMatrix<double> A(6 * nodes_, 6 * nodes_);
    A.setFromTriplets(triplets.begin(), triplets.end());
    if (!analysed_) {
      solver_.analyzePattern(A);
      analysed_ = true;
    }
    solver_.factorize(A);
    if (solver_.info() != Eigen::Success) return false;
    step = solver_.solve(-gradient_);
    return solver_.info() == Eigen::Success && step.allFinite();
  }

private:
  Matrix6d& block(int i, int j) {
    const long long key = static_cast<long long>(i) * nodes_ + j;
    auto [it, inserted] = index_.try_emplace(key, blocks_.size());
    if (inserted) blocks_.push_back(Matrix6d::Zero());
    return blocks_[it->second];
  }
  int nodes_;
  Eigen::VectorXd gradient_;
  std::vector<Matrix6d, Eigen::aligned_allocator<Matrix6d>> blocks_;
  std::unordered_map<long long, std::size_t> index_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
  bool analysed_ = false;
};

Eigen::Matrix3d exponential(const Eigen::Vector3d& theta) {
  const double angle = theta.norm();
  return angle > 0 ? Eigen::AngleAxisd(angle, theta / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

double huberWeight(double residual, double knee) {
  const double a = std::abs(residual);
  return a <= knee ? 1.0 : knee / a;
}

}  // namespace

void DeformationFitParameters::validate() const {
  const parameters::Group check{"deformation"};
  check.requireRange("iterations", iterations, 1, 100);
  check.requireRange("regularisationWeight", regularisationWeight, 0.0, 1e6);
  check.requireRange("restWeight", restWeight, 1e-9, 1e6);
  check.requireRange("restNormalWeight", restNormalWeight, 1e-9, 1e6);
  check.requireRange("restRotationWeight", restRotationWeight, 0.0, 1e6);
  check.requireRange("huberMm", huberMm, 1e-3, 100.0);
}

DeformationFitResult fitDeformation(DeformationGraph& graph, const DeformationCorrespondences& correspondences,
                                    const DeformationFitParameters& parameters) {
  parameters.validate();
  DeformationFitResult result;
  const int nodeCount = graph.nodeCount();
  if (nodeCount == 0 || correspondences.empty()) return result;

  // The canonical points' influences do not change during the fit.
  std::vector<NodeInfluence> influences(correspondences.size());
  std::vector<char> reached(static_cast<std::size_t>(nodeCount), 0);
  for (std::size_t c = 0; c < correspondences.size(); ++c) {
    influences[c] = correspondences[c].influence ? *correspondences[c].influence
                                                 : graph.influence(correspondences[c].canonicalMm);
    if (influences[c].count > 0) ++result.correspondences;
    for (int n = 0; n < influences[c].count; ++n) reached[static_cast<std::size_t>(influences[c].node[n])] = 1;
  }
  if (result.correspondences == 0) return result;

  auto& nodes = graph.nodes();
  const auto& neighbours = graph.neighbours();
  const double regularisation = parameters.regularisationWeight;
  NormalEquations equations(nodeCount);
  for (int iteration = 0; iteration < parameters.iterations; ++iteration) {
    equations.reset();
    // Data: r = n . (warp(p) - q); d warp / d theta_j = -w_j [a_j]x with a_j = R_j (p - g_j), d warp / d delta_j = w_j.
    for (std::size_t c = 0; c < correspondences.size(); ++c) {
      const NodeInfluence& influence = influences[c];
      if (influence.count == 0) continue;
      const DeformationCorrespondence& k = correspondences[c];
      const Eigen::Vector3d offset = graph.warp(k.canonicalMm, influence) - k.targetMm;
      // Point to plane: one row along the normal; point to point: one row per axis.
      for (int axis = 0; axis < (k.pointToPoint ? 3 : 1); ++axis) {
        const Eigen::Vector3d direction = k.pointToPoint ? Eigen::Vector3d(Eigen::Vector3d::Unit(axis)) : k.targetNormal;
        const double residual = direction.dot(offset);
        Vector6d jacobian[NodeInfluence::kMaxNodes];
        for (int n = 0; n < influence.count; ++n) {
          const DeformationNode& node = nodes[static_cast<std::size_t>(influence.node[n])];
          const Eigen::Vector3d a = node.rotation * (k.canonicalMm - node.positionMm);
          const Eigen::Vector3d turn = a.cross(direction);  // named: GCC 12 misreads the inline cross with AVX
          jacobian[n].head<3>() = influence.weight[n] * turn;
          jacobian[n].tail<3>() = influence.weight[n] * direction;
        }
        equations.addRow(influence.count, influence.node, jacobian, residual, huberWeight(residual, parameters.huberMm));
      }
    }
    // As rigid as possible: e = R_i (g_j - g_i) + g_i + t_i - g_j - t_j, one scalar row per axis.
    for (int i = 0; i < nodeCount; ++i) {
      const DeformationNode& a = nodes[static_cast<std::size_t>(i)];
      for (const int j : neighbours[static_cast<std::size_t>(i)]) {
        const DeformationNode& b = nodes[static_cast<std::size_t>(j)];
        const Eigen::Vector3d arm = a.rotation * (b.positionMm - a.positionMm);
        const Eigen::Vector3d e = arm + a.positionMm + a.translationMm - b.positionMm - b.translationMm;
        for (int axis = 0; axis < 3; ++axis) {
          // d(theta x arm)/d theta = -[arm]x, whose row `axis` is arm x e_axis.
          const Eigen::Vector3d unit = Eigen::Vector3d::Unit(axis);
          const Eigen::Vector3d turn = arm.cross(unit);
          Vector6d rowI, rowJ;
          rowI.head<3>() = turn;
          rowI.tail<3>() = unit;
          rowJ.head<3>().setZero();
          rowJ.tail<3>() = -unit;
          const int pair[2] = {i, j};
          const Vector6d rows[2] = {rowI, rowJ};
          equations.addRow(2, pair, rows, e[axis], regularisation);
        }
      }
    }
    // Rest: t_i -> 0 along the node's tangent plane (restWeight) and along its normal (restNormalWeight); R_i ->
    // identity (restRotationWeight, on its rotation vector: d log(exp(delta) R) / d delta = I near the identity).
    for (int i = 0; i < nodeCount; ++i) {
      const DeformationNode& node = nodes[static_cast<std::size_t>(i)];
      Vector6d damping = Vector6d::Zero();
      damping.head<3>().setConstant(parameters.restNormalWeight);
      equations.addDiagonal(i, damping);
      Eigen::Vector3d axes[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
      double weights[3] = {parameters.restWeight, parameters.restWeight, parameters.restWeight};
      if (node.restNormal.squaredNorm() > 0) {
        const Eigen::Vector3d& n = node.restNormal;
        const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
        axes[0] = n.cross(helper).normalized();
        axes[1] = n.cross(axes[0]);
        axes[2] = n;
        weights[2] = parameters.restNormalWeight;
      }
      const int single[1] = {i};
      for (int axis = 0; axis < 3; ++axis) {
        Vector6d row = Vector6d::Zero();
        row.tail<3>() = axes[axis];
        equations.addRow(1, single, &row, axes[axis].dot(node.translationMm), weights[axis]);
      }
      if (parameters.restRotationWeight > 0) {
        const Eigen::AngleAxisd turned(node.rotation);
        const Eigen::Vector3d theta = turned.angle() * turned.axis();
        for (int axis = 0; axis < 3; ++axis) {
          Vector6d row = Vector6d::Zero();
          row(axis) = 1.0;
          equations.addRow(1, single, &row, theta(axis), parameters.restRotationWeight);
        }
      }
    }
    Eigen::VectorXd step;
    if (!equations.solve(step)) break;
    for (int i = 0; i < nodeCount; ++i) {
      DeformationNode& node = nodes[static_cast<std::size_t>(i)];
      node.rotation = exponential(step.segment<3>(6 * i)) * node.rotation;
      node.translationMm += step.segment<3>(6 * i + 3);
    }
    result.iterations = iteration + 1;
    if (step.lpNorm<Eigen::Infinity>() < 1e-5) break;
  }

  double sum2 = 0, motionSum = 0;
  int rows = 0, reachedCount = 0;
  for (std::size_t c = 0; c < correspondences.size(); ++c) {
    if (influences[c].count == 0) continue;
    const DeformationCorrespondence& k = correspondences[c];
    const Eigen::Vector3d offset = graph.warp(k.canonicalMm, influences[c]) - k.targetMm;
    sum2 += k.pointToPoint ? offset.squaredNorm() : std::pow(k.targetNormal.dot(offset), 2);
    rows += k.pointToPoint ? 3 : 1;
  }
  result.dataRmsMm = std::sqrt(sum2 / rows);
  for (int i = 0; i < nodeCount; ++i) {
    if (!reached[static_cast<std::size_t>(i)]) continue;
    const double motion = nodes[static_cast<std::size_t>(i)].translationMm.norm();
    motionSum += motion;
    result.maxNodeMotionMm = std::max(result.maxNodeMotionMm, motion);
    ++reachedCount;
  }
  result.meanNodeMotionMm = reachedCount > 0 ? motionSum / reachedCount : 0;
  return result;
}

}  // namespace tissuemosaic
