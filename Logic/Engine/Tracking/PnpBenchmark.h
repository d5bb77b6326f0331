#pragma once
/// @file PnpBenchmark.h
/// @brief Synthetic 3D-2D matches with exact ground truth, and the `tissuemosaic bench pnp` comparison of R1PPnP,
/// DynamicR1PPnP and OpenCV's solvePnPRansac (AP3P) on them. Lives next to the solver so that the engine tests can
/// run the same scenes and the same JSON as the command line.
#include "Tracking/PnpSolver.h"

#include <cstdint>
#include <string>
#include <vector>

namespace tissuemosaic {

/// One synthetic PnP problem: a camera 60-110 mm from a smooth, tilted surface patch (fx = fy = 1000 px, 960x540),
/// random world pose, Gaussian pixel noise on inliers, outliers replaced by uniform random pixels in the image.
struct SyntheticPnpCase {
  Points3d pointsMm;                  ///< world frame
  Pixels2d pixelsPx;                  ///< primary matches
  std::vector<unsigned char> isInlier;
  /// Per point two further candidates (for DynamicR1PPnP): for an outlier, with probability 1/2 one of them is the
  /// true pixel (plus noise), as a second-best descriptor match would be; the rest are distractors, half of them
  /// within 40 px of the true pixel (repeating texture), half anywhere in the image.
  std::vector<std::vector<CandidateMatch>> candidates;
  PinholeIntrinsics intrinsics;
  int widthPx = 960, heightPx = 540;
  Eigen::Matrix4d T_camera_world = Eigen::Matrix4d::Identity();
};

/// Deterministic from seed. outlierRatio in [0, 1): exactly round(n * outlierRatio) outliers at random positions.
SyntheticPnpCase makeSyntheticPnpCase(std::uint64_t seed, int n, double outlierRatio, double noisePx = 1.0);

struct PnpBenchmarkOptions {
  int repeats = 40;
  std::uint64_t seed = 1;
  bool quick = false;  ///< N = 200 and outlier ratios 0.5, 0.9 only (for tests)
};

/// Runs every method on the same scenes, single-threaded (cv::setNumThreads(1) for OpenCV too), and returns one
/// JSON object: {"device", "threads": 1, "repeats", "seed", "success", "cases": [{"method", "outlier_ratio", "n",
/// "success_rate", "median_ms"}, ...]}. Success: rotation error < 1 degree and camera-centre error < 2 mm.
std::string runPnpBenchmark(const PnpBenchmarkOptions& options);

}  // namespace tissuemosaic
