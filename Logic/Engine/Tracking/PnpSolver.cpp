#include "Tracking/PnpSolver.h"

#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "Tracking/R1PpnpCore.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace tissuemosaic {

namespace {

using detail::Hypothesis;
using detail::PnpProblem;

PnpResult failure(const std::string& reason, int hypotheses = 0, int innerIterations = 0) {
  PnpResult result;
  result.failureReason = reason;
  result.hypotheses = hypotheses;
  result.innerIterations = innerIterations;
  return result;
}

bool finite(const Eigen::Vector2d& v) { return v.allFinite(); }
bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

/// Coincident or collinear points: the second principal spread is negligible against the first.
bool collinear(const Points3d& points, const std::vector<int>& indices) {
  if (indices.size() < 3) return true;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : indices) mean += points[i];
  mean /= static_cast<double>(indices.size());
  // The six distinct entries of the scatter matrix (it runs on every inlier set that PnP polishes).
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (int i : indices) {
    const Eigen::Vector3d d = points[i] - mean;
    xx += d.x() * d.x();
    xy += d.x() * d.y();
    xz += d.x() * d.z();
    yy += d.y() * d.y();
    yz += d.y() * d.z();
    zz += d.z() * d.z();
  }
  Eigen::Matrix3d covariance;
  covariance << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  const Eigen::Vector3d eig =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly).eigenvalues();
  return !(eig[2] > 0) || eig[1] <= 1e-10 * eig[2] || eig[1] <= 1e-12;
}

/// The match of each 3D point (primary or candidate) with the smallest reprojection error under (R, t).
struct BestMatch {
  int slot = -1;      ///< -1 primary, j candidate
  double error2 = 0;  ///< px^2
  double primaryError2 = 0;  ///< px^2 of the primary match alone
  Eigen::Vector2d pixelPx;
};

std::vector<BestMatch> bestMatches(const Points3d& points, const Pixels2d& pixels,
                                   const std::vector<std::vector<CandidateMatch>>& candidates,
                                   const PinholeIntrinsics& k, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  std::vector<BestMatch> best(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d c = R * points[i] + t;
    BestMatch& b = best[i];
    if (!(c.z() > 1e-9)) {
      b.error2 = b.primaryError2 = std::numeric_limits<double>::infinity();
      b.pixelPx = pixels[i];
      continue;
    }
    Eigen::Vector2d projected;
    k.project(c.x(), c.y(), c.z(), projected.x(), projected.y());
    b.pixelPx = pixels[i];
    b.error2 = b.primaryError2 = (projected - pixels[i]).squaredNorm();
    if (candidates.empty()) continue;
    for (std::size_t j = 0; j < candidates[i].size(); ++j) {
      const double e2 = (projected - candidates[i][j].pixelPx).squaredNorm();
      if (e2 < b.error2) {
        b.error2 = e2;
        b.slot = static_cast<int>(j);
        b.pixelPx = candidates[i][j].pixelPx;
      }
    }
  }
  return best;
}

