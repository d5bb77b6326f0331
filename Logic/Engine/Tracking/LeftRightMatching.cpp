#include "Tracking/LeftRightMatching.h"

#include "Core/Error.h"
#include "Core/HostDevice.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <utility>

namespace tissuemosaic {

namespace {

constexpr int kDescriptorBytes = 32;

int hammingDistance(const uint8_t* a, const uint8_t* b) {
  int distance = 0;
  for (int k = 0; k < kDescriptorBytes; k += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + k, 8);
    std::memcpy(&y, b + k, 8);
    distance += popcount64(x ^ y);
  }
  return distance;
}

/// The nearest and second nearest candidate of one feature.
struct Nearest {
  int index = -1;
  int distance = INT_MAX, second = INT_MAX;
  void offer(int candidate, int d) {
    if (d < distance) {
      second = distance;
      distance = d;
      index = candidate;
    } else if (d < second) {
      second = d;
    }
  }
};

}  // namespace

std::vector<LeftRightMatch> matchLeftRight(const OrbFeatures& left, const OrbFeatures& right,
                                           const LeftRightMatchOptions& options) {
  const auto leftCount = static_cast<int>(left.keypoints.size());
  const auto rightCount = static_cast<int>(right.keypoints.size());
  require(left.descriptors.rows == leftCount && right.descriptors.rows == rightCount,
          "left-right matching: one descriptor row per keypoint is needed");
  require(leftCount == 0 || (left.descriptors.cols == kDescriptorBytes && left.descriptors.type() == CV_8U),
          "left-right matching: descriptors must be 32-byte CV_8U rows");
  require(rightCount == 0 || (right.descriptors.cols == kDescriptorBytes && right.descriptors.type() == CV_8U),
          "left-right matching: descriptors must be 32-byte CV_8U rows");
  std::vector<LeftRightMatch> matches;
  if (leftCount == 0 || rightCount == 0) return matches;

  // Right features in row order, so that each left feature's band is one binary search away.
  std::vector<int> byRow(static_cast<std::size_t>(rightCount));
  std::iota(byRow.begin(), byRow.end(), 0);
  std::sort(byRow.begin(), byRow.end(),
            [&](int a, int b) { return right.keypoints[a].yPx < right.keypoints[b].yPx; });
  std::vector<float> rows(byRow.size());
  for (std::size_t i = 0; i < byRow.size(); ++i) rows[i] = right.keypoints[byRow[i]].yPx;

  std::vector<Nearest> nearestRight(static_cast<std::size_t>(leftCount));
  std::vector<Nearest> nearestLeft(static_cast<std::size_t>(rightCount));
  for (int l = 0; l < leftCount; ++l) {
    const OrbKeypoint& k = left.keypoints[l];
    const double bandCentre = k.yPx + options.rowOffsetPx;
    const auto first = std::lower_bound(rows.begin(), rows.end(), static_cast<float>(bandCentre - options.rowTolerancePx));
    for (auto it = first; it != rows.end() && *it <= bandCentre + options.rowTolerancePx; ++it) {
      const int r = byRow[static_cast<std::size_t>(it - rows.begin())];
      const double disparity = k.xPx - right.keypoints[r].xPx;
      if (disparity < options.minDisparityPx || disparity > options.maxDisparityPx) continue;
      const int d = hammingDistance(left.descriptors.ptr(l), right.descriptors.ptr(r));
      nearestRight[l].offer(r, d);
      nearestLeft[r].offer(l, d);
    }
  }
  const auto passes = [&](const Nearest& n) {
    return n.index >= 0 && n.distance <= options.maxHammingDistance &&
           (n.second == INT_MAX || n.distance < options.maxRatio * n.second);
  };
  for (int l = 0; l < leftCount; ++l) {
    const Nearest& n = nearestRight[l];
    if (!passes(n) || !passes(nearestLeft[n.index]) || nearestLeft[n.index].index != l) continue;
    LeftRightMatch match;
    match.left = l;
    match.right = n.index;
    match.disparityPx = left.keypoints[l].xPx - right.keypoints[n.index].xPx;
    match.rowOffsetPx = right.keypoints[n.index].yPx - left.keypoints[l].yPx;
    match.distance = n.distance;
    matches.push_back(match);
  }
  return matches;
}

std::vector<LeftRightMatch> consistentMatches(const std::vector<LeftRightMatch>& matches, const OrbFeatures& left,
                                              const MatchConsistencyOptions& options) {
  require(options.neighbourhoodPx > 0, "match consistency: the neighbourhood must be positive");
  const auto cellOf = [&](const LeftRightMatch& m) {
    const OrbKeypoint& k = left.keypoints.at(static_cast<std::size_t>(m.left));
    return std::make_pair(static_cast<int>(std::floor(k.xPx / options.neighbourhoodPx)),
                          static_cast<int>(std::floor(k.yPx / options.neighbourhoodPx)));
  };
  std::map<std::pair<int, int>, std::vector<float>> cells;
  for (const LeftRightMatch& m : matches) cells[cellOf(m)].push_back(m.disparityPx);

  std::vector<LeftRightMatch> kept;
  std::vector<float> neighbours, deviations;
  for (const LeftRightMatch& m : matches) {
    const auto [cx, cy] = cellOf(m);
    neighbours.clear();
    bool self = false;  // the match's own entry is left out once
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto cell = cells.find({cx + dx, cy + dy});
        if (cell == cells.end()) continue;
        for (float d : cell->second) {
          if (!self && dx == 0 && dy == 0 && d == m.disparityPx) {
            self = true;
            continue;
          }
          neighbours.push_back(d);
        }
      }
    }
    if (static_cast<int>(neighbours.size()) < options.minNeighbours) continue;
    const auto middle = neighbours.begin() + static_cast<std::ptrdiff_t>(neighbours.size() / 2);
    std::nth_element(neighbours.begin(), middle, neighbours.end());
    const float median = *middle;
    deviations.clear();
    for (float d : neighbours) deviations.push_back(std::abs(d - median));
    const auto deviationMiddle = deviations.begin() + static_cast<std::ptrdiff_t>(deviations.size() / 2);
    std::nth_element(deviations.begin(), deviationMiddle, deviations.end());
    const double tolerance = std::max(options.minTolerancePx, options.spreadFactor * *deviationMiddle);
    if (std::abs(m.disparityPx - median) <= tolerance) kept.push_back(m);
  }
  return kept;
}

}  // namespace tissuemosaic
