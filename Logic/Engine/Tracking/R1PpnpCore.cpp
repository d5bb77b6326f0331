#include "Tracking/R1PpnpCore.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace tissuemosaic::detail {

namespace {
constexpr float behindCameraError2 = 1e12f;  // px^2 given to a match whose point falls behind the camera
constexpr float minDepthRatio = 1e-6f;        // Y_z = depth / depth(o) below this: behind the camera
constexpr double kSettledRotation = 1e-5;      // Frobenius change of R between iterations (about 1e-5 rad)
constexpr double kSettledScale = 1e-5;         // relative change of the scale mu between iterations
}  // namespace

HypothesisSolver::HypothesisSolver(const PnpProblem& problem, const TrackingParameters& parameters)
    : p_(problem), params_(parameters), dynamic_(problem.candidateCount() > 0) {
  const int n = p_.size();
  for (Eigen::ArrayXf* a : {&sx_, &sy_, &sz_, &s2_, &lam_, &w_, &e2_, &a_, &b_, &c_}) a->resize(n);
  const int m = p_.candidateCount();
  for (Eigen::ArrayXf* a : {&csx_, &csy_, &csz_, &cs2_, &clam_, &cw_, &ce2_, &ca_, &cb_, &cc_}) a->resize(m);
  inv_.resize(std::max(n, m));
  ownerSum_.resize(n);
  firstSeen_.resize(m);
  inlierFlag_.resize(n);
}

// Weighted Procrustes input: M = sum w P S^T with P = lambda x - x_o, sum w |S|^2 (denominator) and sum w |P|^2.
void HypothesisSolver::procrustes(float xo, float yo, Eigen::Matrix3d& M, double& denominator) {
  a_ = lam_ * p_.xn - xo;
  b_ = lam_ * p_.yn - yo;
  c_ = lam_ - 1.0f;
  pNorm2_ = (w_ * (a_.square() + b_.square() + c_.square())).sum();
  a_ *= w_;
  b_ *= w_;
  c_ *= w_;
  M << (a_ * sx_).sum(), (a_ * sy_).sum(), (a_ * sz_).sum(),  //
      (b_ * sx_).sum(), (b_ * sy_).sum(), (b_ * sz_).sum(),   //
      (c_ * sx_).sum(), (c_ * sy_).sum(), (c_ * sz_).sum();
  denominator = (w_ * s2_).sum();
  if (!candidatesActive_) return;
  ca_ = clam_ * p_.cxn - xo;
  cb_ = clam_ * p_.cyn - yo;
  cc_ = clam_ - 1.0f;
  pNorm2_ += (cw_ * (ca_.square() + cb_.square() + cc_.square())).sum();
  ca_ *= cw_;
  cb_ *= cw_;
  cc_ *= cw_;
  Eigen::Matrix3d C;
  C << (ca_ * csx_).sum(), (ca_ * csy_).sum(), (ca_ * csz_).sum(),  //
      (cb_ * csx_).sum(), (cb_ * csy_).sum(), (cb_ * csz_).sum(),   //
      (cc_ * csx_).sum(), (cc_ * csy_).sum(), (cc_ * csz_).sum();
  M += C;
  denominator += (cw_ * cs2_).sum();
}

