#pragma once
/// @file Statistics.h
/// @brief The summary statistics that the benchmarks and timing tables report: one definition of each.
#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace tissuemosaic {

/// The median (the mean of the two middle values for an even count); 0 for no values.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const std::size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(middle), values.end());
  const double upper = values[middle];
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(middle)));
}

/// The arithmetic mean; 0 for no values.
inline double mean(const std::vector<double>& values) {
  return values.empty() ? 0 : std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

/// The 99th percentile by the nearest rank (the smallest value with at least 99 % of the values at or below it):
/// the worst frame in a hundred, which a user feels more than the median. 0 for no values.
inline double percentile99(std::vector<double> values) {
  if (values.empty()) return 0;
  const std::size_t rank = (99 * values.size() + 99) / 100;  // ceil(0.99 n), at least 1
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank - 1), values.end());
  return values[rank - 1];
}

/// The largest value; 0 for no values.
inline double largest(const std::vector<double>& values) {
  return values.empty() ? 0 : *std::max_element(values.begin(), values.end());
}

}  // namespace tissuemosaic
