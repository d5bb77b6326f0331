#pragma once
/// @file vtkTissueMosaicRegistration.h
/// @brief Registration of the reconstructed model to a CT/MR surface: landmark pairs (Umeyama, optionally with
/// a uniform scale), then ICP refinement, point-to-plane with a trimmed correspondence set and a Tukey kernel so
/// that scanned tissue the CT model does not contain (fat, instruments, parts outside the segmentation) does not
/// pull the model. Transforms are 4x4 T_target_model in LPS millimetres: target = T * model.
#include <Eigen/Core>

#include <functional>
#include <limits>
#include <vector>

namespace tissuemosaic {

class TargetSurface;

struct LandmarkRegistration {
  Eigen::Matrix4d targetFromModel = Eigen::Matrix4d::Identity();
  double scale = 1;                  ///< uniform scale (1 for a rigid registration)
  double rmseMm = 0;                 ///< RMS of the pairs' residual distances after registration
  std::vector<double> residualsMm;   ///< |target_i - T * model_i| per pair
};

/// Least-squares rigid (or similarity, withScale) transform mapping the model landmarks onto the target ones
/// (Umeyama 1991, Eigen::umeyama). Throws Error for fewer than 3 pairs, non-finite positions, or landmarks that
/// are (nearly) collinear on either side, where the rotation about their line is undetermined.
LandmarkRegistration registerLandmarks(const std::vector<Eigen::Vector3d>& modelLps,
                                       const std::vector<Eigen::Vector3d>& targetLps, bool withScale);

/// ICP parameters; validated by refineIcp.
struct IcpParameters {
  int maxIterations = 100;
  /// Trimmed ICP: only this fraction of the correspondences, the closest ones, enters each step (0 < f <= 1).
  double inlierFraction = 0.8;
  /// Correspondences farther than this never enter (mm; infinity: no limit).
  double maxDistanceMm = std::numeric_limits<double>::infinity();
  /// Tukey biweight cut-off in robust standard deviations (1.4826 * median |residual|); 4.685 is the 95%
  /// efficient choice.
  double tukeyCutoff = 4.685;
  /// Floor of the robust standard deviation (mm), so that an exact fit does not make the kernel reject all.
  double minSigmaMm = 0.02;
  /// Converged when a step rotates less than this and translates less than convergenceTranslationMm.
  double convergenceRotationDeg = 1e-4;
  double convergenceTranslationMm = 1e-4;
  /// Model points used per step (an even subsample when the model has more); the evaluation uses all of them.
  int maxPoints = 20000;
  /// Called after every step with the steps taken so far (e.g. for a progress bar); returning false cancels the
  /// refinement (refineIcp throws Error "ICP was cancelled"). Empty: no calls.
  std::function<bool(int iterations)> progress;
};

struct IcpResult {
  Eigen::Matrix4d targetFromModel = Eigen::Matrix4d::Identity();
  int iterations = 0;       ///< steps taken
  bool converged = false;   ///< the last step was below the convergence thresholds
  double inlierRmseMm = 0;  ///< RMS point-to-plane residual over the correspondences with non-zero weight
  double inlierFraction = 0;///< share of the used points with non-zero weight in the last step
};

/// Refines T_target_model from `initialTargetFromModel` (the landmark result). The scale of the initial
/// transform is kept; only rotation and translation are refined. Throws Error for invalid parameters, an empty
/// model, or when no correspondence survives trimming.
IcpResult refineIcp(const std::vector<Eigen::Vector3d>& modelPointsLps, const TargetSurface& target,
                    const Eigen::Matrix4d& initialTargetFromModel, const IcpParameters& parameters = {});

/// The model points mapped by a 4x4 transform.
std::vector<Eigen::Vector3d> transformedPoints(const std::vector<Eigen::Vector3d>& points, const Eigen::Matrix4d& transform);

/// Rotation angle (degrees) of the rotation part of a rigid/similarity transform (scale removed).
double rotationAngleDeg(const Eigen::Matrix4d& transform);

}  // namespace tissuemosaic
