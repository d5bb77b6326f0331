#pragma once
/// @file HistogramVoting.h
/// @brief Paper III.A: matches between adjacent frames are ranked by how many other matches share their 2D
/// displacement. Between adjacent frames of a slow scan the true matches move nearly alike, while wrong matches
/// scatter; the ranking (the vote order) tells DynamicR1PPnP which matches to try first as control points.
#include <Eigen/Core>
#include <Eigen/StdVector>

#include <vector>

namespace tissuemosaic {

struct HistogramVote {
  /// Indices of the matches, most likely inliers first: by descending score, ties by ascending index.
  std::vector<int> order;
  /// Per match: the count of matches in its displacement bin and the 8 neighbouring bins (so matches near a bin
  /// border are not split from their peers).
  std::vector<int> scores;
};

/// Votes on displacements to - from (pixels) in a 2D histogram with square bins of binSizePx. from and to must be
/// of equal length (Error otherwise); binSizePx must be positive. Non-finite displacements score 0 and come last.
HistogramVote histogramVote(const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& fromPx,
                            const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& toPx,
                            double binSizePx);

}  // namespace tissuemosaic