// Given R and mu: Y = x_o + mu R S is the camera-frame point scaled by 1/depth(o). Updates errors, depths and
// weights of every match; returns the number of 3D points with an inlier match.
int HypothesisSolver::evaluate(const Eigen::Matrix3d& R, double mu, float xo, float yo, int iteration) {
  const float H = static_cast<float>(params_.inlierThresholdPx), H2 = H * H;
  const float fx = p_.fxPx, fy = p_.fyPx;
  const Eigen::Matrix3f muR = (mu * R).cast<float>();
  const int n = p_.size();
  // a, b, c: Y components (scratch arrays are free again after procrustes()).
  a_ = xo + muR(0, 0) * sx_ + muR(0, 1) * sy_ + muR(0, 2) * sz_;
  b_ = yo + muR(1, 0) * sx_ + muR(1, 1) * sy_ + muR(1, 2) * sz_;
  c_ = 1.0f + muR(2, 0) * sx_ + muR(2, 1) * sy_ + muR(2, 2) * sz_;
  lam_ = (p_.xn * a_ + p_.yn * b_ + c_) * p_.invNorm2;
  auto inv = inv_.head(n);
  inv = c_.max(minDepthRatio).inverse();
  e2_ = (c_ > minDepthRatio)
            .select((fx * (a_ * inv - p_.xn)).square() + (fy * (b_ * inv - p_.yn)).square(), behindCameraError2);
  w_ = (e2_ <= H2).select(1.0f, H * e2_.rsqrt());
  for (int i = 0; i < n; ++i) inlierFlag_[i] = e2_[i] <= H2;
  if (candidatesActive_) {
    const int m = p_.candidateCount();
    ca_ = xo + muR(0, 0) * csx_ + muR(0, 1) * csy_ + muR(0, 2) * csz_;
    cb_ = yo + muR(1, 0) * csx_ + muR(1, 1) * csy_ + muR(1, 2) * csz_;
    cc_ = 1.0f + muR(2, 0) * csx_ + muR(2, 1) * csy_ + muR(2, 2) * csz_;
    clam_ = (p_.cxn * ca_ + p_.cyn * cb_ + cc_) * p_.cInvNorm2;
    auto cinv = inv_.head(m);
    cinv = cc_.max(minDepthRatio).inverse();
    ce2_ = (cc_ > minDepthRatio)
               .select((fx * (ca_ * cinv - p_.cxn)).square() + (fy * (cb_ * cinv - p_.cyn)).square(), behindCameraError2);
    const float window2 = static_cast<float>(params_.candidateEta * params_.candidateEta) * H2;
    // w_ij = min(H / e_ij, 1) * score inside the eta * H window, 0 outside.
    cw_ = (ce2_ < window2).select((H * ce2_.rsqrt()).min(1.0f) * p_.cScore, 0.0f);
    ownerSum_.setZero();
    const float T = static_cast<float>(params_.candidateRampIterations);
    for (int j = 0; j < m; ++j) ownerSum_[p_.cOwner[j]] += cw_[j];
    for (int j = 0; j < m; ++j) {
      const int i = p_.cOwner[j];
      if (cw_[j] <= 0) {
        firstSeen_[j] = -1;  // left the window: seen anew if it comes back
        continue;
      }
      if (firstSeen_[j] < 0) firstSeen_[j] = iteration;
      const float ramp = std::min((iteration - firstSeen_[j]) / T, 1.0f);
      cw_[j] = ramp * cw_[j] / (ownerSum_[i] + w_[i]);
      if (ce2_[j] <= H2) inlierFlag_[i] = 1;
    }
  }
  int count = 0;
  for (int i = 0; i < n; ++i) count += inlierFlag_[i];
  return count;
}

