#include "Reconstruction/TimingTable.h"
#include "Core/Statistics.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <numeric>
#include <sstream>

namespace tissuemosaic {
namespace {

std::vector<double> stageValues(const StageTimesMs& t) {
  return {t.videoReading, t.stereo, t.orbVoting, t.pnp, t.agreement, t.refinement, t.tsdf, t.deformation, t.total};
}


std::vector<std::vector<double>> byStage(const std::vector<StageTimesMs>& frames) {
  std::vector<std::vector<double>> stages(TimingTable::stageNames().size());
  for (const StageTimesMs& frame : frames) {
    const std::vector<double> values = stageValues(frame);
    for (std::size_t i = 0; i < values.size(); ++i) stages[i].push_back(values[i]);
  }
  return stages;
}

std::string jsonGroup(const std::vector<std::string>& names, const std::vector<double>& values) {
  std::ostringstream out;
  out << "{";
  for (std::size_t i = 0; i < names.size(); ++i) out << (i ? ", " : "") << "\"" << names[i] << "\": " << cv::format("%.4f", values[i]);
  out << "}";
  return out.str();
}

}  // namespace

const std::vector<std::string>& TimingTable::stageNames() {
  static const std::vector<std::string> names = {"video_reading", "stereo",     "orb_voting", "dynamic_r1ppnp",
                                                 "model_agreement", "refinement", "tsdf",       "deformation",
                                                 "total"};
  return names;
}

void TimingTable::add(const FrameResult& frame) { add(frame.timesMs, frame.keyFrame); }

void TimingTable::add(const StageTimesMs& times, bool keyFrame) {
  (keyFrame ? keyFrameTimes_ : otherFrameTimes_).push_back(times);
}

std::vector<double> TimingTable::medians(bool keyFrames) const {
  std::vector<double> result;
  for (const auto& values : byStage(keyFrames ? keyFrameTimes_ : otherFrameTimes_)) result.push_back(median(values));
  return result;
}

std::vector<double> TimingTable::means(bool keyFrames) const {
  std::vector<double> result;
  for (const auto& values : byStage(keyFrames ? keyFrameTimes_ : otherFrameTimes_)) result.push_back(mean(values));
  return result;
}

std::vector<double> TimingTable::percentiles99(bool keyFrames) const {
  std::vector<double> result;
  for (const auto& values : byStage(keyFrames ? keyFrameTimes_ : otherFrameTimes_)) result.push_back(percentile99(values));
  return result;
}

bool TimingTable::stageShown(std::size_t stage) const {
  if (stageNames()[stage] != "deformation") return true;
  return means(true)[stage] != 0 || means(false)[stage] != 0;
}

std::string TimingTable::format() const {
  static const std::vector<std::string> labels = {"video reading", "stereo matching", "ORB matching and voting",
                                                  "DynamicR1PPnP", "model agreement", "refinement", "TSDF",
                                                  "deformation", "total"};
  const std::vector<double> keyMedian = medians(true), keyMean = means(true), keyP99 = percentiles99(true);
  const std::vector<double> otherMedian = medians(false), otherMean = means(false), otherP99 = percentiles99(false);
  std::ostringstream out;
  out << cv::format("%-26s %29s %29s\n", "milliseconds",
                    cv::format("key frames (%d)", keyFrames()).c_str(),
                    cv::format("other frames (%d)", otherFrames()).c_str());
  out << cv::format("%-26s %9s %9s %9s %9s %9s %9s\n", "", "median", "mean", "p99", "median", "mean", "p99");
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (!stageShown(i)) continue;
    out << cv::format("%-26s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f\n", labels[i].c_str(), keyMedian[i], keyMean[i],
                      keyP99[i], otherMedian[i], otherMean[i], otherP99[i]);
  }
  return out.str();
}

std::string TimingTable::toJson() const {
  const std::vector<std::string>& names = stageNames();
  std::ostringstream out;
  out << "{\"key_frames\": {\"count\": " << keyFrames() << ", \"median_ms\": " << jsonGroup(names, medians(true))
      << ", \"mean_ms\": " << jsonGroup(names, means(true)) << ", \"p99_ms\": " << jsonGroup(names, percentiles99(true))
      << "}, \"other_frames\": {\"count\": " << otherFrames() << ", \"median_ms\": " << jsonGroup(names, medians(false))
      << ", \"mean_ms\": " << jsonGroup(names, means(false)) << ", \"p99_ms\": " << jsonGroup(names, percentiles99(false))
      << "}}";
  return out.str();
}

}  // namespace tissuemosaic
