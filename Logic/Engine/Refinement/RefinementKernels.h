#pragma once
/// @file RefinementKernels.h
/// @brief The per-residual and per-point steps of the key-frame refinement (paper III.D), written once for both
/// backends: functors with a TM_HOST_DEVICE operator() that parallelFor runs on the CPU or as a CUDA kernel.
///
/// Poses are camera-from-world (X_c = R X_w + t) and are perturbed on the left: R <- exp([w]x) R,
/// t <- exp([w]x) t + d, so that dX_c/dd = I and dX_c/dw = -[X_c]x. The pose parameters are ordered (d, w).
/// Each pose residual adds its normal-equation terms (upper triangle of w J^T J, w J^T r, and its robust cost) to the
/// array it is given; parallelChunkSums (Core/ParallelChunkSums.h) sums them over fixed chunks in one fixed order on
/// both backends, so that they add the same numbers in the same order.
#include "Core/Float3.h"
#include "Core/HostDevice.h"
#include "Core/Image.h"
#include "Core/PinholeIntrinsics.h"

#include <cmath>
#include <cstdint>

namespace tissuemosaic::refinement {

/// Camera from world: X_c = R X_w + t, R row-major.
struct Pose {
  double r[9];
  double t[3];
};

/// Feature point `point` seen in frame `frame` at (uPx, vPx).
struct Observation {
  int frame;
  int point;
  double uPx, vPx;
};

/// The rectified left camera.
struct Camera {
  PinholeIntrinsics intrinsics;
  int width, height;
};

struct RobustConstants {
  double baHuberPx;   ///< Huber's constant of the reprojection error
  double icpTukeyMm;  ///< Tukey's constant of the point-to-plane distance
  double beta;        ///< weight of the ICP term
  double minDepthMm;  ///< a point nearer than this (or behind) the camera has no gradient and a fixed cost
};

constexpr int kHessianTerms = 21;  ///< upper triangle of the 6x6 J^T W J, row by row
constexpr int kGradientOffset = 21;
constexpr int kCostOffset = 27;
constexpr int kTerms = 28;
/// Reprojection error charged for a point behind the camera (its Huber cost, no gradient): a step that pushes a
/// point behind a camera must not look like an improvement.
constexpr double kBehindCameraErrorPx = 1000.0;

TM_HOST_DEVICE inline void transformPoint(const Pose& pose, double x, double y, double z, double c[3]) {
  c[0] = pose.r[0] * x + pose.r[1] * y + pose.r[2] * z + pose.t[0];
  c[1] = pose.r[3] * x + pose.r[4] * y + pose.r[5] * z + pose.t[1];
  c[2] = pose.r[6] * x + pose.r[7] * y + pose.r[8] * z + pose.t[2];
}

/// Huber's penalty of an error of length e: e^2 / 2 within k, linear beyond.
TM_HOST_DEVICE inline double huberCost(double e, double k) { return e <= k ? 0.5 * e * e : k * (e - 0.5 * k); }
/// The IRLS weight of Huber's penalty.
TM_HOST_DEVICE inline double huberWeight(double e, double k) { return e <= k ? 1.0 : k / e; }
/// Tukey's biweight penalty: c^2/6 (1 - (1 - (r/c)^2)^3) within c, the constant c^2/6 beyond.
TM_HOST_DEVICE inline double tukeyCost(double r, double c) {
  if (r < -c || r > c) return c * c / 6.0;
  const double a = 1.0 - (r / c) * (r / c);
  return c * c / 6.0 * (1.0 - a * a * a);
}
/// The IRLS weight of Tukey's penalty: (1 - (r/c)^2)^2 within c, 0 beyond.
TM_HOST_DEVICE inline double tukeyWeight(double r, double c) {
  if (r < -c || r > c) return 0.0;
  const double a = 1.0 - (r / c) * (r / c);
  return a * a;
}

/// Adds the weighted residual row (J, r) to the 28 normal-equation terms.
TM_HOST_DEVICE inline void addRow(double terms[kTerms], const double J[6], double r, double w) {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    const double wJi = w * J[i];
    for (int j = i; j < 6; ++j) terms[k++] += wJi * J[j];
    terms[kGradientOffset + i] += wJi * r;
  }
}

/// Row of the pose Jacobian of a scalar residual whose derivative with respect to X_c is `a`: (a, X_c x a).
TM_HOST_DEVICE inline void poseRow(const double c[3], const double a[3], double J[6]) {
  J[0] = a[0];
  J[1] = a[1];
  J[2] = a[2];
  J[3] = c[1] * a[2] - c[2] * a[1];
  J[4] = c[2] * a[0] - c[0] * a[2];
  J[5] = c[0] * a[1] - c[1] * a[0];
}

