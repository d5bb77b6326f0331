#pragma once
/// @file DisparityRangeFollower.h
/// @brief The disparity range of a stereo video, frame by frame, as StereoParameters::disparityRangeMode asks. Fixed
/// and WorkingDistance give one range for the whole video. Automatic measures the first frame before it is matched,
/// and after each frame decides the next frame's range from that frame's sparse matches
/// (DisparityRangeEstimator::followingRange, with hysteresis). The range never changes inside a frame: whoever runs
/// the matcher asks beforeFrame() once per frame, before the dense matching starts.
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "Stereo/DisparityRange.h"
#include "Stereo/DisparityRangeEstimator.h"
#include "Stereo/StereoParameters.h"

#include <memory>
#include <optional>
#include <string>

namespace tissuemosaic {

/// What the follower chose so far.
struct DisparityRangeHistory {
  DisparityRangeMode mode = DisparityRangeMode::Automatic;
  std::optional<DisparityRange> first, current;
  DisparityRange widest;       ///< the union of every range used (valid once first is set)
  int changes = 0;             ///< range changes after the first frame
  int firstMatches = 0;        ///< Automatic: left-right feature matches of the first frame
  /// Automatic: the first frame's right row minus left row of the same point, px (DisparitySample::rowOffsetPx);
  /// not 0: the pair is not rectified, and the description says so.
  double rowOffsetPx = 0;
};

class DisparityRangeFollower {
public:
  /// geometry: of the rectified frames (WorkingDistance converts through it; the automatic range takes its doffs,
  /// the disparity at infinity being -doffs; a default geometry means doffs 0). Throws Error for invalid parameters,
  /// a working distance the rig cannot turn into a range, or CUDA where there is none.
  DisparityRangeFollower(const StereoParameters& parameters, const RectifiedGeometry& geometry, Device device);
  ~DisparityRangeFollower();
  DisparityRangeFollower(const DisparityRangeFollower&) = delete;
  DisparityRangeFollower& operator=(const DisparityRangeFollower&) = delete;

  bool automatic() const;
  /// The range to match this frame with (rectified 8-bit grey or BGR views). Automatic: the first call measures this
  /// pair and throws Error saying what was found when it has too few matches; later calls return what afterFrame()
  /// decided.
  DisparityRange beforeFrame(const cv::Mat& leftRectified, const cv::Mat& rightRectified);
  /// Automatic: the sparse disparities of a frame (may run beside the frame's dense matching, on another thread than
  /// beforeFrame and afterFrame, one call at a time). Otherwise an empty sample.
  DisparitySample measure(const cv::Mat& leftRectified, const cv::Mat& rightRectified);
  /// Automatic: decides the range of the frames after the sample's (DisparityRangeEstimator::followingRange, with
  /// its predictedMoves: 1 when every frame is measured). Otherwise nothing.
  void afterFrame(const DisparitySample& sample, double predictedMoves = 1.0);
  /// Automatic: how often a pipeline that measures beside its frames measures
  /// (DisparityRangeEstimatorOptions::sampleEveryFrames); 1 otherwise.
  int sampleEveryFrames() const;
  /// measure() then afterFrame(), for callers that do one thing at a time.
  void afterFrame(const cv::Mat& leftRectified, const cv::Mat& rightRectified);

  const DisparityRangeHistory& history() const;
  /// The right rectified view moved onto the left's rows when the first frame found them apart (history().rowOffsetPx;
  /// alignRightRows), else the same image. Callers give the dense matcher and measure() the aligned view.
  cv::Mat alignedRight(const cv::Mat& rightRectified) const;
  /// One line for logs and the GUI, e.g. "auto: 64..95 px (from 412 left-right feature matches)", "auto: 72..103 px
  /// (first 64..95 px from 412 left-right feature matches; 2 changes, widest 64..103 px)", "fixed: -20..80 px" or
  /// "working distance 30..150 mm: 28..143 px"; followed by rowOffsetWarning() where the rows disagree.
  std::string description() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// description() of a history, for whoever holds only the history (the app's logic).
std::string describeDisparityRange(const DisparityRangeHistory& history, const StereoParameters& parameters);

/// Empty for a rectified pair; else one sentence: "not rectified: the right view's rows lay 4 px above the left's; it
/// is moved 4 rows down before matching (check the calibration)".
std::string rowOffsetWarning(const DisparityRangeHistory& history);

/// The right view moved by -rowOffsetPx rows (rounded), so that a point lies on the same row in both views; rows that
/// enter are black (textureless: the matcher gives them no estimate). The same image for an offset under half a row.
cv::Mat alignRightRows(const cv::Mat& rightRectified, double rowOffsetPx);

/// A history as one JSON object: {"mode": "auto", "first": [min, max], "last": [min, max], "widest": [min, max],
/// "changes": n, "first_frame_matches": n, "row_offset_px": x} (ranges null before the first frame; matches and the
/// row offset only for auto).
std::string disparityRangeJson(const DisparityRangeHistory& history);

}  // namespace tissuemosaic
