#include "TimingStatistics.h"

#include "Core/Error.h"
#include "Core/Statistics.h"

#include <opencv2/core.hpp>

namespace tissuemosaic::cli {

TimingSeries::TimingSeries(std::vector<std::string> stageNames) {
  for (std::string& name : stageNames) stages_.emplace_back(std::move(name), std::vector<double>{});
}

void TimingSeries::add(const std::string& stage, double milliseconds) {
  for (auto& [name, values] : stages_) {
    if (name == stage) return values.push_back(milliseconds);
  }
  throw Error("no timing stage named '" + stage + "'");
}

const std::vector<double>& TimingSeries::values(const std::string& stage) const {
  for (const auto& [name, values] : stages_) {
    if (name == stage) return values;
  }
  throw Error("no timing stage named '" + stage + "'");
}

std::string TimingSeries::json(const std::string& prefix) const {
  const auto group = [&](const char* key, double (*statistic)(std::vector<double>)) {
    std::string text = "\"" + prefix + key + "\": {";
    for (std::size_t i = 0; i < stages_.size(); ++i) {
      text += cv::format("%s\"%s\": %.4f", i ? ", " : "", stages_[i].first.c_str(), statistic(stages_[i].second));
    }
    return text + "}";
  };
  const auto meanOf = [](std::vector<double> values) { return mean(values); };
  return group("median_ms", median) + ", " + group("mean_ms", meanOf) + ", " + group("p99_ms", percentile99);
}

}  // namespace tissuemosaic::cli
