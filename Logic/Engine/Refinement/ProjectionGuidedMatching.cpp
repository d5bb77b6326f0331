#include "ProjectionGuidedMatching.h"

#include "Core/CountingSort.h"
#include "Core/Error.h"
#include "Core/Statistics.h"
#include "Tracking/OrbKernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuemosaic {

namespace {

/// The frame's keypoints bucketed by pixel in square cells of the search radius: the candidates of a projection
/// lie in its cell and the 8 around it. Their pixels are copied in cell order, so that a search reads them from
/// contiguous memory (loading each from its cv::KeyPoint was most of the search's time).
class KeypointGrid {
public:
  KeypointGrid(const std::vector<cv::KeyPoint>& keypoints, double cellPx) : cellPx_(cellPx) {
    float maxX = 0, maxY = 0;
    for (const cv::KeyPoint& k : keypoints) {
      maxX = std::max(maxX, k.pt.x);
      maxY = std::max(maxY, k.pt.y);
    }
    columns_ = static_cast<int>(maxX / cellPx_) + 1;
    rows_ = static_cast<int>(maxY / cellPx_) + 1;
    // The keypoints by cell: start_[c] .. start_[c + 1] index order_.
    Buckets byCell = bucketByKey(static_cast<int>(keypoints.size()), columns_ * rows_, [&](int i) {
      return cell(keypoints[static_cast<std::size_t>(i)].pt.x, keypoints[static_cast<std::size_t>(i)].pt.y);
    });
    start_ = std::move(byCell.begin);
    order_ = std::move(byCell.order);
    xPx_.reserve(order_.size());
    yPx_.reserve(order_.size());
    for (int k : order_) {
      xPx_.push_back(keypoints[static_cast<std::size_t>(k)].pt.x);
      yPx_.push_back(keypoints[static_cast<std::size_t>(k)].pt.y);
    }
  }

  /// Calls visit(keypoint index, its x, its y) for every keypoint in the cells around (x, y).
  template <class Visit>
  void forNeighbours(double x, double y, const Visit& visit) const {
    const int cx = static_cast<int>(std::floor(x / cellPx_)), cy = static_cast<int>(std::floor(y / cellPx_));
    for (int gy = std::max(0, cy - 1); gy <= std::min(rows_ - 1, cy + 1); ++gy) {
      // The three cells of a grid row are consecutive in cell order: one contiguous run.
      const int first = gy * columns_ + std::max(0, cx - 1), last = gy * columns_ + std::min(columns_ - 1, cx + 1);
      if (first > last) continue;
      for (int k = start_[static_cast<std::size_t>(first)]; k < start_[static_cast<std::size_t>(last) + 1]; ++k) {
        visit(order_[static_cast<std::size_t>(k)], xPx_[static_cast<std::size_t>(k)], yPx_[static_cast<std::size_t>(k)]);
      }
    }
  }

private:
  int cell(float x, float y) const {
    const int gx = std::clamp(static_cast<int>(x / cellPx_), 0, columns_ - 1);
    const int gy = std::clamp(static_cast<int>(y / cellPx_), 0, rows_ - 1);
    return gy * columns_ + gx;
  }

  double cellPx_;
  int columns_ = 1, rows_ = 1;
  std::vector<int> start_, order_;
  std::vector<float> xPx_, yPx_;  ///< the keypoints' pixels, in order_
};

}  // namespace