/// The reprojection residual of one observation: normal-equation terms of its frame's pose (points fixed), added to
/// terms (kTerms; parallelChunkSums sums them per chunk). Where fixedOnly[frame] is set, observations of free points
/// count nothing (the first pose step, which starts every pose from the fixed points alone); fixedOnly null: no frame.
struct BaPoseTerms {
  const Observation* observations;
  const Pose* poses;
  const double* pointsWorldMm;  ///< 3 per point
  const uint8_t* pointFixed;
  const uint8_t* fixedOnly;     ///< per frame, or null
  Camera camera;
  RobustConstants robust;

  TM_HOST_DEVICE void operator()(int64_t i, double acc[kTerms]) const {
    const Observation o = observations[i];
    if (fixedOnly && fixedOnly[o.frame] && !pointFixed[o.point]) return;
    const double* X = pointsWorldMm + 3 * static_cast<int64_t>(o.point);
    double c[3];
    transformPoint(poses[o.frame], X[0], X[1], X[2], c);
    if (c[2] < robust.minDepthMm) {
      acc[kCostOffset] = huberCost(kBehindCameraErrorPx, robust.baHuberPx);
    } else {
      double u, v, au[3], av[3];
      camera.intrinsics.projectWithDerivatives(c, u, v, au, av);
      const double eu = u - o.uPx, ev = v - o.vPx;
      const double e = sqrt(eu * eu + ev * ev);
      const double w = huberWeight(e, robust.baHuberPx);
      acc[kCostOffset] = huberCost(e, robust.baHuberPx);
      double J[6];
      poseRow(c, au, J);
      addRow(acc, J, eu, w);
      poseRow(c, av, J);
      addRow(acc, J, ev, w);
    }
  }
};

/// The point-to-plane residual of one model point p_i (paper eq. ICPterm) for the key frame's pose:
/// r = n_i . (R p_i + t - q_i), q_i and n_i read from the measurement at the pixel nearest to where R p_i + t
/// projects (re-found at every evaluation). Weighted by beta and Tukey's penalty; a model point without a valid q_i
/// (rho = 0 in the paper) is charged Tukey's constant cost, as an outlier, so that sliding off the measurement is no
/// gain. Adds model point i's terms to acc.
struct IcpPoseTerms {
  const Float3* modelPointsWorldMm;
  const Pose* poses;  ///< poses[0] is the key frame's
  ImageView<const Float3> measuredPointsCameraMm;
  ImageView<const Float3> measuredNormalsCamera;
  Camera camera;
  RobustConstants robust;

  TM_HOST_DEVICE void operator()(int64_t i, double acc[kTerms]) const {
    const Pose pose = poses[0];
    const double beta = robust.beta, tukey = robust.icpTukeyMm;
    acc[kCostOffset] = beta * tukeyCost(2.0 * tukey, tukey);
    const Float3 p = modelPointsWorldMm[i];
    double c[3];
    transformPoint(pose, p.x, p.y, p.z, c);
    if (c[2] >= robust.minDepthMm) {
      double u, v;
      camera.intrinsics.project(c[0], c[1], c[2], u, v);
      const double x = floor(u + 0.5), y = floor(v + 0.5);
      if (x >= 0 && y >= 0 && x < measuredPointsCameraMm.width && y < measuredPointsCameraMm.height) {
        const Float3 q = measuredPointsCameraMm.at(static_cast<int>(x), static_cast<int>(y));
        const Float3 n = measuredNormalsCamera.at(static_cast<int>(x), static_cast<int>(y));
        if (isFinite(q) && isFinite(n)) {
          const double a[3] = {n.x, n.y, n.z};
          const double r = a[0] * (c[0] - q.x) + a[1] * (c[1] - q.y) + a[2] * (c[2] - q.z);
          acc[kCostOffset] = beta * tukeyCost(r, tukey);
          const double w = beta * tukeyWeight(r, tukey);
          if (w > 0.0) {
            double J[6];
            poseRow(c, a, J);
            addRow(acc, J, r, w);
          }
        }
      }
    }
  }
};

