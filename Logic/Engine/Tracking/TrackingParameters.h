#pragma once
/// @file TrackingParameters.h
/// @brief Every parameter of the section III camera tracking (DynamicR1PPnP, key-frame decision), with the paper's
/// defaults, in one validated struct. The command line, the parameter files and the GUI panel all edit this object.
#include <string>

namespace cv {
class FileStorage;
class FileNode;
}  // namespace cv

namespace tissuemosaic {

struct TrackingParameters {
  // R1PPnP / DynamicR1PPnP (III.B).
  double inlierThresholdPx = 5.0;     ///< H: a match whose reprojection error is <= H px is an inlier (re-weighting knee)
  double candidateEta = 2.0;          ///< eta > 1: a candidate match enters when its error is < eta * H
  int candidateRampIterations = 5;    ///< T: a newly seen candidate's weight ramps in over T iterations
  int maxRansacIterations = 500;      ///< most control points (1-point RANSAC hypotheses) tried per solve
  double ransacConfidence = 0.99;     ///< stop once a better pose is this unlikely (1-point RANSAC bound)
  int maxInnerIterations = 40;        ///< most re-weighting iterations per hypothesis (not in the paper)
  int minInliers = 12;                ///< fewer inliers than this: the solve reports failure (not in the paper)

  // Key-frame decision (III.C).
  int keyFrameMinInliers = 50;        ///< a key frame needs at least this many DynamicR1PPnP inliers
  int keyFrameMinGapFrames = 10;      ///< ... and this many frames since the last key frame,
  double keyFramePoseThreshold = 10;  ///< ... or a pose difference ||dt|| + 20 min(||dE||, 2pi - ||dE||) above this

  // Scene motion (not in the paper). Frames are tracked against the last key frame; a key-frame feature moved with
  // the scene (breathing, an instrument) when its match lands off where the frame's pose projects it (farther than
  // 3 times the frame's median inlier residual, 0.5 px at least, dynamicResidualPx at most), or its depth in this
  // frame differs from the depth the pose predicts by more than 3 times the frame's median difference (in disparity,
  // dynamicDisparityPx at least): both bounds follow the frame's own noise, larger on real in-vivo stereo than on
  // synthetic scans (docs/SCENE_MOTION.md). Its motion score then jumps to 1; the score decays by dynamicScoreDecay per
  // tracked frame and is handed on to the feature it matched when the frame becomes a key frame. Features scoring
  // above dynamicExcludeScore do not steer the pose (while enough others remain) and are not stored for refinement
  // or relocalisation. The pose is polished last on the matches that sit where it projects them (the same bound).
  // dynamicResidualPx 0 switches the image test and the final fit off, dynamicDisparityPx 0 the depth test.
  double dynamicResidualPx = 5.0;
  double dynamicDisparityPx = 1.0;
  double dynamicScoreDecay = 0.97;
  double dynamicExcludeScore = 0.3;

  // The scope's motion prior (not in the paper): a scope moves smoothly. A pose within priorStepMm and
  // priorStepDeg of the one predicted from the last two tracked frames continues that motion: it is kept when the
  // model disagrees with the frame's depth (the tissue moved, not the camera) instead of the frame being lost.
  double priorStepMm = 1.5;
  double priorStepDeg = 1.5;

  // Relocalisation (not in the paper): a lost frame is matched with stored key frames (those that overlapped the
  // last tracked view first, then the others in turn), R1PPnP on the matches.
  int relocalisationMinInliers = 30;  ///< a relocalised pose needs this many inliers
  int relocalisationCandidates = 6;   ///< stored key frames tried per lost frame

  /// Throws Error naming the first parameter that is out of range.
  void validate() const;

  /// Writes the parameters under the node name "tracking".
  void write(cv::FileStorage& storage) const;
  /// Reads the parameters from a "tracking" node; keys that are missing keep their defaults, keys of the wrong type
  /// are an error. Validates the result.
  static TrackingParameters read(const cv::FileNode& trackingNode);
};

}  // namespace tissuemosaic
