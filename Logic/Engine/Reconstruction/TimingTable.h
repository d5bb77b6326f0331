#pragma once
/// @file TimingTable.h
/// @brief The paper's runtime table (video reading, stereo, ORB + voting, DynamicR1PPnP, refinement, TSDF, total;
/// and the model agreement, not in the paper)
/// gathered over a run, separately for key frames and for the other frames, as medians and means.
#include "Reconstruction/ReconstructionPipeline.h"

#include <string>
#include <vector>

namespace tissuemosaic {

class TimingTable {
public:
  /// The stage names, in the paper's order; the JSON keys of toJson().
  static const std::vector<std::string>& stageNames();

  void add(const FrameResult& frame);
  void add(const StageTimesMs& times, bool keyFrame);
  int keyFrames() const { return static_cast<int>(keyFrameTimes_.size()); }
  int otherFrames() const { return static_cast<int>(otherFrameTimes_.size()); }

  /// Median (or mean) milliseconds of each stage over the key frames (keyFrames = true) or the other frames, in
  /// stageNames() order; zeros when there are none.
  std::vector<double> medians(bool keyFrames) const;
  std::vector<double> means(bool keyFrames) const;
  std::vector<double> percentiles99(bool keyFrames) const;  ///< Statistics.h percentile99
  /// Whether a stage's row is shown (stageNames() order): every stage of the paper always; the deformation (not in
  /// the paper, fusion.deformation) only where it ran.
  bool stageShown(std::size_t stage) const;

  /// A plain-text table: one row per stage, columns key frame median / mean / p99, other frame median / mean / p99.
  std::string format() const;
  /// {"key_frames": {"count": n, "median_ms": {...}, "mean_ms": {...}, "p99_ms": {...}}, "other_frames": {...}}.
  std::string toJson() const;

private:
  std::vector<StageTimesMs> keyFrameTimes_, otherFrameTimes_;
};

}  // namespace tissuemosaic
