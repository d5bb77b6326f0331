#pragma once
/// @file EditDistance.h
/// @brief Levenshtein distance and the nearest of a list of names: "did you mean ...?" for options and parameter keys.
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace tissuemosaic {

/// The number of single-character insertions, deletions and substitutions that turn a into b.
inline std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The candidate nearest to word, or "" when none is within maxDistance edits.
inline std::string nearestName(const std::string& word, const std::vector<std::string>& candidates,
                               std::size_t maxDistance) {
  std::string best;
  std::size_t bestDistance = maxDistance + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = editDistance(word, candidate);
    if (distance < bestDistance) {
      bestDistance = distance;
      best = candidate;
    }
  }
  return best;
}

}  // namespace tissuemosaic