Hypothesis HypothesisSolver::solve(int o, int abortBelowInliers, const Eigen::Matrix4d* guess) {
  Hypothesis result;
  const float xo = p_.xn[o], yo = p_.yn[o];
  sx_ = p_.X - p_.X[o];
  sy_ = p_.Y - p_.Y[o];
  sz_ = p_.Z - p_.Z[o];
  s2_ = sx_.square() + sy_.square() + sz_.square();
  // Start as a weak-perspective camera: every point at the control point's depth, all weights 1.
  lam_.setOnes();
  w_.setOnes();
  if (dynamic_) {
    csx_ = p_.cX - p_.X[o];
    csy_ = p_.cY - p_.Y[o];
    csz_ = p_.cZ - p_.Z[o];
    cs2_ = csx_.square() + csy_.square() + csz_.square();
    clam_.setOnes();
    cw_.setZero();  // candidates join once a pose exists to measure them against
    std::fill(firstSeen_.begin(), firstSeen_.end(), -1);
  }
  candidatesActive_ = false;
  if (guess) {
    // Y = x_o + mu R S with mu = 1 / depth(o) under the guess: evaluate() sets the depths and weights it implies.
    const Eigen::Matrix3d Rg = guess->block<3, 3>(0, 0);
    const Eigen::Vector3d Xo = Eigen::Vector3d(p_.X[o], p_.Y[o], p_.Z[o]) + p_.originMm;
    const double depthO = (Rg * Xo + guess->block<3, 1>(0, 3)).z();
    if (depthO > 0 && std::isfinite(depthO) && Rg.allFinite()) evaluate(Rg, 1.0 / depthO, xo, yo, 0);
  }
  const int checkIteration = std::min(8, params_.maxInnerIterations - 1);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(), bestR = R;
  double mu = 0, bestMu = 0;
  int bestInliers = -1, stagnant = 0;
  const int patience = 3;  // iterations without more inliers before a hypothesis counts as settled
  // Once the candidates have ramped in (or without candidates), a pose that no longer moves has settled even when
  // the inlier count still creeps up by one now and then; the caller polishes it on its inliers anyway.
  int settledFrom = dynamic_ ? params_.maxInnerIterations : 0;
  Eigen::Matrix3d previousR = R;
  double previousMu = 0;
  for (int k = 0; k < params_.maxInnerIterations; ++k) {
    Eigen::Matrix3d M;
    double denominator = 0;
    procrustes(xo, yo, M, denominator);
    result.iterations = k + 1;
    if (!(denominator > 0) || !M.allFinite()) break;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d& U = svd.matrixU();
    const Eigen::Matrix3d& V = svd.matrixV();
    Eigen::Vector3d d(1, 1, (U * V.transpose()).determinant() < 0 ? -1 : 1);
    R = U * d.asDiagonal() * V.transpose();
    // Scale: the ratio of weighted spreads (Horn's symmetric form), not the least-squares sum(w P.RS) / sum(w S^2),
    // which outliers' uncorrelated P drag towards 0 at 90 % outliers and the iteration never recovers.
    mu = std::sqrt(pNorm2_ / denominator);
    if (!(mu > 0) || !std::isfinite(mu)) break;  // control point would lie behind the camera
    const double rotationChange = (R - previousR).norm(), scaleChange = std::abs(mu - previousMu) / mu;
    previousR = R;
    previousMu = mu;
    const int inliers = evaluate(R, mu, xo, yo, k);
    if (inliers > bestInliers) {
      bestInliers = inliers;
      bestR = R;
      bestMu = mu;
      stagnant = 0;
    } else if (++stagnant >= patience) {
      // DynamicR1PPnP: once the primary matches have settled the pose, let the candidates in and go on.
      if (!dynamic_ || candidatesActive_ || bestInliers < abortBelowInliers) break;
      candidatesActive_ = true;
      settledFrom = k + params_.candidateRampIterations;
      stagnant = 0;
    }
    if (k >= settledFrom && bestInliers >= abortBelowInliers && rotationChange < kSettledRotation &&
        scaleChange < kSettledScale) {
      break;
    }
    if (k == checkIteration && bestInliers < abortBelowInliers) return result;
  }
  if (bestInliers < 0) return result;
  R = bestR;
  mu = bestMu;
  const int inliers = bestInliers;
  result.valid = true;
  result.R = R;
  result.inliers = inliers;
  // X_c(o) = x_o / mu, so t = x_o / mu - R X_o.
  result.tMm = Eigen::Vector3d(xo, yo, 1.0) / mu - R * (Eigen::Vector3d(p_.X[o], p_.Y[o], p_.Z[o]) + p_.originMm);
  return result;
}

}  // namespace tissuemosaic::detail
