#include "Reconstruction/QualityLog.h"

#include "Core/Error.h"
#include "IO/AtomicFile.h"

#include <opencv2/core.hpp>


namespace tissuemosaic {
namespace {

/// A JSON string literal: quotes, backslashes and control characters escaped.
std::string jsonString(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') quoted += std::string("\\") + c;
    else if (static_cast<unsigned char>(c) < 0x20) quoted += cv::format("\\u%04x", c);
    else quoted += c;
  }
  return quoted + "\"";
}

}  // namespace

void QualityLog::add(const FrameResult& frame) {
  records_.push_back({frame.frameIndex, frame.status, frame.agreement, frame.inliers, frame.keyFrame,
                      frame.movingMatches, frame.disparityRange, frame.trackingMessage, frame.sceneMotion,
                      frame.deformation});
}

std::vector<std::pair<int, int>> QualityLog::lostSpans() const {
  std::vector<std::pair<int, int>> spans;
  for (const Record& r : records_) {
    if (r.status != FrameStatus::Lost) continue;
    if (!spans.empty() && spans.back().second == r.frame - 1) spans.back().second = r.frame;
    else spans.emplace_back(r.frame, r.frame);
  }
  return spans;
}

std::vector<int> QualityLog::relocalisations() const {
  std::vector<int> frames;
  for (const Record& r : records_) {
    if (r.status == FrameStatus::Relocalised) frames.push_back(r.frame);
  }
  return frames;
}

std::string QualityLog::lostSpansJson() const {
  std::string json = "[";
  for (const auto& [first, last] : lostSpans()) json += cv::format("%s[%d, %d]", json.size() > 1 ? ", " : "", first, last);
  return json + "]";
}

std::string QualityLog::relocalisationsJson() const {
  std::string json = "[";
  for (int frame : relocalisations()) json += cv::format("%s%d", json.size() > 1 ? ", " : "", frame);
  return json + "]";
}

void QualityLog::writeJson(const std::string& path) const {
  // Atomic: a failed write leaves an existing file as it was (docs/RELIABILITY.md).
  writeStreamAtomically(path, "quality JSON", [this](std::ostream& out) {
  out << "[";
  for (std::size_t i = 0; i < records_.size(); ++i) {
    const Record& r = records_[i];
    const bool measured = r.agreement.measured;
    out << (i ? ",\n " : "\n ")
        << cv::format("{\"frame\": %d, \"status\": \"%s\", \"median_depth_difference_mm\": %s, \"share_within_1mm\": %s, "
                      "\"inliers\": %d, \"key_frame\": %s, \"moving_matches\": %d, \"disparity_range\": [%d, %d], "
                      "\"message\": %s, \"scene_motion\": \"%s\"",
                      r.frame, frameStatusName(r.status),
                      measured ? cv::format("%.4f", r.agreement.medianDepthDifferenceMm).c_str() : "null",
                      measured ? cv::format("%.4f", r.agreement.shareWithin1mm).c_str() : "null", r.inliers,
                      r.keyFrame ? "true" : "false", r.movingMatches, r.disparityRange.minPx, r.disparityRange.maxPx,
                      jsonString(r.message).c_str(), sceneMotionName(r.sceneMotion));
    const DeformationFrame& d = r.deformation;
    const auto figure = [&d](double value) { return d.fitted ? cv::format("%.4f", value) : std::string("null"); };
    out << ", \"deformation_mean_mm\": " << figure(d.meanNodeMotionMm) << ", \"deformation_max_mm\": "
        << figure(d.maxNodeMotionMm) << ", \"live_share_within_1mm\": " << figure(d.liveShareWithin1mm)
        << ", \"rigid_share_within_1mm\": " << figure(d.rigidShareWithin1mm) << "}";
  }
  out << "\n]\n";
  });
}

std::string QualityLog::progressText(const FrameResult& frame) {
  if (frame.status == FrameStatus::Lost) return "LOST";
  const std::string prefix = frame.status == FrameStatus::Relocalised ? "relocalised, " : "";
  if (!frame.agreement.measured) return prefix + "agreement not measured";
  return prefix + cv::format("agreement %.0f%% within 1 mm, median %.2f mm (%s)", 100 * frame.agreement.shareWithin1mm,
                             frame.agreement.medianDepthDifferenceMm, agreementLevelName(frame.agreementLevel));
}

}  // namespace tissuemosaic
