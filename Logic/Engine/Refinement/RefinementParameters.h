#pragma once
/// @file RefinementParameters.h
/// @brief Every parameter of the key-frame refinement of paper section III.D (matching with earlier key frames, and
/// Levenberg-Marquardt on f_BA + beta f_ICP), with the paper's defaults where it gives them, in one validated struct.
/// The command line, the parameter files and the GUI panel all edit this object.
namespace cv {
class FileStorage;
class FileNode;
}  // namespace cv

namespace tissuemosaic {

struct RefinementParameters {
  // Cost (paper eq. totalcost and ICPterm).
  /// beta = icpWeightFactor * BA residuals / ICP points (the paper's 0.1 * feature points / ICP points).
  double icpWeightFactor = 0.1;
  double icpTukeyMm = 2.0;       ///< Tukey's constant c of the point-to-plane term: |r| > c is an outlier (mm)
  double baHuberPx = 2.0;        ///< Huber's constant of the reprojection term (not in the paper): beyond it, linear (px)
  int icpSamples = 10000;        ///< model points p_i used per key frame (an even subsample of those visible)

  // Levenberg-Marquardt, alternating the feature points and the poses (paper: "update alternatively").
  /// Point step + pose step rounds (more end early once the cost stops falling). One: on the 300-frame bench scan
  /// (H100) rounds until convergence doubled the solve (0.95 -> 1.9 ms) for no gain in accuracy (model RMSE 0.1485 ->
  /// 0.1482 mm, key-frame position RMSE 0.2022 -> 0.2031 mm).
  int alternations = 1;
  int lmIterations = 5;          ///< LM iterations of each step (per point, per pose)
  double initialLambda = 1e-3;   ///< lambda of (J^T J + lambda diag(J^T J)) x = J^T b at the start

  // Which frames take part (Omega).
  int maxMatchedKeyFrames = 4;   ///< earlier key frames matched at most (the most overlapping first)
  /// An earlier key frame is a candidate when at least this fraction of its stored points project into the current
  /// view (in front of the camera) at the tracked pose.
  double minKeyFrameOverlap = 0.3;
  int minKeyFrameInliers = 20;   ///< DynamicR1PPnP inliers for a match with an earlier key frame to count
  int minFrameInliers = 12;      ///< ... and for an intermediate frame to join the bundle adjustment
  /// DynamicR1PPnP hypotheses tried at most per match with an earlier key frame or an intermediate frame (the
  /// tracker's maxRansacIterations when that is smaller). The first starts from the tracked pose and a solve must
  /// stay within the correction limits below, so a set that no early hypothesis explains does not match: without
  /// this cap such a set cost all 500 hypotheses (40 ms at a key frame).
  int maxSolveHypotheses = 50;
  /// Intermediate frames kept per key frame (thinned evenly beyond). The paper takes every frame since the last key
  /// frame (Omega); each costs one descriptor matching and one DynamicR1PPnP solve here.
  int maxIntermediateFrames = 10;
  /// Matching guided by the tracked poses (ProjectionGuidedMatching.h): a point is looked for near where the tracked
  /// pose projects it, the nearest descriptor within this radius (px), kept when its offset agrees with the median
  /// offset within the tracker's inlier threshold H.
  /// - Intermediate frames: the key frame's features; the agreeing matches are the frame's observations.
  /// - Earlier key frames: their stored points in the key frame; DynamicR1PPnP then checks the agreeing matches.
  /// Where the matches are not trusted (few agree, or the median offset is large: tracking drifted), or are fewer
  /// than minFrameInliers / minKeyFrameInliers, all descriptors are matched and DynamicR1PPnP picks the inliers.
  /// 0: always the latter.
  double guidedSearchRadiusPx = 16.0;
  int storedFeaturesPerKeyFrame = 1000;  ///< strongest features with depth kept per key frame for later matching
  int maxStoredKeyFrames = 3000;  ///< beyond this the oldest key frame is forgotten (memory bound of a long scan)
  int minIcpPoints = 100;        ///< fewer valid model points than this: no ICP term

  // Safety: a refinement is never worse than tracking.
  double maxCorrectionMm = 10.0;   ///< a refined pose farther than this from the tracked one is rejected
  double maxCorrectionDeg = 5.0;   ///< ... and the same for rotation

  /// Throws Error naming the first parameter that is out of range.
  void validate() const;

  /// Writes the parameters under the node name "refinement".
  void write(cv::FileStorage& storage) const;
  /// Reads the parameters from a "refinement" node; keys that are missing keep their defaults, keys of the wrong
  /// type are an error. Validates the result.
  static RefinementParameters read(const cv::FileNode& refinementNode);
};

}  // namespace tissuemosaic