/// Gauss-Newton on the reprojection error of the given matches (left-multiplied rotation increments).
/// Returns false when the normal equations are singular (a degenerate inlier set).
bool polish(const Points3d& points, const std::vector<BestMatch>& matches, const std::vector<int>& indices,
            const PinholeIntrinsics& k, Eigen::Matrix3d& R, Eigen::Vector3d& t) {
  for (int iteration = 0; iteration < 10; ++iteration) {
    // The upper triangle of J^T J and J^T r, written out: the rows of J = d(projection) / d(w, t) have two zeros
    // each, and this loop is most of the solver's time (every hypothesis' inlier set, until it settles).
    double upper[21] = {}, Jtr[6] = {};
    for (int i : indices) {
      const Eigen::Vector3d rotated = R * points[i];  // R X
      const Eigen::Vector3d c = rotated + t;
      if (!(c.z() > 1e-9)) return false;
      const double cameraPoint[3] = {c.x(), c.y(), c.z()};
      double u, v, dU[3], dV[3];
      k.projectWithDerivatives(cameraPoint, u, v, dU, dV);
      const double ru = u - matches[i].pixelPx.x(), rv = v - matches[i].pixelPx.y();
      // d(exp(w) R X + t) / d(w, t) = [-[RX]x, I], times d(projection) / dc. (The refinement's poseRow differs: its
      // increments move the camera-frame point, so its rotation rows use c, not R X, and come after translation.)
      const double au = dU[0], cu = dU[2], bv = dV[1], cv = dV[2];
      const double x = rotated.x(), y = rotated.y(), z = rotated.z();
      const double Ju[6] = {cu * y, au * z - cu * x, -au * y, au, 0.0, cu};
      const double Jv[6] = {cv * y - bv * z, -cv * x, bv * x, 0.0, bv, cv};
      for (int a = 0, e = 0; a < 6; ++a) {
        for (int b = a; b < 6; ++b, ++e) upper[e] += Ju[a] * Ju[b] + Jv[a] * Jv[b];
        Jtr[a] += Ju[a] * ru + Jv[a] * rv;
      }
    }
    Eigen::Matrix<double, 6, 6> JtJ;
    for (int a = 0, e = 0; a < 6; ++a) {
      for (int b = a; b < 6; ++b, ++e) JtJ(a, b) = JtJ(b, a) = upper[e];
    }
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(JtJ);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-9 * JtJ.diagonal().maxCoeff())) return false;
    const Eigen::Matrix<double, 6, 1> delta = -ldlt.solve(Eigen::Map<const Eigen::Matrix<double, 6, 1>>(Jtr));
    if (!delta.allFinite()) return false;
    const double angle = delta.head<3>().norm();
    if (angle > 0) R = Eigen::AngleAxisd(angle, delta.head<3>() / angle).toRotationMatrix() * R;
    t += delta.tail<3>();
    if (angle < 1e-10 && delta.tail<3>().norm() < 1e-8) break;  // below 1e-8 deg and 10 nm: converged
  }
  // Re-orthonormalise against drift.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  R = svd.matrixU() * svd.matrixV().transpose();
  return R.allFinite() && t.allFinite();
}

/// A hypothesis' pose polished on its inliers until the inlier set settles. Returns the inlier count (0 when the
/// inliers are too few, collinear or do not fix a pose).
int refine(const Points3d& points, const Pixels2d& pixels, const std::vector<std::vector<CandidateMatch>>& candidates,
           const PinholeIntrinsics& k, double inlierThresholdPx, Eigen::Matrix3d& R, Eigen::Vector3d& t) {
  const double H2 = inlierThresholdPx * inlierThresholdPx;
  std::vector<int> inliers, previous;
  auto select = [&](std::vector<BestMatch>& matches) {
    matches = bestMatches(points, pixels, candidates, k, R, t);
    inliers.clear();
    for (int i = 0; i < static_cast<int>(points.size()); ++i) {
      if (matches[i].error2 <= H2) inliers.push_back(i);
    }
    return inliers.size() >= 4 && !collinear(points, inliers);
  };
  std::vector<BestMatch> matches;
  for (int round = 0; round < 10; ++round) {
    if (!select(matches)) return 0;
    if (inliers == previous) return static_cast<int>(inliers.size());
    if (!polish(points, matches, inliers, k, R, t)) return 0;
    previous = inliers;
  }
  return select(matches) ? static_cast<int>(inliers.size()) : 0;
}

/// The result for the pose (R, t): its matches within thresholdPx (primary or candidate) and their RMS error;
/// failure when fewer than max(minInliers, 4).
PnpResult solvedPose(const Points3d& points, const Pixels2d& pixels,
                     const std::vector<std::vector<CandidateMatch>>& candidates, const PinholeIntrinsics& k,
                     const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double thresholdPx, int minInliers,
                     int hypotheses, int innerIterations) {
  const double H2 = thresholdPx * thresholdPx;
  const std::vector<BestMatch> matches = bestMatches(points, pixels, candidates, k, R, t);
  PnpResult result;
  double sum2 = 0;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    if (matches[i].error2 > H2) continue;
    result.inlierIndices.push_back(i);
    result.inlierMatch.push_back(matches[i].slot);
    sum2 += matches[i].error2;
  }
  if (static_cast<int>(result.inlierIndices.size()) < std::max(minInliers, 4))
    return failure("PnP: too few inliers after polishing", hypotheses, innerIterations);
  result.success = true;
  result.T_camera_world.block<3, 3>(0, 0) = R;
  result.T_camera_world.block<3, 1>(0, 3) = t;
  result.hypotheses = hypotheses;
  result.innerIterations = innerIterations;
  result.rmsInlierErrorPx = std::sqrt(sum2 / static_cast<double>(result.inlierIndices.size()));
  return result;
}

