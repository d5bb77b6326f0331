#pragma once
/// @file PoseLmKernels.h
/// @brief The Levenberg-Marquardt pose iterations of the refinement (RefinementSolver.h), as steps that run where
/// the problem lives: on the GPU the whole loop is queued without a round trip to the host, which used to wait for
/// every evaluation (about 0.1 ms each, a dozen per key frame). Written once for both backends; the arithmetic is
/// plain IEEE (no transcendental function, no fused multiply-add), so the CPU and CUDA poses agree bit for bit.
///
/// One iteration: ProposePoseSteps (a damped 6x6 step per frame), the residual terms at the candidates
/// (RefinementKernels.h) summed per chunk (Core/ParallelChunkSums.h), SumFrameTerms, AcceptPoseSteps (each frame keeps
/// its step when its own cost falls), FinishPoseIteration. PoseLmControl::stop, once set, turns the rest of the queued
/// iterations into no-ops. The per-frame steps are light, so RefinementPipeline.inl chains them
/// (Core/ParallelChain.h): two launches per iteration on the GPU.
#include "RefinementKernels.h"

namespace tissuemosaic::refinement {

/// Shared by the steps of one pose LM run (a one-element device buffer).
struct PoseLmControl {
  int stop;        ///< set when no frame can step or the cost stopped falling: later iterations do nothing
  int iterations;  ///< evaluated iterations, over the whole solve
};

/// A relative cost decrease below this ends the iterations (about 1e-4 px of reprojection error left to gain).
constexpr double kConvergedGain = 1e-9;
/// A lambda beyond this means the frame's steps keep failing: it stops stepping until the points move.
constexpr double kMaxLambda = 1e12;
constexpr double kMinLambda = 1e-12;

/// The damped step -(H + lambda diag(H))^-1 g of one frame's normal equations (terms: RefinementKernels.h layout),
/// by LDL^T without pivoting (the damped H is positive definite; an unconstrained direction gets a tiny floor on its
/// diagonal, so it gets no step). False when a pivot is not positive or the step is not finite.
TM_HOST_DEVICE inline bool dampedPoseStep(const double terms[kTerms], double lambda, double step[6]) {
  double H[6][6];
  int k = 0;
  double maxDiagonal = 0.0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) H[i][j] = H[j][i] = terms[k++];
    maxDiagonal = H[i][i] > maxDiagonal ? H[i][i] : maxDiagonal;
  }
  const double floor = 1e-12 * (maxDiagonal > 1e-300 ? maxDiagonal : 1e-300);
  for (int i = 0; i < 6; ++i) {
    H[i][i] += lambda * (H[i][i] > floor ? H[i][i] : floor);
    if (!(H[i][i] > 0.0)) return false;
  }
  // H = L D L^T, L unit lower triangular (stored below the diagonal), D on the diagonal.
  double D[6];
  for (int j = 0; j < 6; ++j) {
    double d = H[j][j];
    for (int p = 0; p < j; ++p) d -= H[j][p] * H[j][p] * D[p];
    if (!(d > 0.0)) return false;
    D[j] = d;
    for (int i = j + 1; i < 6; ++i) {
      double v = H[i][j];
      for (int p = 0; p < j; ++p) v -= H[i][p] * H[j][p] * D[p];
      H[i][j] = v / d;
    }
  }
  double y[6];
  for (int i = 0; i < 6; ++i) {
    double v = -terms[kGradientOffset + i];
    for (int p = 0; p < i; ++p) v -= H[i][p] * y[p];
    y[i] = v;
  }
  for (int i = 5; i >= 0; --i) {
    double v = y[i] / D[i];
    for (int p = i + 1; p < 6; ++p) v -= H[p][i] * step[p];
    step[i] = v;
    if (!(v - v == 0.0)) return false;  // NaN or infinite
  }
  return true;
}

/// The pose moved by step (d, w), perturbed on the left (RefinementKernels.h): R <- C(w) R, t <- C(w) t + d, with
/// the Cayley rotation C(w) = I + 2 / (1 + |v|^2) ([v]x + [v]x^2), v = w / 2. It agrees with exp([w]x) to second
/// order (the same LM steps near the optimum) and needs no sine, whose last bit the CPU and GPU libraries round
/// differently.
TM_HOST_DEVICE inline Pose stepPose(const Pose& pose, const double step[6]) {
  const double v[3] = {0.5 * step[3], 0.5 * step[4], 0.5 * step[5]};
  const double s = 2.0 / (1.0 + v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  // [v]x and [v]x^2 = v v^T - |v|^2 I.
  const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  const double K[9] = {0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0};
  double C[9];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const double square = v[r] * v[c] - (r == c ? vv : 0.0);
      C[3 * r + c] = (r == c ? 1.0 : 0.0) + s * (K[3 * r + c] + square);
    }
  }
  Pose out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      out.r[3 * r + c] = C[3 * r] * pose.r[c] + C[3 * r + 1] * pose.r[3 + c] + C[3 * r + 2] * pose.r[6 + c];
    }
    out.t[r] = C[3 * r] * pose.t[0] + C[3 * r + 1] * pose.t[1] + C[3 * r + 2] * pose.t[2] + step[r];
  }
  return out;
}

