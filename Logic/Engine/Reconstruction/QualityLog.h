#pragma once
/// @file QualityLog.h
/// @brief What a run tells the user about each frame's pose: its status (tracked, lost, relocalised), the model
/// agreement (ModelAgreement.h) and the inliers, gathered frame by frame; the spans of lost frames and the frames
/// where tracking resumed; the JSON that `reconstruct --quality-json` and `--timing-json` write.
#include "Reconstruction/ReconstructionPipeline.h"

#include <string>
#include <utility>
#include <vector>

namespace tissuemosaic {

class QualityLog {
public:
  struct Record {
    int frame = 0;
    FrameStatus status = FrameStatus::Lost;
    ModelAgreement agreement;
    int inliers = 0;
  };

  void add(const FrameResult& frame);
  const std::vector<Record>& records() const { return records_; }
  /// [first, last] of each run of consecutive lost frames, in order.
  std::vector<std::pair<int, int>> lostSpans() const;
  /// The frames whose status is relocalised, in order.
  std::vector<int> relocalisations() const;
  /// "[[first, last], ...]" and "[frame, ...]".
  std::string lostSpansJson() const;
  std::string relocalisationsJson() const;
  /// A JSON array of one object per frame: "frame", "status", "median_depth_difference_mm", "share_within_1mm"
  /// (null where not measured), "inliers". Throws Error when the file cannot be written.
  void writeJson(const std::string& path) const;
  /// For a progress line: "agreement 96% within 1 mm, median 0.21 mm", "LOST", ...
  static std::string progressText(const FrameResult& frame);

private:
  std::vector<Record> records_;
};

}  // namespace tissuemosaic