PnpResult solve(const Points3d& points, const Pixels2d& pixels,
                const std::vector<std::vector<CandidateMatch>>& candidates, const PinholeIntrinsics& k,
                const TrackingParameters& params, const std::vector<int>& voteOrder, const Eigen::Matrix4d* guess,
                int hypothesesAtOnce) {
  params.validate();
  require(hypothesesAtOnce >= 1, "PnP: hypothesesAtOnce must be at least 1");
  const int n = static_cast<int>(points.size());
  require(pixels.size() == points.size(), "PnP: " + std::to_string(points.size()) + " 3D points but " +
                                              std::to_string(pixels.size()) + " pixels");
  require(candidates.empty() || candidates.size() == points.size(),
          "DynamicR1PPnP: candidate lists (" + std::to_string(candidates.size()) + ") must match the 3D points (" +
              std::to_string(points.size()) + ")");
  for (int index : voteOrder) {
    if (index < 0 || index >= n) {  // no message built per index (this runs per match, every frame)
      throw Error("PnP: vote order index " + std::to_string(index) + " is outside [0, " + std::to_string(n) + ")");
    }
  }
  if (n < 4) return failure("PnP needs at least 4 matches, got " + std::to_string(n));
  const bool intrinsicsOk = std::isfinite(k.fxPx) && std::isfinite(k.fyPx) && std::isfinite(k.cxPx) &&
                            std::isfinite(k.cyPx) && k.fxPx > 0 && k.fyPx > 0;
  if (!intrinsicsOk) return failure("PnP: intrinsics must be finite with positive focal lengths");
  for (int i = 0; i < n; ++i) {
    if (!finite(points[i]) || !finite(pixels[i]))
      return failure("PnP: match " + std::to_string(i) + " has a non-finite 3D point or pixel");
    if (candidates.empty()) continue;
    for (const CandidateMatch& c : candidates[i]) {
      if (!finite(c.pixelPx) || !std::isfinite(c.score) || !(c.score > 0) || c.score > 1)
        return failure("DynamicR1PPnP: a candidate of match " + std::to_string(i) +
                       " has a non-finite pixel or a score outside (0, 1]");
    }
  }
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  if (collinear(points, all)) return failure("PnP: the 3D points are coincident or collinear");

  // Structure of arrays in normalised coordinates.
  PnpProblem problem;
  problem.fxPx = static_cast<float>(k.fxPx);
  problem.fyPx = static_cast<float>(k.fyPx);
  for (Eigen::ArrayXf* a : {&problem.X, &problem.Y, &problem.Z, &problem.xn, &problem.yn, &problem.invNorm2})
    a->resize(n);
  for (int i = 0; i < n; ++i) problem.originMm += points[i] / n;
  for (int i = 0; i < n; ++i) {
    problem.X[i] = static_cast<float>(points[i].x() - problem.originMm.x());
    problem.Y[i] = static_cast<float>(points[i].y() - problem.originMm.y());
    problem.Z[i] = static_cast<float>(points[i].z() - problem.originMm.z());
    problem.xn[i] = k.normalisedX(pixels[i].x());
    problem.yn[i] = k.normalisedY(pixels[i].y());
  }
  problem.invNorm2 = (problem.xn.square() + problem.yn.square() + 1.0f).inverse();
  int m = 0;
  for (const auto& list : candidates) m += static_cast<int>(list.size());
  for (Eigen::ArrayXf* a : {&problem.cX, &problem.cY, &problem.cZ, &problem.cxn, &problem.cyn, &problem.cInvNorm2,
                            &problem.cScore})
    a->resize(m);
  problem.cOwner.reserve(m);
  problem.cSlot.reserve(m);
  for (int i = 0, j = 0; i < static_cast<int>(candidates.size()); ++i) {
    for (std::size_t s = 0; s < candidates[i].size(); ++s, ++j) {
      problem.cX[j] = problem.X[i];
      problem.cY[j] = problem.Y[i];
      problem.cZ[j] = problem.Z[i];
      problem.cxn[j] = k.normalisedX(candidates[i][s].pixelPx.x());
      problem.cyn[j] = k.normalisedY(candidates[i][s].pixelPx.y());
      problem.cScore[j] = candidates[i][s].score;
      problem.cOwner.push_back(i);
      problem.cSlot.push_back(static_cast<int>(s));
    }
  }
  problem.cInvNorm2 = (problem.cxn.square() + problem.cyn.square() + 1.0f).inverse();

  // Control points: the vote order first, then every match not listed, in input order.
  std::vector<int> order;
  order.reserve(n);
  std::vector<unsigned char> listed(n, 0);
  for (int index : voteOrder) {
    if (!listed[index]) order.push_back(index);
    listed[index] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (!listed[i]) order.push_back(i);
  }

  // Hypotheses: the first alone (it starts from the guess and usually settles the pose), then waves of
  // hypothesesAtOnce, each solved against the best pose before the wave and merged in order as the sequential loop
  // would take them (a control point that an earlier hypothesis of the wave explained is dropped).
  const int wave = std::min(hypothesesAtOnce, static_cast<int>(order.size()));
  // Made when a wave first needs them: most solves settle at the first hypothesis and need one.
  std::vector<std::unique_ptr<detail::HypothesisSolver>> solvers;
  struct Tried {
    bool skipped = false;  ///< its control point was explained before the wave
    Hypothesis polished;
    int iterations = 0;
  };
  std::vector<Tried> tried(static_cast<std::size_t>(wave));
  Hypothesis best;
  std::vector<unsigned char> explained(n, 0);  // inliers of the best hypothesis: as control points they repeat it
  const double logFail = std::log(1.0 - params.ransacConfidence);
  int needed = std::min(params.maxRansacIterations, n);
  int hypotheses = 0, innerIterations = 0;
  const auto tryHypothesis = [&](int h, detail::HypothesisSolver& solver, Tried& out) {
    const int o = order[h];
    out = Tried{};
    out.skipped = explained[o] != 0;
    if (out.skipped) return;
    // A hypothesis must beat the best so far to matter: abandon it early when it is far behind.
    const int abortBelow = std::max(params.minInliers, best.inliers / 2);
    const Hypothesis hypothesis = solver.solve(o, abortBelow, h == 0 ? guess : nullptr);
    out.iterations = hypothesis.iterations;
    if (!hypothesis.valid) return;
    out.polished = hypothesis;
    out.polished.inliers =
        refine(points, pixels, candidates, k, params.inlierThresholdPx, out.polished.R, out.polished.tMm);
  };
  const auto take = [&](int h, const Tried& t) {
    ++hypotheses;
    if (t.skipped || explained[order[h]]) return;
    innerIterations += t.iterations;
    if (!t.polished.valid || t.polished.inliers <= best.inliers) return;
    best = t.polished;
    // Mark the new best's inliers, and bound the hypotheses still needed (1-point sample: 1 - eps per miss).
    const std::vector<BestMatch> matches = bestMatches(points, pixels, candidates, k, best.R, best.tMm);
    const double H2 = params.inlierThresholdPx * params.inlierThresholdPx;
    int primaryInliers = 0;
    for (int i = 0; i < n; ++i) {
      explained[i] = matches[i].primaryError2 <= H2;
      primaryInliers += explained[i];
    }
    // Control points are primary matches: their inlier share, not the candidates', sets the odds of a miss.
    const double inlierRatio = std::min(static_cast<double>(primaryInliers) / n, 1.0);
    if (inlierRatio >= 1.0) {
      needed = h + 1;
    } else {
      const double bound = std::ceil(logFail / std::log(1.0 - inlierRatio));
      needed = static_cast<int>(std::min<double>(needed, bound));
    }
  };
  const int orderSize = static_cast<int>(order.size());
  for (int h = 0; h < orderSize && h < needed;) {
    const int count = h == 0 ? 1 : std::min({wave, orderSize - h, needed - h});
    while (static_cast<int>(solvers.size()) < count) {
      solvers.push_back(std::make_unique<detail::HypothesisSolver>(problem, params));
    }
    if (count == 1) {
      tryHypothesis(h, *solvers[0], tried[0]);
    } else {
      parallelFor<CpuBackend>(count, [&](int64_t i) { tryHypothesis(h + static_cast<int>(i), *solvers[i], tried[i]); }, 1);
    }
    for (int i = 0; i < count && h + i < needed; ++i) take(h + i, tried[static_cast<std::size_t>(i)]);
    h += count;
  }
  if (!best.valid || best.inliers < params.minInliers) {
    return failure("PnP: no pose with at least " + std::to_string(params.minInliers) + " inliers (best " +
                       std::to_string(best.inliers) + ")",
                   hypotheses, innerIterations);
  }

  return solvedPose(points, pixels, candidates, k, best.R, best.tMm, params.inlierThresholdPx, params.minInliers,
                    hypotheses, innerIterations);
}

}  // namespace