ProjectionGuidedMatches matchProjectedPoints(const Points3d& queryPointsWorldMm,
                                             const cv::Mat& queryDescriptors,
                                             const std::vector<cv::KeyPoint>& keypoints,
                                             const cv::Mat& trainDescriptors,
                                             const Eigen::Matrix4d& T_camera_world,
                                             const PinholeIntrinsics& intrinsics,
                                             const ProjectionGuidedMatchParameters& parameters) {
  require(parameters.searchRadiusPx > 0 && parameters.consistencyPx > 0,
          "guided matching: the search radius and the consistency distance must be positive");
  const auto rowsOf32Bytes = [](const cv::Mat& descriptors, std::size_t rows) {
    return descriptors.type() == CV_8U && descriptors.cols == 32 && descriptors.rows == static_cast<int>(rows);
  };
  require(rowsOf32Bytes(queryDescriptors, queryPointsWorldMm.size()),
          "guided matching: the query descriptors must be one 32-byte row per query point");
  require(rowsOf32Bytes(trainDescriptors, keypoints.size()),
          "guided matching: the frame's descriptors must be one 32-byte row per keypoint");
  ProjectionGuidedMatches result;
  if (queryPointsWorldMm.empty() || keypoints.empty()) return result;

  const KeypointGrid grid(keypoints, parameters.searchRadiusPx);
  const double radius2 = parameters.searchRadiusPx * parameters.searchRadiusPx;
  const Eigen::Matrix3d R = T_camera_world.block<3, 3>(0, 0);
  const Eigen::Vector3d t = T_camera_world.block<3, 1>(0, 3);

  // The nearest descriptor near each projection; a keypoint claimed twice goes to the nearer descriptor.
  constexpr int kNone = -1;
  std::vector<int> bestQueryOfTrain(keypoints.size(), kNone), bestDistanceOfTrain(keypoints.size(), 0);
  std::vector<Eigen::Vector2d> projectedPx(queryPointsWorldMm.size());
  for (std::size_t q = 0; q < queryPointsWorldMm.size(); ++q) {
    const Eigen::Vector3d c = R * queryPointsWorldMm[q] + t;
    if (!(c.z() >= kMinVisibleDepthMm)) continue;
    double u, v;
    intrinsics.project(c.x(), c.y(), c.z(), u, v);
    projectedPx[q] = Eigen::Vector2d(u, v);
    const uchar* query = queryDescriptors.ptr<uchar>(static_cast<int>(q));
    int best = kNone, bestDistance = parameters.maxHammingDistance + 1;
    grid.forNeighbours(u, v, [&](int k, float xPx, float yPx) {
      const double du = xPx - u, dv = yPx - v;
      if (du * du + dv * dv > radius2) return;
      const int distance = orb::hammingDistance(query, trainDescriptors.ptr<uchar>(k));
      if (distance < bestDistance) {
        bestDistance = distance;
        best = k;
      }
    });
    if (best == kNone) continue;
    int& holder = bestQueryOfTrain[static_cast<std::size_t>(best)];
    if (holder == kNone || bestDistance < bestDistanceOfTrain[static_cast<std::size_t>(best)]) {
      holder = static_cast<int>(q);
      bestDistanceOfTrain[static_cast<std::size_t>(best)] = bestDistance;
    }
  }

  std::vector<ProjectionGuidedMatch> matches;
  std::vector<double> offsetX, offsetY;
  for (std::size_t k = 0; k < keypoints.size(); ++k) {
    const int q = bestQueryOfTrain[k];
    if (q == kNone) continue;
    matches.push_back({q, static_cast<int>(k)});
    offsetX.push_back(keypoints[k].pt.x - projectedPx[static_cast<std::size_t>(q)].x());
    offsetY.push_back(keypoints[k].pt.y - projectedPx[static_cast<std::size_t>(q)].y());
  }
  result.candidates = static_cast<int>(matches.size());
  if (matches.empty()) return result;
  result.medianOffsetPx = Eigen::Vector2d(median(offsetX), median(offsetY));
  const double consistency2 = parameters.consistencyPx * parameters.consistencyPx;
  for (std::size_t m = 0; m < matches.size(); ++m) {
    const double dx = offsetX[m] - result.medianOffsetPx.x(), dy = offsetY[m] - result.medianOffsetPx.y();
    if (dx * dx + dy * dy <= consistency2) result.matches.push_back(matches[m]);
  }
  // In query order, as the descriptor matcher's lists come.
  std::sort(result.matches.begin(), result.matches.end(),
            [](const ProjectionGuidedMatch& a, const ProjectionGuidedMatch& b) { return a.query < b.query; });
  // A pose off by more than a few pixels moves true matches out of the search radius (the median offset grows) or
  // shifts the projections unevenly (fewer agree): the agreeing matches would cover only part of the view.
  result.trusted = result.medianOffsetPx.norm() <= parameters.maxMedianOffsetShare * parameters.searchRadiusPx &&
                   result.matches.size() >= parameters.minConsistentShare * matches.size();
  return result;
}

}  // namespace tissuemosaic