/// Solves the symmetric 3x3 system A x = b by the adjugate; false when A is (nearly) singular.
TM_HOST_DEVICE inline bool solve3x3(const double A[9], const double b[3], double x[3]) {
  const double c00 = A[4] * A[8] - A[5] * A[7];
  const double c01 = A[5] * A[6] - A[3] * A[8];
  const double c02 = A[3] * A[7] - A[4] * A[6];
  const double det = A[0] * c00 + A[1] * c01 + A[2] * c02;
  const double scale = fabs(A[0]) + fabs(A[4]) + fabs(A[8]);
  if (!(fabs(det) > 1e-15 * scale * scale * scale)) return false;
  const double c10 = A[2] * A[7] - A[1] * A[8];
  const double c11 = A[0] * A[8] - A[2] * A[6];
  const double c12 = A[1] * A[6] - A[0] * A[7];
  const double c20 = A[1] * A[5] - A[2] * A[4];
  const double c21 = A[2] * A[3] - A[0] * A[5];
  const double c22 = A[0] * A[4] - A[1] * A[3];
  x[0] = (c00 * b[0] + c10 * b[1] + c20 * b[2]) / det;
  x[1] = (c01 * b[0] + c11 * b[1] + c21 * b[2]) / det;
  x[2] = (c02 * b[0] + c12 * b[1] + c22 * b[2]) / det;
  return true;
}

/// One free feature point's LM (paper: "one GPU thread for each feature point"): poses fixed, the point's 3x3
/// normal equations from its observations, `iterations` damped steps, each kept only when its robust reprojection
/// cost falls. freePoints[f] is the point, its observations observationIndex[observationBegin[f] ..
/// observationBegin[f+1]); lambdas[f] carries its damping between calls.
struct UpdatePoints {
  const Observation* observations;
  const Pose* poses;
  const int* freePoints;
  const int* observationBegin;
  const int* observationIndex;
  double* pointsWorldMm;
  double* lambdas;
  Camera camera;
  RobustConstants robust;
  int iterations;

  /// The point's robust cost at X and, when H and g are given, its normal equations.
  TM_HOST_DEVICE double evaluate(int f, const double X[3], double* H, double* g) const {
    if (H) {
      for (int k = 0; k < 9; ++k) H[k] = 0.0;
      for (int k = 0; k < 3; ++k) g[k] = 0.0;
    }
    double cost = 0.0;
    for (int j = observationBegin[f]; j < observationBegin[f + 1]; ++j) {
      const Observation o = observations[observationIndex[j]];
      const Pose& pose = poses[o.frame];
      double c[3];
      transformPoint(pose, X[0], X[1], X[2], c);
      if (c[2] < robust.minDepthMm) {
        cost += huberCost(kBehindCameraErrorPx, robust.baHuberPx);
        continue;
      }
      double u, v, au[3], av[3];
      camera.intrinsics.projectWithDerivatives(c, u, v, au, av);
      const double eu = u - o.uPx, ev = v - o.vPx;
      const double e = sqrt(eu * eu + ev * ev);
      cost += huberCost(e, robust.baHuberPx);
      if (!H) continue;
      const double w = huberWeight(e, robust.baHuberPx);
      // d(u, v)/dX_w = d(u, v)/dX_c R.
      double Ju[3], Jv[3];
      for (int k = 0; k < 3; ++k) {
        Ju[k] = au[0] * pose.r[k] + au[1] * pose.r[3 + k] + au[2] * pose.r[6 + k];
        Jv[k] = av[0] * pose.r[k] + av[1] * pose.r[3 + k] + av[2] * pose.r[6 + k];
      }
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) H[3 * a + b] += w * (Ju[a] * Ju[b] + Jv[a] * Jv[b]);
        g[a] += w * (Ju[a] * eu + Jv[a] * ev);
      }
    }
    return cost;
  }

  TM_HOST_DEVICE void operator()(int64_t i) const {
    const int f = static_cast<int>(i);
    double* P = pointsWorldMm + 3 * static_cast<int64_t>(freePoints[f]);
    double X[3] = {P[0], P[1], P[2]};
    double lambda = lambdas[f];
    double H[9], g[3];
    double cost = evaluate(f, X, H, g);
    for (int it = 0; it < iterations; ++it) {
      double A[9];
      for (int k = 0; k < 9; ++k) A[k] = H[k];
      for (int k = 0; k < 3; ++k) A[4 * k] += lambda * H[4 * k];
      const double b[3] = {-g[0], -g[1], -g[2]};
      double step[3];
      if (!solve3x3(A, b, step)) break;
      const double candidate[3] = {X[0] + step[0], X[1] + step[1], X[2] + step[2]};
      const double candidateCost = evaluate(f, candidate, nullptr, nullptr);
      if (candidateCost < cost) {
        for (int k = 0; k < 3; ++k) X[k] = candidate[k];
        cost = evaluate(f, X, H, g);
        lambda = lambda * 0.1 < 1e-12 ? 1e-12 : lambda * 0.1;
      } else {
        lambda *= 10.0;
        if (lambda > 1e12) break;
      }
    }
    for (int k = 0; k < 3; ++k) P[k] = X[k];
    lambdas[f] = lambda;
  }
};

}  // namespace tissuemosaic::refinement