PnpResult solveR1Ppnp(const Points3d& pointsMm, const Pixels2d& pixelsPx, const PinholeIntrinsics& intrinsics,
                      const TrackingParameters& parameters, const std::vector<int>& voteOrder) {
  return solve(pointsMm, pixelsPx, {}, intrinsics, parameters, voteOrder, nullptr, 1);
}

PnpResult solveDynamicR1Ppnp(const Points3d& pointsMm, const Pixels2d& pixelsPx,
                             const std::vector<std::vector<CandidateMatch>>& candidates,
                             const PinholeIntrinsics& intrinsics, const TrackingParameters& parameters,
                             const std::vector<int>& voteOrder, const Eigen::Matrix4d* T_camera_world_guess,
                             int hypothesesAtOnce) {
  if (T_camera_world_guess) {
    require(T_camera_world_guess->allFinite(), "DynamicR1PPnP: the pose guess is not finite");
  }
  return solve(pointsMm, pixelsPx, candidates, intrinsics, parameters, voteOrder, T_camera_world_guess,
               hypothesesAtOnce);
}

PnpResult polishPnpPose(const Points3d& pointsMm, const Pixels2d& pixelsPx,
                        const std::vector<std::vector<CandidateMatch>>& candidates, const PinholeIntrinsics& intrinsics,
                        const Eigen::Matrix4d& T_camera_world, double thresholdPx, int minInliers) {
  require(pixelsPx.size() == pointsMm.size() && (candidates.empty() || candidates.size() == pointsMm.size()),
          "PnP polish: the 3D points, pixels and candidate lists differ in number");
  require(thresholdPx > 0 && T_camera_world.allFinite(), "PnP polish: the threshold must be positive, the pose finite");
  Eigen::Matrix3d R = T_camera_world.block<3, 3>(0, 0);
  Eigen::Vector3d t = T_camera_world.block<3, 1>(0, 3);
  if (refine(pointsMm, pixelsPx, candidates, intrinsics, thresholdPx, R, t) < std::max(minInliers, 4)) {
    return failure("PnP polish: fewer than " + std::to_string(std::max(minInliers, 4)) + " matches within " +
                   cv::format("%.1f", thresholdPx) + " px");
  }
  return solvedPose(pointsMm, pixelsPx, candidates, intrinsics, R, t, thresholdPx, minInliers, 0, 0);
}

