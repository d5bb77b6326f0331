#pragma once
/// @file ProjectionGuidedMatching.h
/// @brief Descriptor matching guided by a known pose: each query point (in world coordinates, with its descriptor)
/// is projected into a frame at the frame's tracked pose and matched to the nearest descriptor among the frame's
/// keypoints within a search radius of the projection. The refiner uses it for the frames between two key frames,
/// whose tracked poses are good to a few pixels: it replaces an all-pairs descriptor search and a DynamicR1PPnP
/// solve per frame (the paper takes these observations from tracking, without a pose solve).
#include "Tracking/PnpSolver.h"

#include <opencv2/core.hpp>
#include <opencv2/core/types.hpp>

#include <Eigen/Core>

#include <vector>

namespace tissuemosaic {

/// A point nearer to the camera than this (or behind it) is not seen: it has no projection (refinement: guided
/// matching, key-frame overlap, ICP samples and the LM's residuals).
constexpr double kMinVisibleDepthMm = 0.1;

struct ProjectionGuidedMatchParameters {
  double searchRadiusPx = 16.0;  ///< a keypoint farther than this from the projection is not a candidate
  int maxHammingDistance = 64;   ///< of 256 bits; a nearer descriptor is needed for a match
  /// A match counts when its offset from the projection lies within this distance of the median offset of all
  /// matches: the pose's error shifts the projections alike, a wrong match by chance.
  double consistencyPx = 5.0;
  /// The matches are trusted (the pose is good enough for this way of matching) when at least this share of the
  /// candidates agree ...
  double minConsistentShare = 0.9;
  /// ... and the median offset is at most this share of the search radius.
  double maxMedianOffsetShare = 0.5;
};

/// One match: query row and the frame's keypoint (train) index.
struct ProjectionGuidedMatch {
  int query = 0;
  int train = 0;
};

struct ProjectionGuidedMatches {
  std::vector<ProjectionGuidedMatch> matches;  ///< those that agree with the median offset, in query order
  int candidates = 0;                          ///< nearest descriptors found before the agreement test
  Eigen::Vector2d medianOffsetPx = Eigen::Vector2d::Zero();  ///< keypoint minus projection, median of the candidates
  bool trusted = false;  ///< see ProjectionGuidedMatchParameters::minConsistentShare and maxMedianOffsetShare
};

/// Matches query points to a frame's keypoints as described above. Each keypoint matches at most one query (the
/// nearest descriptor wins). queryDescriptors and trainDescriptors: CV_8U, 32 bytes a row, one row per query point
/// and per keypoint. T_camera_world maps world points into the frame's camera. Throws Error on inconsistent
/// inputs.
ProjectionGuidedMatches matchProjectedPoints(const Points3d& queryPointsWorldMm,
                                             const cv::Mat& queryDescriptors,
                                             const std::vector<cv::KeyPoint>& keypoints,
                                             const cv::Mat& trainDescriptors,
                                             const Eigen::Matrix4d& T_camera_world,
                                             const PinholeIntrinsics& intrinsics,
                                             const ProjectionGuidedMatchParameters& parameters);

}  // namespace tissuemosaic