/// Starts a run of pose iterations, per frame: clears stop (frame 0), and a frame whose steps kept failing (lambda
/// beyond kMaxLambda) starts again from initialLambda, as the points have moved since; with resetAll every frame does.
struct BeginPoseSteps {
  double* lambdas;
  double initialLambda;
  bool resetAll;
  PoseLmControl* control;

  TM_HOST_DEVICE void operator()(int64_t f) const {
    if (f == 0) control->stop = 0;
    lambdas[f] = resetAll || lambdas[f] > kMaxLambda ? initialLambda : lambdas[f];
  }
};

/// Per frame: candidates[f] = poses[f] moved by its damped step; stepped[f] says whether it has one (else the
/// candidate is the pose itself).
struct ProposePoseSteps {
  const Pose* poses;
  const double* currentTerms;  ///< frames x kTerms
  const double* lambdas;
  Pose* candidates;
  uint8_t* stepped;
  const PoseLmControl* control;

  TM_HOST_DEVICE void operator()(int64_t f) const {
    if (control->stop) return;
    double step[6];
    const bool ok = lambdas[f] <= kMaxLambda && dampedPoseStep(currentTerms + f * kTerms, lambdas[f], step);
    candidates[f] = ok ? stepPose(poses[f], step) : poses[f];
    stepped[f] = ok ? 1 : 0;
  }
};

/// Per (frame, term): the frame's sum of the residuals' chunk sums, in chunk order (frameChunks lists the chunks
/// of frame f at frameChunkBegin[f] .. frameChunkBegin[f + 1]).
struct SumFrameTerms {
  const double* partials;  ///< chunks x kTerms
  const int* frameChunkBegin;
  const int* frameChunks;
  double* frameTerms;      ///< frames x kTerms
  const PoseLmControl* control;

  TM_HOST_DEVICE void operator()(int64_t i) const {
    if (control->stop) return;
    const int64_t f = i / kTerms;
    const int k = static_cast<int>(i % kTerms);
    double sum = 0.0;
    TM_UNROLL_BY(8)
    for (int j = frameChunkBegin[f]; j < frameChunkBegin[f + 1]; ++j) sum += partials[frameChunks[j] * kTerms + k];
    frameTerms[i] = sum;
  }
};

/// Ends an iteration, per frame (when any frame had a step): a frame whose cost fell at its candidate keeps it, lowers
/// its lambda and writes its relative decrease to gains[f]; the others raise their lambda (gain 0). Per frame rather
/// than in one thread: one thread's copies wait for each load in turn (tens of microseconds on the GPU).
struct AcceptPoseSteps {
  Pose* poses;
  const Pose* candidates;
  const uint8_t* stepped;
  double* currentTerms;
  const double* trialTerms;
  double* lambdas;
  double* gains;
  int frames;
  const PoseLmControl* control;

  TM_HOST_DEVICE void operator()(int64_t f) const {
    if (control->stop) return;
    bool anyStep = false;
    for (int g = 0; g < frames; ++g) anyStep = anyStep || stepped[g];
    if (!anyStep) return;  // nothing was tried: FinishPoseIteration stops
    double* current = currentTerms + f * kTerms;
    const double* trial = trialTerms + f * kTerms;
    const double currentCost = current[kCostOffset], trialCost = trial[kCostOffset];
    gains[f] = 0.0;
    if (trialCost < currentCost) {
      gains[f] = (currentCost - trialCost) / currentCost;
      poses[f] = candidates[f];
      double accepted[kTerms];
      for (int k = 0; k < kTerms; ++k) accepted[k] = trial[k];
      for (int k = 0; k < kTerms; ++k) current[k] = accepted[k];
      lambdas[f] = lambdas[f] * 0.1 > kMinLambda ? lambdas[f] * 0.1 : kMinLambda;
    } else {
      lambdas[f] *= 10.0;
    }
  }
};

/// After AcceptPoseSteps (one thread): stop when no frame had a step (nothing was tried, not counted as an
/// iteration) or when the largest relative decrease of a frame is below kConvergedGain.
struct FinishPoseIteration {
  const uint8_t* stepped;
  const double* gains;
  int frames;
  PoseLmControl* control;

  TM_HOST_DEVICE void operator()(int64_t) const {
    if (control->stop) return;
    bool anyStep = false;
    double gain = 0.0;
    for (int f = 0; f < frames; ++f) {
      anyStep = anyStep || stepped[f];
      gain = gains[f] > gain ? gains[f] : gain;
    }
    if (!anyStep) {
      control->stop = 1;
      return;
    }
    ++control->iterations;
    if (gain > 0.0 && gain < kConvergedGain) control->stop = 1;
  }
};

}  // namespace tissuemosaic::refinement