PnpResult polishOnFittingMatches(const Points3d& pointsMm, const Pixels2d& pixelsPx,
                                 const std::vector<std::vector<CandidateMatch>>& candidates,
                                 const PinholeIntrinsics& intrinsics, const PnpResult& solved, double maxPx,
                                 int minInliers, double* fitPx) {
  if (fitPx) *fitPx = maxPx;
  if (!solved.success || solved.inlierIndices.empty() || !(maxPx > 0)) return solved;
  const Eigen::Matrix3d R = solved.rotation();
  const Eigen::Vector3d t = solved.translationMm();
  std::vector<double> residuals;
  residuals.reserve(solved.inlierIndices.size());
  for (std::size_t k = 0; k < solved.inlierIndices.size(); ++k) {
    const int i = solved.inlierIndices[k], slot = solved.inlierMatch[k];
    const Eigen::Vector3d c = R * pointsMm[static_cast<std::size_t>(i)] + t;
    Eigen::Vector2d projected;
    intrinsics.project(c.x(), c.y(), c.z(), projected.x(), projected.y());
    const Eigen::Vector2d& seen = slot < 0 ? pixelsPx[static_cast<std::size_t>(i)]
                                           : candidates[static_cast<std::size_t>(i)][static_cast<std::size_t>(slot)].pixelPx;
    residuals.push_back((projected - seen).norm());
  }
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  const double bound = std::clamp(kFitMedianFactor * residuals[residuals.size() / 2], std::min(kFitMinPx, maxPx), maxPx);
  if (fitPx) *fitPx = bound;
  PnpResult tight = polishPnpPose(pointsMm, pixelsPx, candidates, intrinsics, solved.T_camera_world, bound, minInliers);
  if (!tight.success) return solved;
  tight.hypotheses = solved.hypotheses;
  tight.innerIterations = solved.innerIterations;
  return tight;
}

void poseDifference(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double& rotationDeg, double& centreMm) {
  const Eigen::Matrix3d Ra = a.block<3, 3>(0, 0), Rb = b.block<3, 3>(0, 0);
  rotationDeg = Eigen::AngleAxisd(Ra.transpose() * Rb).angle() * 180.0 / M_PI;  // atan2-based: exact near 0
  const Eigen::Vector3d centreA = -Ra.transpose() * a.block<3, 1>(0, 3);
  const Eigen::Vector3d centreB = -Rb.transpose() * b.block<3, 1>(0, 3);
  centreMm = (centreA - centreB).norm();
}

}  // namespace tissuemosaic
