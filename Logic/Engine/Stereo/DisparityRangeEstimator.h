#pragma once
/// @file DisparityRangeEstimator.h
/// @brief The automatic disparity range: measured from sparse left-right feature matches (ORB features of both
/// rectified views matched along rows, Tracking/LeftRightMatching.h), whose disparities do not depend on any range.
/// A first frame's range is its robust ends (quantiles) widened by a margin, on the kernels' grid; later ranges
/// follow the tissue with hysteresis, so that they change rarely and do not flap. docs/STEREO.md, "Disparity range".
#include "Core/Device.h"
#include "Core/Error.h"
#include "Stereo/DisparityRange.h"

#include <opencv2/core.hpp>

#include <memory>
#include <vector>

namespace tissuemosaic {

/// The automatic range could not be chosen (too few left-right matches): callers can say how to give one instead.
class DisparityRangeError : public Error {
public:
  using Error::Error;
};

struct DisparityRangeEstimatorOptions {
  // The sparse features (OrbExtractor on the full image only: pixel-accurate positions).
  /// Wider images are measured at a half (a quarter, ...) of their size, disparities scaled back: ORB costs 4x less
  /// per halving. Not lower by default: at half size the near end of a 960 px desk scene came out 12 px short.
  int measureWidthPx = 1280;
  int maxFeatures = 1500;            ///< per view
  int fastThreshold = 4;             ///< FAST threshold (grey levels): tissue has weak texture
  /// Fewer matches than this (a close-up, blurred or smooth tissue): measured again with weakFastThreshold.
  int weakTextureMatches = 100;
  int weakFastThreshold = 2;
  int saturatedGrey = 245;           ///< features within 5 px of a pixel this bright are not matched (highlights)
  int minMatches = 30;               ///< fewer left-right matches: no estimate (a first frame: Error)
  // The range a sample asks for.
  /// Robust ends of the matched disparities (a few percent of wrong matches pass every test; the plane fit, see
  /// DisparitySample::lowPx, reaches the parts of the view beyond them).
  double lowQuantile = 0.02, highQuantile = 0.98;
  /// Matches below infinityDisparityPx - minMarginPx (behind the camera), or beyond the near fence (this many
  /// interquartile ranges above the upper quartile, the range at least a quarter of that quartile's distance from
  /// infinity), are not the tissue and are dropped before the quantiles are taken. During a video, a frame that had more than this share of them shows no tissue (random
  /// matches spread over every disparity): the range stays.
  double maxImplausibleShare = 0.2;
  double nearFenceIqr = 3.0;
  /// The plane fit widens the ends only where the matches lie on it: robust standard deviation about it at most
  /// max(planeTolerancePx, planeToleranceFraction x the quantiles' span). A folded, cratered or instrument-filled
  /// view is no plane, and its corners' extrapolation would be guesses.
  double planeTolerancePx = 2.0, planeToleranceFraction = 0.05;
  double marginFraction = 0.15;      ///< each end moves out by this share of the robust span ...
  double minMarginPx = 3.0;          ///< ... and by at least this much;
  /// but the low (far) end by at most this share of its distance from infinityDisparityPx (depth ~ 1 / (d - that)):
  /// at most 1 / (1 - 0.25) = 1.33 x the farthest tissue's depth.
  double farMarginFraction = 0.25;
  double infinityDisparityPx = 0;    ///< the disparity of a point at infinity: -doffs (0 for the usual rectification)
  // Hysteresis (followingRange): the current range stays while both hold.
  double keepMarginFraction = 0.5;   ///< the robust ends lie at least this share of the margin inside it ...
  double maxWidthFactor = 1.3;       ///< ... and it is at most this many times the robust span wide ...
  double maxWidthSlackPx = 12;
  /// During a video, a frame whose robust span is more than this many times the current range's width, or whose
  /// range the matcher cannot take, is not the tissue: the random matches of a view without tissue (the scope
  /// withdrawn: dark, smoke, blur). The range stays.
  double maxSpanGrowth = 3.0;       ///< ... plus this (never less than the wanted range plus one grid step)
  /// A pipeline that measures beside its frames (ReconstructionPipeline) measures every this many frames, and the
  /// sample decides the range from this many frames after its own on: the measurement (ORB on both views) costs
  /// more than the rest of a frame on the GPU, and the tissue's distance changes little in a tenth of a second.
  int sampleEveryFrames = 3;
  // The rectification check (measure with RowCheck::Measure: a first frame).
  /// Rows searched either way (full-size px) for the offset between the views' rows.
  double rowSearchPx = 12;
  /// Rows offset by more than this (full-size px): the pair is not rectified. Its matches are then sought along the
  /// offset rows (where they are found more often than along equal rows), so that the range is the scene's, and the
  /// sample says so (DisparitySample::rowOffsetPx).
  double maxRowOffsetPx = 1.0;

