#pragma once
/// @file RefinementSolver.h
/// @brief Levenberg-Marquardt on f_BA + beta f_ICP (paper III.D), alternating the free feature points and the poses:
/// the bundle-adjustment problem as plain arrays, independent of how the matches were found. KeyFrameRefiner builds
/// the problem; tests build it directly. Runs its per-point and per-residual steps on the chosen device.
///
/// Costs: f_BA = sum Huber(|reprojection error|, baHuberPx); f_ICP = sum Tukey(n_i . (R p_i + t - q_i), icpTukeyMm),
/// weighted by beta as in the paper's eq. totalcost (the normal equations take beta J^T J, not beta^2).
/// Order: first every frame that sees at least 10 fixed-point observations takes an LM pose step on those alone
/// (the free points start at the key frame's tracked pose and would otherwise hold every pose near its tracked error:
/// alternation converges slowly out of that); then `alternations` rounds of [every free point: lmIterations of its
/// 3x3 LM; every pose: lmIterations of its 6x6 LM], ending early once the cost stops falling. A step is kept only
/// when its own cost falls (per point, per frame: given the points, the frames are independent).
#include "Core/Device.h"
#include "Core/SurfaceMeasurement.h"
#include "Refinement/RefinementKernels.h"
#include "Refinement/RefinementParameters.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace tissuemosaic::refinement {

struct RefinementProblem {
  Camera camera{};
  RobustConstants robust{};           ///< beta included
  std::vector<Pose> poses;            ///< the frames optimised; poses[0] is the key frame (the ICP term's)
  std::vector<double> pointsWorldMm;  ///< 3 per feature point
  std::vector<uint8_t> pointFixed;    ///< 1: the point keeps its position (seen by an earlier key frame)
  std::vector<Observation> observations;  ///< any order; frames index poses
  std::vector<Float3> modelPointsWorldMm; ///< p_i (empty: no ICP term)
  cv::Mat measuredPointsCameraMm;     ///< CV_32FC3 q, NaN = none (needed when there are model points)
  cv::Mat measuredNormalsCamera;      ///< CV_32FC3 n, NaN = none
  /// The same maps on the device (measureSurface on CUDA): a CUDA solve reads them there, and they stand in for
  /// the host maps when those are empty.
  std::shared_ptr<const SurfaceMapsOnDevice> measuredOnDevice;
};

struct RefinementSolution {
  std::vector<Pose> poses;
  std::vector<double> pointsWorldMm;
  double initialCost = 0, finalCost = 0;
  int iterations = 0;  ///< pose LM iterations
};

/// Throws Error for inconsistent input (indices out of range, missing measurement) or CUDA where there is none.
RefinementSolution solveRefinement(const RefinementProblem& problem, const RefinementParameters& parameters,
                                   Device device);

}  // namespace tissuemosaic::refinement
