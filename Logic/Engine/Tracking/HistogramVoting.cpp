#include "Tracking/HistogramVoting.h"

#include "Core/Error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace tissuemosaic {

HistogramVote histogramVote(const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& fromPx,
                            const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>& toPx,
                            double binSizePx) {
  require(fromPx.size() == toPx.size(), "histogram voting: " + std::to_string(fromPx.size()) + " start points but " +
                                            std::to_string(toPx.size()) + " end points");
  require(binSizePx > 0 && std::isfinite(binSizePx), "histogram voting: the bin size must be a positive number of pixels");
  const int n = static_cast<int>(fromPx.size());
  // Sparse histogram: displacements span the whole image, but only a few bins are occupied.
  // Shifted as unsigned: shifting a negative bin index is undefined behaviour in C++17 (UBSan reports it).
  const auto key = [](long long bx, long long by) {
    return (static_cast<unsigned long long>(bx) << 32) ^ (static_cast<unsigned long long>(by) & 0xffffffffULL);
  };
  std::vector<long long> binX(n), binY(n);
  std::vector<char> valid(n, 0);
  std::unordered_map<unsigned long long, int> counts;
  counts.reserve(2 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d d = toPx[i] - fromPx[i];
    if (!d.allFinite() || std::abs(d.x()) > 1e9 || std::abs(d.y()) > 1e9) continue;
    valid[i] = 1;
    binX[i] = static_cast<long long>(std::floor(d.x() / binSizePx));
    binY[i] = static_cast<long long>(std::floor(d.y() / binSizePx));
    ++counts[key(binX[i], binY[i])];
  }
  HistogramVote vote;
  vote.scores.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    int score = 0;
    for (long long dy = -1; dy <= 1; ++dy) {
      for (long long dx = -1; dx <= 1; ++dx) {
        const auto bin = counts.find(key(binX[i] + dx, binY[i] + dy));
        if (bin != counts.end()) score += bin->second;
      }
    }
    vote.scores[i] = score;
  }
  vote.order.resize(n);
  std::iota(vote.order.begin(), vote.order.end(), 0);
  std::stable_sort(vote.order.begin(), vote.order.end(),
                   [&](int a, int b) { return vote.scores[a] > vote.scores[b]; });
  return vote;
}

}  // namespace tissuemosaic