  /// Throws Error naming the first option out of range.
  void validate() const;
};

/// One frame's sparse disparities.
struct DisparitySample {
  std::vector<float> disparitiesPx;  ///< one per left-right match
  std::vector<cv::Point2f> pointsPx; ///< where in the left view (empty when not known)
  int leftFeatures = 0, rightFeatures = 0;
  /// The robust ends: the quantiles lowQuantile and highQuantile of disparitiesPx, widened to the values at the
  /// corners of the view both eyes see of a plane d = a + b x + c y fitted to the matches (robustly) where they
  /// spread over that view and lie on it.
  /// A planar piece of tissue has exactly such disparities, and featureless parts of the view (smooth, dark or
  /// blurred tissue) have no matches of their own. 0 when there are no matches.
  double lowPx = 0, highPx = 0;
  double medianPx = 0;  ///< of disparitiesPx: how the tissue moves from frame to frame
  /// Right view's row minus left view's row of the same point (full-size px, whole measuring pixels), where the
  /// rectification check ran and found more than maxRowOffsetPx; else 0. Not 0: the pair is not rectified (a wrong
  /// calibration, a capture that shifts one eye) and the disparities were measured along the offset rows; the dense
  /// matching compares equal rows, so the right view must be moved to match (alignRightRows).
  double rowOffsetPx = 0;
  /// Share of the given matches that no tissue can give (beyond infinity, behind the camera): dropped.
  double implausibleShare = 0;
  int matches() const { return static_cast<int>(disparitiesPx.size()); }
};

class DisparityRangeEstimator {
public:
  /// ORB runs on `device` (identical features on the CPU and CUDA, so the same ranges). Throws Error for invalid
  /// options or CUDA where there is none.
  explicit DisparityRangeEstimator(Device device, const DisparityRangeEstimatorOptions& options = {});
  ~DisparityRangeEstimator();
  DisparityRangeEstimator(const DisparityRangeEstimator&) = delete;
  DisparityRangeEstimator& operator=(const DisparityRangeEstimator&) = delete;

  /// The sparse disparities of a rectified pair (8-bit grey, BGR or BGRA, equal sizes): ORB features of both views
  /// (again with a lower FAST threshold where texture is weak), matched along rows (LeftRightMatching.h), without
  /// matches that disagree with their neighbours, lie in a highlight, or come from a part of one view that the other
  /// does not see. An image too small for ORB's border gives an empty sample. Throws Error only for misuse (empty,
  /// mismatched or unsupported images). One call at a time per estimator.
  /// RowCheck::Measure (a video's first frame) also measures how far the views' rows are apart (options'
  /// maxRowOffsetPx), and matches along the offset rows; Skip matches along equal rows (a pair already aligned).
  enum class RowCheck { Skip, Measure };
  DisparitySample measure(const cv::Mat& leftRectified, const cv::Mat& rightRectified, RowCheck rows = RowCheck::Skip);
  /// A sample of given disparities, with its robust ends (what measure() returns for these matches). pointsPx (one
  /// per disparity, in an image of imageSize) or empty: then the ends are the quantiles only.
  DisparitySample sample(std::vector<float> disparitiesPx, int leftFeatures, int rightFeatures,
                         std::vector<cv::Point2f> pointsPx = {}, cv::Size imageSize = {}) const;

  /// The range a sample asks for: its robust ends widened by the margin, on the grid. Throws DisparityRangeError
  /// saying what was found (features, matches) when the sample has fewer than minMatches matches: a dark, blurred or featureless
  /// frame, or two images that are not a rectified stereo pair, must not get a silent default.
  DisparityRange wantedRange(const DisparitySample& sample) const;

  /// The range for the frames the sample decides, given the current one. Those frames are predicted: while the
  /// tissue moves, the robust ends are expected `predictedMoves` times the move of the median disparity since
  /// `previous` (the sample before, when it has enough matches) further: 1 when every frame is measured and decides
  /// the next; (2N - 1) / N when every N-th is, and decides the N frames from N after its own. The current range
  /// stays while it holds the predicted ends with keepMarginFraction of the margin and is not wider than
  /// maxWidthFactor x span + maxWidthSlackPx (hysteresis:
  /// changes are rare and do not flap). Otherwise: the wanted range of the predicted ends, or, when the current one
  /// is wide enough and only misplaced, the current one moved over it (same count: the matcher keeps its
  /// workspace). A sample with fewer than minMatches matches keeps the current range.
  DisparityRange followingRange(const DisparityRange& current, const DisparitySample& sample,
                                const DisparitySample* previous = nullptr, double predictedMoves = 1.0) const;

  const DisparityRangeEstimatorOptions& options() const;
  Device device() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissuemosaic
