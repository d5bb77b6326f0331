#pragma once
/// @file TimingStatistics.h
/// @brief The statistics every timing JSON of the bench commands carries per stage: median, mean and 99th
/// percentile milliseconds (Core/Statistics.h), as `"median_ms": {...}, "mean_ms": {...}, "p99_ms": {...}`.
#include <string>
#include <utility>
#include <vector>

namespace tissuemosaic::cli {

/// Milliseconds per stage over the timed runs, in the order the stages were named.
class TimingSeries {
public:
  explicit TimingSeries(std::vector<std::string> stageNames);
  /// Appends one run's time of `stage` (one of the names given to the constructor).
  void add(const std::string& stage, double milliseconds);
  const std::vector<double>& values(const std::string& stage) const;
  /// The three statistics as JSON members, each key prefixed by `prefix` ("" or e.g. "orb_voting_parts_"):
  /// `"<prefix>median_ms": {"stage": ms, ...}, "<prefix>mean_ms": {...}, "<prefix>p99_ms": {...}`.
  std::string json(const std::string& prefix = "") const;

private:
  std::vector<std::pair<std::string, std::vector<double>>> stages_;
};

}  // namespace tissuemosaic::cli
