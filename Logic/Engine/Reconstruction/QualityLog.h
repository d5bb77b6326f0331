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
    bool keyFrame = false;
    int movingMatches = 0;           ///< key-frame matches kept out of the pose (they moved with the scene)
    DisparityRange disparityRange;   ///< the range the frame was matched over
    std::string message;             ///< why it was lost, or how it was relocalised; empty otherwise
    SceneMotion sceneMotion = SceneMotion::Unknown;
    DeformationFrame deformation;    ///< fusion.deformation on: the node motions and the live surface's agreement
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
  /// (null where not measured), "inliers" (the contract keys), then "key_frame", "moving_matches",
  /// "disparity_range" ([min, max] px), "message" (why lost, how relocalised; "" otherwise) and "scene_motion"
  /// ("still", "camera", "tissue", "both"; "unknown" for a lost or first frame: sceneMotionName), and the
  /// deformation's "deformation_mean_mm", "deformation_max_mm" (node motions from rest), "live_share_within_1mm" and
  /// "rigid_share_within_1mm" (the warped and the unwarped model's samples against the frame's depth), null where
  /// not fitted (fusion.deformation off, lost frames, no model yet). Throws Error when the file cannot be written.
  void writeJson(const std::string& path) const;
  /// For a progress line: "agreement 96% within 1 mm, median 0.21 mm", "LOST", ...
  static std::string progressText(const FrameResult& frame);

private:
  std::vector<Record> records_;
};

}  // namespace tissuemosaic
