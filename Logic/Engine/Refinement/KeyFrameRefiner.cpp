#include "KeyFrameRefiner.h"

#include "Core/BackgroundWorker.h"
#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelFor.h"
#include "Core/RigidTransform.h"
#include "Core/Stopwatch.h"
#include "Refinement/ProjectionGuidedMatching.h"
#include "Refinement/RefinementSolver.h"
#include "Tracking/HistogramVoting.h"
#include "Tracking/OrbFeatures.h"
#include "Tracking/PnpSolver.h"
#include "Tracking/SubPixelMatch.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <optional>

namespace tissuemosaic {

namespace {

using refinement::Observation;
using refinement::Pose;

constexpr int kOverlapSamples = 200;  ///< stored points projected per earlier key frame to measure its overlap
/// DynamicR1PPnP hypotheses tried at once (solveDynamicR1Ppnp): a set matched by all descriptors after tracking
/// drifted (a return to an earlier key frame) can take all of maxSolveHypotheses, one after another the longest part
/// of such a key frame. A constant, so that the answer does not depend on the machine's thread count.
constexpr int kPnpHypothesesAtOnce = 8;
/// Share of an earlier key frame's guided candidates that must agree with their median offset before DynamicR1PPnP
/// checks them (an intermediate frame's guided matches need ProjectionGuidedMatchParameters' default, 0.9: they are
/// taken as observations unchecked). An old key frame seen again from another distance and angle (the bench scan's
/// first key frame at its return) has more wrong nearest descriptors: 0.81-0.88 of its candidates agreed, with a
/// median offset of 0.2 px, and all descriptors then took all 50 hypotheses and mostly found no pose.
constexpr double kKeyFrameGuidedMinConsistentShare = 0.5;

Pose toPose(const Eigen::Matrix4d& T_camera_world) {
  Pose pose;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) pose.r[3 * r + c] = T_camera_world(r, c);
    pose.t[r] = T_camera_world(r, 3);
  }
  return pose;
}

Eigen::Matrix4d fromPose(const Pose& pose) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T(r, c) = pose.r[3 * r + c];
    T(r, 3) = pose.t[r];
  }
  return T;
}

/// Rotation (degrees) and translation (mm) between two camera-to-world poses.
void correction(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double& degrees, double& mm) {
  degrees = Eigen::AngleAxisd(Eigen::Matrix3d(a.block<3, 3>(0, 0).transpose() * b.block<3, 3>(0, 0))).angle() * 180.0 / M_PI;
  mm = (a.block<3, 1>(0, 3) - b.block<3, 1>(0, 3)).norm();
}

/// An earlier key frame as stored for matching: no images.
struct StoredKeyFrame {
  int frameIndex = 0;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  std::vector<cv::Point2f> pixelsPx;
  cv::Mat descriptors;  ///< CV_8U, one row per pixel
  std::vector<Eigen::Vector3f> pointsWorldMm;
  /// A sphere holding every point of pointsWorldMm: a key frame whose sphere lies outside the view overlaps nothing.
  Eigen::Vector3d boundsCentreWorldMm = Eigen::Vector3d::Zero();
  double boundsRadiusMm = 0;

  std::size_t bytes() const {
    return pixelsPx.size() * sizeof(cv::Point2f) + descriptors.total() * descriptors.elemSize() +
           pointsWorldMm.size() * sizeof(Eigen::Vector3f);
  }
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

struct IntermediateFrame {
  int frameIndex = 0;
  StereoFeatures features;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// Descriptor matches of query features (with world points) in a frame, ready for DynamicR1PPnP.
struct MatchSet {
  Points3d pointsWorldMm;
  Pixels2d pixelsPx, fromPx;
  std::vector<std::vector<CandidateMatch>> candidates;
  std::vector<int> query, train;
  std::vector<std::vector<int>> candidateTrain;

  /// Query q (its world point and pixel) matched to the frame's keypoint `trainIndex`, with DynamicR1PPnP's further
  /// candidates (keypoint indices in furtherTrain).
  void add(int q, int trainIndex, const Points3d& queryWorld, const std::vector<cv::Point2f>& queryPx,
           const StereoFeatures& frame, std::vector<CandidateMatch> further = {}, std::vector<int> furtherTrain = {}) {
    query.push_back(q);
    train.push_back(trainIndex);
    pointsWorldMm.push_back(queryWorld[static_cast<std::size_t>(q)]);
    const cv::Point2f& from = queryPx[static_cast<std::size_t>(q)];
    fromPx.emplace_back(from.x, from.y);
    const cv::Point2f& to = frame.keypoints[static_cast<std::size_t>(trainIndex)].pt;
    pixelsPx.emplace_back(to.x, to.y);
    candidates.push_back(std::move(further));
    candidateTrain.push_back(std::move(furtherTrain));
  }
};

/// A DynamicR1PPnP inlier: match index in its MatchSet, the frame's feature, and its pixel.
struct Inlier {
  int match;
  int train;
  Eigen::Vector2d pixelPx;
};

}  // namespace

struct KeyFrameMatches::Data {
  int frameIndex = 0;
  const StereoFeatures* features = nullptr;  ///< the caller's, alive until refineMatchedKeyFrame
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  std::chrono::steady_clock::time_point start;
  uint64_t refinerState = 0;  ///< KeyFrameRefiner::Impl::state when matched
  RefinementResult result;    ///< the matching's counts and times so far
  /// Per key-frame feature: its world point (fixed where an earlier key frame saw it, else lifted with the tracked
  /// pose) and whether it is fixed.
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> trackWorld;
  std::vector<uint8_t> fixed;
  std::vector<Observation> observations;  ///< of the key frame's features in the intermediate frames (pose slot 1..)
  std::vector<int> frameOfSlot;           ///< intermediate frame per pose slot 1..
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

/// The intermediate frames' part of KeyFrameMatches, with what it counted.
struct IntermediateMatches {
  std::vector<Observation> observations;  ///< pose slot 1.. per intermediate frame kept
  std::vector<int> frameOfSlot;
  int guidedFrames = 0;
  int hypotheses = 0;
  double milliseconds = 0;
};

KeyFrameMatches::KeyFrameMatches() = default;
KeyFrameMatches::~KeyFrameMatches() = default;
KeyFrameMatches::KeyFrameMatches(KeyFrameMatches&&) noexcept = default;
KeyFrameMatches& KeyFrameMatches::operator=(KeyFrameMatches&&) noexcept = default;

struct KeyFrameRefiner::Impl {
  RectifiedGeometry geometry;
  RefinementParameters parameters;
  TrackingParameters tracking;  ///< the tracker's DynamicR1PPnP settings, hypotheses capped by maxSolveHypotheses
  FeatureParameters features;
  Device device;
  HammingMatcher matcher;  ///< all frames of a step in one call
  HammingMatcher intermediateMatcher;  ///< the same for the intermediate frames, matched beside the key frames
  std::shared_ptr<SubPixelMatcher> subPixel;
  std::deque<StoredKeyFrame, Eigen::aligned_allocator<StoredKeyFrame>> keyFrames;
  std::vector<IntermediateFrame, Eigen::aligned_allocator<IntermediateFrame>> intermediates;
  uint64_t state = 0;  ///< counts the changes of keyFrames and intermediates (matches must see the same frames)
  BackgroundWorker worker;  ///< matches the intermediate frames beside the earlier key frames; last: stops first

  Impl(const RectifiedGeometry& g, const RefinementParameters& p, const TrackingParameters& t,
       const FeatureParameters& f, Device d, std::shared_ptr<SubPixelMatcher> sharedSubPixel)
      : geometry(g), parameters(p), tracking(t), features(f), device(d), matcher(d), intermediateMatcher(d),
        subPixel(sharedSubPixel ? std::move(sharedSubPixel)
                                : std::make_shared<SubPixelMatcher>(d, f.maxRefinementShiftPx)) {
    tracking.maxRansacIterations = std::min(tracking.maxRansacIterations, parameters.maxSolveHypotheses);
  }

  int matchK() const { return std::min(8, 1 + features.candidatesPerFeature); }

  /// Descriptor matches (knn: one list per query row, from HammingMatcher) of query rows with world points
  /// queryWorld and pixels queryPx in a frame's features: the nearest descriptor is the primary match, the next
  /// ones DynamicR1PPnP's candidates.
  MatchSet toMatchSet(const std::vector<std::vector<cv::DMatch>>& knn, const Points3d& queryWorld,
                      const std::vector<cv::Point2f>& queryPx, const StereoFeatures& frame) const {
    MatchSet set;
    for (const std::vector<cv::DMatch>& list : knn) {
      if (list.empty() || list[0].distance > features.maxHammingDistance) continue;
      std::vector<CandidateMatch> further;
      std::vector<int> furtherTrain;
      for (std::size_t j = 1; j < list.size() && list[j].distance <= features.maxHammingDistance; ++j) {
        const cv::Point2f& p = frame.keypoints[list[j].trainIdx].pt;
        CandidateMatch candidate;
        candidate.pixelPx = Eigen::Vector2d(p.x, p.y);
        further.push_back(candidate);
        furtherTrain.push_back(list[j].trainIdx);
      }
      set.add(list[0].queryIdx, list[0].trainIdx, queryWorld, queryPx, frame, std::move(further), std::move(furtherTrain));
    }
    return set;
  }

  /// Matches found near the projections (no further candidates), as a MatchSet like the one above.
  MatchSet toMatchSet(const ProjectionGuidedMatches& found, const Points3d& queryWorld,
                      const std::vector<cv::Point2f>& queryPx, const StereoFeatures& frame) const {
    MatchSet set;
    for (const ProjectionGuidedMatch& match : found.matches) set.add(match.query, match.train, queryWorld, queryPx, frame);
    return set;
  }

  ProjectionGuidedMatchParameters guidedMatchParameters() const {
    ProjectionGuidedMatchParameters guide;
    guide.searchRadiusPx = parameters.guidedSearchRadiusPx;
    guide.maxHammingDistance = features.maxHammingDistance;
    guide.consistencyPx = tracking.inlierThresholdPx;
    return guide;
  }

  /// Sub-pixel positions of the inliers of every frame (as the tracker refines its matches), in one call: each
  /// inlier's pixel is moved so that the window there matches the window at its query pixel in the key frame; an
  /// inlier whose window does not lock on is dropped.
  /// frameIds: the frame indices of the key frame and of the frames (the images' names in the matcher's cache).
  void refineInliers(std::vector<std::vector<Inlier>>& inlierSets, const std::vector<MatchSet>& sets,
                     const cv::Mat& keyFrameGrey, int keyFrameIndex, const std::vector<cv::Mat>& frameGreys,
                     const std::vector<int>& frameIndices) {
    if (!features.subPixelRefinement || keyFrameGrey.empty()) return;
    std::vector<cv::Mat> images{keyFrameGrey};
    std::vector<int64_t> ids{keyFrameIndex};
    std::vector<SubPixelMatchQuery> queries;
    for (std::size_t f = 0; f < inlierSets.size(); ++f) {
      if (frameGreys[f].empty()) continue;
      images.push_back(frameGreys[f]);
      ids.push_back(frameIndices[f]);
      for (const Inlier& inlier : inlierSets[f]) {
        SubPixelMatchQuery query;
        query.referenceImage = 0;
        query.image = static_cast<int>(images.size()) - 1;
        const Eigen::Vector2d& from = sets[f].fromPx[inlier.match];
        query.fromPx = cv::Point2f(static_cast<float>(from.x()), static_cast<float>(from.y()));
        query.toPx = cv::Point2f(static_cast<float>(inlier.pixelPx.x()), static_cast<float>(inlier.pixelPx.y()));
        queries.push_back(query);
      }
    }
    const std::vector<SubPixelMatchAnswer> answers = subPixel->refine(images, queries, ids);
    std::size_t q = 0;
    for (std::size_t f = 0; f < inlierSets.size(); ++f) {
      if (frameGreys[f].empty()) continue;
      std::vector<Inlier>& inliers = inlierSets[f];
      std::size_t kept = 0;
      for (std::size_t i = 0; i < inliers.size(); ++i, ++q) {
        if (!answers[q].locked) continue;
        inliers[kept] = inliers[i];
        inliers[kept++].pixelPx = Eigen::Vector2d(answers[q].toPx.x, answers[q].toPx.y);
      }
      inliers.resize(kept);
    }
  }

  /// Drops the inliers farther from the projection of their point at T_camera_world (after the set's median offset,
  /// the pose's own error) than the tracker's final fit allows: kFitMedianFactor times the median, at least
  /// kFitMinPx, at most the tracking's dynamicResidualPx.
  void keepFitting(std::vector<Inlier>& inliers, const MatchSet& set, const Eigen::Matrix4d& T_camera_world) const {
    if (inliers.empty() || !(tracking.dynamicResidualPx > 0)) return;
    const PinholeIntrinsics k = geometry.leftIntrinsics();
    const Eigen::Matrix3d R = T_camera_world.block<3, 3>(0, 0);
    const Eigen::Vector3d t = T_camera_world.block<3, 1>(0, 3);
    std::vector<Eigen::Vector2d> offsets;
    for (const Inlier& inlier : inliers) {
      const Eigen::Vector3d c = R * set.pointsWorldMm[static_cast<std::size_t>(inlier.match)] + t;
      Eigen::Vector2d projected(0, 0);
      if (c.z() > kMinVisibleDepthMm) k.project(c.x(), c.y(), c.z(), projected.x(), projected.y());
      offsets.push_back(inlier.pixelPx - projected);
    }
    const auto median = [](std::vector<double> values) {
      std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
      return values[values.size() / 2];
    };
    std::vector<double> xs, ys;
    for (const Eigen::Vector2d& o : offsets) {
      xs.push_back(o.x());
      ys.push_back(o.y());
    }
    const Eigen::Vector2d centre(median(xs), median(ys));
    std::vector<double> residuals;
    for (const Eigen::Vector2d& o : offsets) residuals.push_back((o - centre).norm());
    const double bound = std::clamp(kFitMedianFactor * median(residuals), std::min(kFitMinPx, tracking.dynamicResidualPx),
                                    tracking.dynamicResidualPx);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < inliers.size(); ++i) {
      if ((offsets[i] - centre).norm() <= bound) inliers[kept++] = inliers[i];
    }
    inliers.resize(kept);
  }

  /// Drops the inliers on key-frame features the tracker saw moving, and those whose stored world point is not where
  /// the key frame's own stereo puts it: its depth in the key frame's camera (at T_camera_world) differs from the measured one by more than the tracking's
  /// dynamicDisparityPx of disparity. The tissue moved there since that key frame (breathing), so the old position
  /// must not be fixed in the bundle adjustment.
  void dropMovedPoints(std::vector<Inlier>& inliers, const MatchSet& set, const StereoFeatures& keyFrame,
                       const Eigen::Matrix4d& T_camera_world) const {
    const double focalBaseline = geometry.focalPx * geometry.baselineMm;
    const Eigen::Matrix3d R = T_camera_world.block<3, 3>(0, 0);
    const Eigen::Vector3d t = T_camera_world.block<3, 1>(0, 3);
    std::size_t kept = 0;
    for (const Inlier& inlier : inliers) {
      const Eigen::Vector3d c = R * set.pointsWorldMm[static_cast<std::size_t>(inlier.match)] + t;
      const Eigen::Vector3d& measured = keyFrame.pointsCameraMm[static_cast<std::size_t>(inlier.train)];
      const bool flagged = !keyFrame.moving.empty() && keyFrame.moving[static_cast<std::size_t>(inlier.train)];
      const bool moved = flagged || (tracking.dynamicDisparityPx > 0 && measured.allFinite() && measured.z() > 0 &&
                                     c.z() > kMinVisibleDepthMm &&
                                     focalBaseline * std::abs(1.0 / measured.z() - 1.0 / c.z()) > tracking.dynamicDisparityPx);
      if (!moved) inliers[kept++] = inlier;
    }
    inliers.resize(kept);
  }

  /// DynamicR1PPnP on the matches, started from T_world_expected (the frame's tracked pose). Returns the inliers as
  /// (match index, train feature, pixel) when the solve succeeds with at least minInliers and its pose lies within
  /// the correction limits of T_world_expected.
  /// hypotheses: set to the DynamicR1PPnP hypotheses tried (0 without a solve).
  std::vector<Inlier> solveInliers(const MatchSet& set, int minInliers, const Eigen::Matrix4d& T_world_expected,
                                   int& hypotheses) {
    std::vector<Inlier> inliers;
    hypotheses = 0;
    if (static_cast<int>(set.query.size()) < std::max(minInliers, 4)) return inliers;
    const HistogramVote vote = histogramVote(set.fromPx, set.pixelsPx, features.voteBinPx);
    // The tracked pose starts the first hypothesis near its answer (PnpSolver.h: same iteration, fewer steps).
    const Eigen::Matrix4d T_camera_world_guess = inverseRigid(T_world_expected);
    PnpResult pnp = solveDynamicR1Ppnp(set.pointsWorldMm, set.pixelsPx, set.candidates, geometry.leftIntrinsics(),
                                       tracking, vote.order, &T_camera_world_guess, kPnpHypothesesAtOnce);
    // Only the matches that sit where the pose puts them, as the tracker keeps them: points the scene moved between
    // the two frames (within H) would pull the bundle adjustment toward their motion.
    pnp = polishOnFittingMatches(set.pointsWorldMm, set.pixelsPx, set.candidates, geometry.leftIntrinsics(), pnp,
                                 tracking.dynamicResidualPx, minInliers);
    hypotheses = pnp.hypotheses;
    if (!pnp.success || static_cast<int>(pnp.inlierIndices.size()) < minInliers) return inliers;
    double degrees = 0, mm = 0;
    correction(inverseRigid(pnp.T_camera_world), T_world_expected, degrees, mm);
    if (degrees > parameters.maxCorrectionDeg || mm > parameters.maxCorrectionMm) return inliers;
    for (std::size_t i = 0; i < pnp.inlierIndices.size(); ++i) {
      const int m = pnp.inlierIndices[i], j = pnp.inlierMatch[i];
      if (j < 0) inliers.push_back({m, set.train[m], set.pixelsPx[m]});
      else inliers.push_back({m, set.candidateTrain[m][j], set.candidates[m][j].pixelPx});
    }
    return inliers;
  }

  /// Step 2 of matchKeyFrame: the observations of the key frame's features with depth (`lifted`, at liftedWorld and
  /// liftedPx) in the intermediate frames. Runs on `worker` beside step 1, with its own Hamming matcher.
  IntermediateMatches matchIntermediateFrames(const StereoFeatures& features, int frameIndex,
                                              const std::vector<int>& lifted, const Points3d& liftedWorld,
                                              const std::vector<cv::Point2f>& liftedPx) {
    const auto start = std::chrono::steady_clock::now();
    IntermediateMatches matched;
    std::vector<Observation>& observations = matched.observations;
    std::vector<int>& frameOfSlot = matched.frameOfSlot;
    if (lifted.empty()) return matched;
    const cv::Mat liftedDescriptors = descriptorRows(features.descriptors, lifted);
    std::vector<MatchSet> sets(intermediates.size());
    std::vector<std::vector<Inlier>> inlierSets(intermediates.size());
    std::vector<int> hypotheses(intermediates.size(), 0);
    // First near the projections at the tracked poses; each frame on its own thread.
    std::vector<uint8_t> guided(intermediates.size(), 0);
    if (parameters.guidedSearchRadiusPx > 0) {
      profiling::ScopedTimer timer("host: refinement, intermediate-frame matching (guided by the tracked poses)");
      parallelFor<CpuBackend>(
          static_cast<int64_t>(intermediates.size()),
          [&](int64_t f) {
            const IntermediateFrame& frame = intermediates[static_cast<std::size_t>(f)];
            const ProjectionGuidedMatches found =
                matchProjectedPoints(liftedWorld, liftedDescriptors, frame.features.keypoints, frame.features.descriptors,
                                     inverseRigid(frame.T_world_camera), geometry.leftIntrinsics(),
                                     guidedMatchParameters());
            if (!found.trusted || static_cast<int>(found.matches.size()) < parameters.minFrameInliers) return;
            // The tracked poses already agree with these matches: they are the observations (the paper takes them
            // from tracking), without a pose solve.
            MatchSet& set = sets[static_cast<std::size_t>(f)];
            set = toMatchSet(found, liftedWorld, liftedPx, frame.features);
            std::vector<Inlier>& inliers = inlierSets[static_cast<std::size_t>(f)];
            for (std::size_t i = 0; i < set.query.size(); ++i) inliers.push_back({static_cast<int>(i), set.train[i], set.pixelsPx[i]});
            guided[static_cast<std::size_t>(f)] = 1;
          },
          1);
    }
    // The other frames: all descriptors, then DynamicR1PPnP; matched and solved in parallel, merged in order (as
    // for the key frames above).
    std::vector<int> unguided;
    for (std::size_t f = 0; f < intermediates.size(); ++f) {
      if (guided[f]) ++matched.guidedFrames;
      else unguided.push_back(static_cast<int>(f));
    }
    std::vector<std::pair<cv::Mat, cv::Mat>> framePairs;
    for (int f : unguided) framePairs.emplace_back(liftedDescriptors, intermediates[static_cast<std::size_t>(f)].features.descriptors);
    const auto frameKnn = [&] {
      profiling::ScopedTimer timer("host: refinement, intermediate-frame matching (Hamming kNN)");
      return intermediateMatcher.matchPairs(framePairs, matchK());
    }();
    parallelFor<CpuBackend>(
        static_cast<int64_t>(unguided.size()),
        [&](int64_t u) {
          const std::size_t f = static_cast<std::size_t>(unguided[static_cast<std::size_t>(u)]);
          const IntermediateFrame& frame = intermediates[f];
          MatchSet& set = sets[f];
          std::vector<Inlier>& inliers = inlierSets[f];
          set = toMatchSet(frameKnn[static_cast<std::size_t>(u)], liftedWorld, liftedPx, frame.features);
          inliers = solveInliers(set, parameters.minFrameInliers, frame.T_world_camera, hypotheses[f]);
        },
        1);
    for (int h : hypotheses) matched.hypotheses += h;
    std::vector<cv::Mat> frameGreys;
    std::vector<int> frameIndices;
    for (const IntermediateFrame& frame : intermediates) {
      frameGreys.push_back(frame.features.grey);
      frameIndices.push_back(frame.frameIndex);
    }
    {
      profiling::ScopedTimer timer("host: refinement, intermediate-frame sub-pixel refinement");
      refineInliers(inlierSets, sets, features.grey, frameIndex, frameGreys, frameIndices);
    }
    // The guided observations that sit where the tracked poses put them (no solve checked them): as the tracker's
    // final fit, within a few times the frame's own median offset from the projections.
    for (std::size_t f = 0; f < intermediates.size(); ++f) {
      if (guided[f]) keepFitting(inlierSets[f], sets[f], inverseRigid(intermediates[f].T_world_camera));
    }
    for (std::size_t f = 0; f < intermediates.size(); ++f) {
      const MatchSet& set = sets[f];
      const std::vector<Inlier>& inliers = inlierSets[f];
      if (static_cast<int>(inliers.size()) < parameters.minFrameInliers) continue;
      const int slot = 1 + static_cast<int>(frameOfSlot.size());
      frameOfSlot.push_back(static_cast<int>(f));
      const std::vector<uint8_t>& moving = intermediates[f].features.moving;
      for (const Inlier& inlier : inliers) {
        if (!moving.empty() && moving[static_cast<std::size_t>(inlier.train)]) continue;  // moved with the scene
        observations.push_back({slot, lifted[set.query[inlier.match]], inlier.pixelPx.x(), inlier.pixelPx.y()});
      }
    }
    synchronize(device);  // nothing of this thread's left in flight for the caller's thread
    matched.milliseconds = millisecondsSince(start);
    return matched;
  }

  /// Stored key frames whose points fall into the view at T_world_camera, the most overlapping first, at most limit.
  std::vector<int> overlappingKeyFrames(const Eigen::Matrix4d& T_world_camera, int limit) const {
    const Eigen::Matrix4d T_camera_world = inverseRigid(T_world_camera);
    const Eigen::Matrix3d R = T_camera_world.block<3, 3>(0, 0);
    const Eigen::Vector3d t = T_camera_world.block<3, 1>(0, 3);
    // The view's four side planes through the camera centre (camera frame, unit normals pointing inwards): a point
    // at depth z > 0 projects inside the image exactly when it is on the inner side of all four.
    const double f = geometry.focalPx, width = geometry.imageSize.width, height = geometry.imageSize.height;
    const PinholeIntrinsics camera = geometry.leftIntrinsics();
    const std::array<Eigen::Vector3d, 4> insideNormals = {
        Eigen::Vector3d(f, 0, geometry.cxLeftPx).normalized(),           // u >= 0
        Eigen::Vector3d(-f, 0, width - geometry.cxLeftPx).normalized(),  // u < width
        Eigen::Vector3d(0, f, geometry.cyPx).normalized(),               // v >= 0
        Eigen::Vector3d(0, -f, height - geometry.cyPx).normalized()};    // v < height
    // Over a long scan most stored key frames are elsewhere: their bounding spheres skip the 200 projections each
    // (900 key frames took about 2 ms per key frame on the GPU machine's CPU).
    constexpr double kNoPoints = -1;  // not a candidate, even for minKeyFrameOverlap = 0
    std::vector<double> overlaps(keyFrames.size(), kNoPoints);
    parallelFor<CpuBackend>(static_cast<int64_t>(keyFrames.size()), [&](int64_t k) {
      const StoredKeyFrame& kf = keyFrames[static_cast<std::size_t>(k)];
      const std::vector<Eigen::Vector3f>& points = kf.pointsWorldMm;
      if (points.empty()) return;
      double& overlap = overlaps[static_cast<std::size_t>(k)];
      overlap = 0;
      const Eigen::Vector3d centre = R * kf.boundsCentreWorldMm + t;
      if (centre.z() + kf.boundsRadiusMm < kMinVisibleDepthMm) return;
      for (const Eigen::Vector3d& normal : insideNormals) {
        if (normal.dot(centre) < -kf.boundsRadiusMm) return;
      }
      const std::size_t step = std::max<std::size_t>(1, points.size() / kOverlapSamples);
      int seen = 0, tried = 0;
      for (std::size_t i = 0; i < points.size(); i += step, ++tried) {
        const Eigen::Vector3d c = R * points[i].cast<double>() + t;
        if (c.z() < kMinVisibleDepthMm) continue;
        double u, v;
        camera.project(c.x(), c.y(), c.z(), u, v);
        seen += u >= 0 && v >= 0 && u < geometry.imageSize.width && v < geometry.imageSize.height;
      }
      overlap = static_cast<double>(seen) / tried;
    }, 16);  // 16 key frames a task: a few microseconds each
    std::vector<std::pair<double, int>> ranked;
    for (std::size_t k = 0; k < keyFrames.size(); ++k) {
      if (overlaps[k] >= parameters.minKeyFrameOverlap) ranked.emplace_back(overlaps[k], static_cast<int>(k));
    }
    // Most overlap first; among equals the most recent.
    std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second > b.second;
    });
    std::vector<int> chosen;
    for (const auto& [overlap, k] : ranked) {
      if (static_cast<int>(chosen.size()) >= limit) break;
      chosen.push_back(k);
    }
    return chosen;
  }

  void store(int frameIndex, const StereoFeatures& f, const Eigen::Matrix4d& T_world_camera) {
    StoredKeyFrame kf;
    kf.frameIndex = frameIndex;
    kf.T_world_camera = T_world_camera;
    std::vector<int> rows;
    for (std::size_t i = 0; i < f.keypoints.size(); ++i) {
      if (f.pointsCameraMm[i].allFinite()) rows.push_back(static_cast<int>(i));
    }
    std::stable_sort(rows.begin(), rows.end(),
                     [&](int a, int b) { return f.keypoints[a].response > f.keypoints[b].response; });
    if (static_cast<int>(rows.size()) > parameters.storedFeaturesPerKeyFrame) rows.resize(parameters.storedFeaturesPerKeyFrame);
    const Eigen::Matrix3d R = T_world_camera.block<3, 3>(0, 0);
    const Eigen::Vector3d t = T_world_camera.block<3, 1>(0, 3);
    kf.descriptors = descriptorRows(f.descriptors, rows);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      kf.pixelsPx.push_back(f.keypoints[rows[r]].pt);
      kf.pointsWorldMm.push_back((R * f.pointsCameraMm[rows[r]] + t).cast<float>());
    }
    if (!kf.pointsWorldMm.empty()) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3f& point : kf.pointsWorldMm) sum += point.cast<double>();
      kf.boundsCentreWorldMm = sum / static_cast<double>(kf.pointsWorldMm.size());
      for (const Eigen::Vector3f& point : kf.pointsWorldMm) {
        kf.boundsRadiusMm = std::max(kf.boundsRadiusMm, (point.cast<double>() - kf.boundsCentreWorldMm).norm());
      }
      kf.boundsRadiusMm *= 1 + 1e-9;  // the points lie inside despite rounding
    }
    keyFrames.push_back(std::move(kf));
    while (static_cast<int>(keyFrames.size()) > parameters.maxStoredKeyFrames) keyFrames.pop_front();
  }
};

KeyFrameRefiner::KeyFrameRefiner(const RectifiedGeometry& geometry, const RefinementParameters& parameters,
                                 const TrackingParameters& tracking, const FeatureParameters& features, Device device,
                                 std::shared_ptr<SubPixelMatcher> subPixelMatcher) {
  parameters.validate();
  tracking.validate();
  features.validate();
  require(geometry.focalPx > 0 && geometry.imageSize.width > 0 && geometry.imageSize.height > 0,
          "refinement: the rectified geometry has no focal length or image size");
  requireUsableDevice(device, "CUDA key-frame refinement");
  require(!subPixelMatcher || subPixelMatcher->device() == device,
          "refinement: the shared sub-pixel matcher runs on another device than the refinement");
  impl_ = std::make_unique<Impl>(geometry, parameters, tracking, features, device, std::move(subPixelMatcher));
}

KeyFrameRefiner::~KeyFrameRefiner() = default;

void KeyFrameRefiner::addIntermediateFrame(int frameIndex, const StereoFeatures& features,
                                           const Eigen::Matrix4d& T_world_camera) {
  require(isRigidTransform(T_world_camera), "refinement: the intermediate frame's pose is not a rigid transform");
  require(features.pointsCameraMm.size() == features.keypoints.size() &&
              features.descriptors.rows == static_cast<int>(features.keypoints.size()),
          "refinement: the intermediate frame's features are inconsistent");
  Impl& s = *impl_;
  const int limit = s.parameters.maxIntermediateFrames;
  if (limit == 0) return;
  IntermediateFrame frame;
  frame.frameIndex = frameIndex;
  frame.features = features;
  frame.T_world_camera = T_world_camera;
  s.intermediates.push_back(std::move(frame));
  ++s.state;
  // Thin evenly: drop the frame whose neighbours are closest (never the newest, which is nearest the key frame).
  while (static_cast<int>(s.intermediates.size()) > limit) {
    std::size_t drop = 0;
    int bestGap = std::numeric_limits<int>::max();
    for (std::size_t i = 1; i + 1 < s.intermediates.size(); ++i) {
      const int gap = s.intermediates[i + 1].frameIndex - s.intermediates[i - 1].frameIndex;
      if (gap < bestGap) {
        bestGap = gap;
        drop = i;
      }
    }
    s.intermediates.erase(s.intermediates.begin() + static_cast<std::ptrdiff_t>(drop));
  }
}

KeyFrameMatches KeyFrameRefiner::matchKeyFrame(int frameIndex, const StereoFeatures& features,
                                               const Eigen::Matrix4d& T_world_camera) {
  const auto start = std::chrono::steady_clock::now();
  require(isRigidTransform(T_world_camera), "refinement: the key frame's pose is not a rigid transform");
  require(features.pointsCameraMm.size() == features.keypoints.size() &&
              features.descriptors.rows == static_cast<int>(features.keypoints.size()),
          "refinement: the key frame's features are inconsistent");
  Impl& s = *impl_;
  const RefinementParameters& p = s.parameters;
  KeyFrameMatches matches;
  matches.data_ = std::make_unique<KeyFrameMatches::Data>();
  KeyFrameMatches::Data& m = *matches.data_;
  m.frameIndex = frameIndex;
  m.features = &features;
  m.T_world_camera = T_world_camera;
  m.start = start;
  m.refinerState = s.state;
  RefinementResult& result = m.result;
  result.T_world_camera = T_world_camera;

  // Tracks: one per key-frame feature. Free ones start at the stereo point lifted with the tracked pose.
  const int n = static_cast<int>(features.keypoints.size());
  const Eigen::Matrix3d R_wc = T_world_camera.block<3, 3>(0, 0);
  const Eigen::Vector3d t_wc = T_world_camera.block<3, 1>(0, 3);
  std::vector<int> lifted;  // features with depth
  Points3d liftedWorld;
  std::vector<cv::Point2f> liftedPx;
  for (int i = 0; i < n; ++i) {
    if (!features.pointsCameraMm[i].allFinite()) continue;
    lifted.push_back(i);
    liftedWorld.push_back(R_wc * features.pointsCameraMm[i] + t_wc);
    liftedPx.push_back(features.keypoints[i].pt);
  }
  auto& trackWorld = m.trackWorld;
  trackWorld.assign(n, Eigen::Vector3d::Constant(NAN));
  std::vector<uint8_t>& fixed = m.fixed;
  fixed.assign(n, 0);
  for (std::size_t k = 0; k < lifted.size(); ++k) trackWorld[lifted[k]] = liftedWorld[k];

  // 2. (beside 1) The intermediate frames: observations of the key frame's features with depth. Independent of the
  // key-frame matches, so they are matched on the refiner's worker meanwhile.
  PendingResult<IntermediateMatches> intermediateTask = s.worker.run(
      [&] { return s.matchIntermediateFrames(features, frameIndex, lifted, liftedWorld, liftedPx); });

  // 1. Earlier key frames that overlap: their matched points are fixed. The frames are matched and solved in
  // parallel (independent), then merged in order: the same result as one after the other.
  const auto partStart = std::chrono::steady_clock::now();
  const std::vector<int> overlapping = [&] {
    profiling::ScopedTimer timer("host: refinement, key-frame overlap test");
    return s.overlappingKeyFrames(T_world_camera, p.maxMatchedKeyFrames);
  }();
  struct KeyFrameMatch {
    Points3d world;
    MatchSet set;
    std::vector<Inlier> inliers;
    int hypotheses = 0;
  };
  std::vector<KeyFrameMatch> keyFrameMatches(overlapping.size());
  const Eigen::Matrix4d T_camera_world = inverseRigid(T_world_camera);
  // Near the projections of the stored points at the tracked pose first: when tracking has not drifted from that
  // key frame, DynamicR1PPnP then checks a set that is nearly all inliers and stops at its first hypotheses.
  std::vector<uint8_t> keyFrameGuided(overlapping.size(), 0);
  ProjectionGuidedMatchParameters keyFrameGuide = s.guidedMatchParameters();
  keyFrameGuide.minConsistentShare = kKeyFrameGuidedMinConsistentShare;
  std::optional<profiling::ScopedTimer> guidedTimer(std::in_place,
                                                    "host: refinement, key-frame matching (guided by the tracked pose)");
  parallelFor<CpuBackend>(
      static_cast<int64_t>(overlapping.size()),
      [&](int64_t c) {
        const StoredKeyFrame& kf = s.keyFrames[static_cast<std::size_t>(overlapping[static_cast<std::size_t>(c)])];
        KeyFrameMatch& match = keyFrameMatches[static_cast<std::size_t>(c)];
        for (const Eigen::Vector3f& point : kf.pointsWorldMm) match.world.push_back(point.cast<double>());
        if (p.guidedSearchRadiusPx <= 0) return;
        const ProjectionGuidedMatches found = matchProjectedPoints(
            match.world, kf.descriptors, features.keypoints, features.descriptors, T_camera_world,
            s.geometry.leftIntrinsics(), keyFrameGuide);
        if (!found.trusted || static_cast<int>(found.matches.size()) < p.minKeyFrameInliers) return;
        match.set = s.toMatchSet(found, match.world, kf.pixelsPx, features);
        keyFrameGuided[static_cast<std::size_t>(c)] = 1;
      },
      1);
  guidedTimer.reset();
  // The others (tracking drifted, e.g. at a return after a long way): all descriptors.
  std::vector<int> keyFramesUnguided;
  std::vector<std::pair<cv::Mat, cv::Mat>> keyFramePairs;
  for (std::size_t c = 0; c < overlapping.size(); ++c) {
    if (keyFrameGuided[c]) {
      ++result.guidedKeyFrames;
      continue;
    }
    keyFramesUnguided.push_back(static_cast<int>(c));
    keyFramePairs.emplace_back(s.keyFrames[static_cast<std::size_t>(overlapping[c])].descriptors, features.descriptors);
  }
  const auto keyFrameKnn = [&] {
    profiling::ScopedTimer timer("host: refinement, key-frame matching (Hamming kNN)");
    return s.matcher.matchPairs(keyFramePairs, s.matchK());
  }();
  for (std::size_t u = 0; u < keyFramesUnguided.size(); ++u) {
    const std::size_t c = static_cast<std::size_t>(keyFramesUnguided[u]);
    const StoredKeyFrame& kf = s.keyFrames[static_cast<std::size_t>(overlapping[c])];
    keyFrameMatches[c].set = s.toMatchSet(keyFrameKnn[u], keyFrameMatches[c].world, kf.pixelsPx, features);
  }
  parallelFor<CpuBackend>(
      static_cast<int64_t>(overlapping.size()),
      [&](int64_t c) {
        KeyFrameMatch& match = keyFrameMatches[static_cast<std::size_t>(c)];
        match.inliers = s.solveInliers(match.set, p.minKeyFrameInliers, T_world_camera, match.hypotheses);
        s.dropMovedPoints(match.inliers, match.set, features, T_camera_world);
        if (static_cast<int>(match.inliers.size()) < p.minKeyFrameInliers) match.inliers.clear();
      },
      1);
  for (const KeyFrameMatch& m : keyFrameMatches) {
    result.pnpHypotheses += m.hypotheses;
    if (m.inliers.empty()) continue;
    ++result.matchedKeyFrames;
    for (const Inlier& inlier : m.inliers) {
      if (fixed[inlier.train]) continue;
      fixed[inlier.train] = 1;
      trackWorld[inlier.train] = m.world[m.set.query[inlier.match]];
    }
  }

  result.keyFrameMatchingMs = millisecondsSince(partStart);

  // 2. The intermediate frames, matched beside step 1; kept only when an earlier key frame anchors the solve.
  IntermediateMatches intermediate = [&] {
    profiling::ScopedTimer timer("host: refinement, wait for the intermediate frames");
    return intermediateTask.get();
  }();
  if (result.matchedKeyFrames > 0) {
    m.observations = std::move(intermediate.observations);
    m.frameOfSlot = std::move(intermediate.frameOfSlot);
    result.guidedFrames = intermediate.guidedFrames;
    result.pnpHypotheses += intermediate.hypotheses;
  }
  result.intermediateMatchingMs = intermediate.milliseconds;
  return matches;
}

RefinementResult KeyFrameRefiner::refineKeyFrame(int frameIndex, const StereoFeatures& features,
                                                 const Eigen::Matrix4d& T_world_camera,
                                                 const SurfaceMeasurement& measurement,
                                                 const std::vector<Eigen::Vector3f>& modelPointsWorldMm,
                                                 const std::vector<Eigen::Vector3f>& /*modelNormalsWorld: not used*/) {
  return refineMatchedKeyFrame(matchKeyFrame(frameIndex, features, T_world_camera), measurement,
                               selectIcpModelPoints(measurement, modelPointsWorldMm, T_world_camera));
}

IcpModelPoints KeyFrameRefiner::selectIcpModelPoints(const SurfaceMeasurement& measurement,
                                                     const std::vector<Eigen::Vector3f>& modelPointsWorldMm,
                                                     const Eigen::Matrix4d& T_world_camera) const {
  const Impl& s = *impl_;
  const RefinementParameters& p = s.parameters;
  IcpModelPoints icp;
  icp.T_world_camera = T_world_camera;
  if (modelPointsWorldMm.empty() || measurement.empty()) return icp;
  require(measurement.onDevice || usableHostMaps(measurement.pointsCameraMm, measurement.normalsCamera),
          "refinement: the measurement needs CV_32FC3 points and normals of one size");
  // Which pixels have q and n: the mask comes with the measurement, so the maps themselves may stay on the device.
  const cv::Mat valid = measurement.validPixelMask();
  const Eigen::Matrix4d T_camera_world = inverseRigid(T_world_camera);
  const Eigen::Matrix3f R = T_camera_world.block<3, 3>(0, 0).cast<float>();
  const Eigen::Vector3f t = T_camera_world.block<3, 1>(0, 3).cast<float>();
  const PinholeIntrinsics camera = s.geometry.leftIntrinsics();
  // Flagged in parallel (a model sample has 10^4 points), kept in order.
  std::vector<uint8_t> lands(modelPointsWorldMm.size(), 0);
  parallelFor<CpuBackend>(static_cast<int64_t>(modelPointsWorldMm.size()), [&](int64_t i) {
    const Eigen::Vector3f c = R * modelPointsWorldMm[static_cast<std::size_t>(i)] + t;
    if (!(c.z() >= kMinVisibleDepthMm)) return;
    double u, v;
    camera.project(c.x(), c.y(), c.z(), u, v);
    const int x = static_cast<int>(std::floor(u + 0.5)), y = static_cast<int>(std::floor(v + 0.5));
    if (x < 0 || y < 0 || x >= valid.cols || y >= valid.rows) return;
    lands[static_cast<std::size_t>(i)] = valid.at<uint8_t>(y, x) ? 1 : 0;
  });
  std::vector<int> usable;
  for (std::size_t i = 0; i < lands.size(); ++i) {
    if (lands[i]) usable.push_back(static_cast<int>(i));
  }
  const std::size_t samples = std::min<std::size_t>(usable.size(), static_cast<std::size_t>(p.icpSamples));
  if (static_cast<int>(samples) < p.minIcpPoints) return icp;
  icp.pointsWorldMm.reserve(samples);
  for (std::size_t k = 0; k < samples; ++k) icp.pointsWorldMm.push_back(modelPointsWorldMm[usable[k * usable.size() / samples]]);
  return icp;
}

RefinementResult KeyFrameRefiner::refineMatchedKeyFrame(KeyFrameMatches matches, const SurfaceMeasurement& measurement,
                                                        const IcpModelPoints& icp) {
  require(matches.data_ != nullptr, "refinement: no key-frame matches to refine (call matchKeyFrame first)");
  Impl& s = *impl_;
  KeyFrameMatches::Data& m = *matches.data_;
  require(m.refinerState == s.state,
          "refinement: the key frames or intermediate frames changed between matchKeyFrame and refineMatchedKeyFrame");
  require(icp.T_world_camera == m.T_world_camera,
          "refinement: the ICP points were selected at another pose than the key frame was matched at");
  const RefinementParameters& p = s.parameters;
  const StereoFeatures& features = *m.features;
  const int frameIndex = m.frameIndex;
  const Eigen::Matrix4d T_world_camera = m.T_world_camera;
  const int n = static_cast<int>(features.keypoints.size());
  const auto& trackWorld = m.trackWorld;
  const std::vector<uint8_t>& fixed = m.fixed;
  const std::vector<Observation>& observations = m.observations;
  const std::vector<int>& frameOfSlot = m.frameOfSlot;
  RefinementResult& result = m.result;
  const auto finish = [&](const std::string& message) {
    profiling::ScopedTimer timer("host: refinement, key frame stored");
    result.message = message;
    s.store(frameIndex, features, result.T_world_camera);
    s.intermediates.clear();
    ++s.state;
    result.milliseconds = millisecondsSince(m.start);
    return result;
  };

  // The bundle adjustment's points: fixed tracks (seen by an earlier key frame) and free tracks seen again.
  std::optional<profiling::ScopedTimer> problemTimer(std::in_place, "host: refinement, problem set-up");
  std::vector<int> seenElsewhere(n, 0);
  for (const Observation& o : observations) ++seenElsewhere[o.point];
  refinement::RefinementProblem problem;
  std::vector<int> pointOf(n, -1);
  if (result.matchedKeyFrames > 0) {
    for (int i = 0; i < n; ++i) {
      if (!fixed[i] && seenElsewhere[i] == 0) continue;
      pointOf[i] = static_cast<int>(problem.pointFixed.size());
      problem.pointFixed.push_back(fixed[i]);
      for (int c = 0; c < 3; ++c) problem.pointsWorldMm.push_back(trackWorld[i](c));
      const cv::Point2f& px = features.keypoints[i].pt;
      problem.observations.push_back({0, pointOf[i], px.x, px.y});
      result.fixedPoints += fixed[i];
      result.freePoints += !fixed[i];
    }
    for (Observation o : observations) {
      o.point = pointOf[o.point];
      problem.observations.push_back(o);
    }
  }
  result.baObservations = static_cast<int>(problem.observations.size());

  // The ICP term: the model points chosen beside the matching (selectIcpModelPoints).
  const Eigen::Matrix4d T_camera_world = inverseRigid(T_world_camera);
  if (!icp.pointsWorldMm.empty()) {
    require(!measurement.empty(), "refinement: ICP points without a measurement");
    problem.modelPointsWorldMm.reserve(icp.pointsWorldMm.size());
    for (const Eigen::Vector3f& point : icp.pointsWorldMm) problem.modelPointsWorldMm.push_back({point.x(), point.y(), point.z()});
    problem.measuredPointsCameraMm = measurement.pointsCameraMm;
    problem.measuredNormalsCamera = measurement.normalsCamera;
    problem.measuredOnDevice = measurement.onDevice;
  }
  result.icpPoints = static_cast<int>(problem.modelPointsWorldMm.size());

  if (result.baObservations == 0 && result.icpPoints == 0) {
    if (s.keyFrames.empty() && s.intermediates.empty()) return finish("first key frame: stored for later matching");
    return finish(result.matchedKeyFrames == 0
                      ? "not refined: no earlier key frame matched and no model points for the ICP term"
                      : "not refined: no feature point to adjust");
  }

  result.intermediateFrames = static_cast<int>(frameOfSlot.size());
  result.beta = result.baObservations > 0 && result.icpPoints > 0
                    ? p.icpWeightFactor * result.baObservations / result.icpPoints
                    : 1.0;
  problem.camera = {s.geometry.leftIntrinsics(), s.geometry.imageSize.width, s.geometry.imageSize.height};
  problem.robust = {p.baHuberPx, p.icpTukeyMm, result.beta, kMinVisibleDepthMm};
  problem.poses.push_back(toPose(T_camera_world));
  for (int f : frameOfSlot) problem.poses.push_back(toPose(inverseRigid(s.intermediates[f].T_world_camera)));

  problemTimer.reset();
  const auto partStart = std::chrono::steady_clock::now();
  const refinement::RefinementSolution solution = [&] {
    profiling::ScopedTimer timer("host: refinement, LM solve");
    return refinement::solveRefinement(problem, p, s.device);
  }();
  result.solveMs = millisecondsSince(partStart);
  result.initialCost = solution.initialCost;
  result.finalCost = solution.finalCost;
  result.iterations = solution.iterations;
  const Eigen::Matrix4d refined = inverseRigid(fromPose(solution.poses[0]));
  double degrees = 0, mm = 0;
  correction(refined, T_world_camera, degrees, mm);
  const std::string what = result.baObservations == 0 ? "ICP only (no earlier key frame matched)"
                                                      : (result.icpPoints == 0 ? "BA only" : "BA + ICP");
  if (!(solution.finalCost < solution.initialCost) || !refined.allFinite()) {
    return finish("not refined (" + what + "): the cost did not fall");
  }
  if (degrees > p.maxCorrectionDeg || mm > p.maxCorrectionMm) {
    return finish(cv::format("not refined (%s): implausible correction of %.2f mm, %.2f deg", what.c_str(), mm, degrees));
  }
  result.refined = true;
  result.T_world_camera = refined;
  for (std::size_t slot = 0; slot < frameOfSlot.size(); ++slot) {
    FramePose pose;
    pose.frameIndex = s.intermediates[frameOfSlot[slot]].frameIndex;
    pose.T_world_camera = inverseRigid(fromPose(solution.poses[slot + 1]));
    result.intermediatePoses.push_back(pose);
  }
  return finish(cv::format("refined (%s): %.2f mm, %.3f deg from the tracked pose", what.c_str(), mm, degrees));
}

int KeyFrameRefiner::keyFrameCount() const { return static_cast<int>(impl_->keyFrames.size()); }
StoredKeyFrameView KeyFrameRefiner::storedKeyFrame(int i) const {
  require(i >= 0 && i < keyFrameCount(), "refinement: no stored key frame " + std::to_string(i));
  const StoredKeyFrame& kf = impl_->keyFrames[static_cast<std::size_t>(i)];
  StoredKeyFrameView view;
  view.frameIndex = kf.frameIndex;
  view.T_world_camera = kf.T_world_camera;
  view.pixelsPx = &kf.pixelsPx;
  view.descriptors = &kf.descriptors;
  view.pointsWorldMm = &kf.pointsWorldMm;
  return view;
}

std::vector<int> KeyFrameRefiner::keyFramesInView(const Eigen::Matrix4d& T_world_camera) const {
  require(isRigidTransform(T_world_camera), "refinement: the view's pose is not a rigid transform");
  return impl_->overlappingKeyFrames(T_world_camera, keyFrameCount());
}

void KeyFrameRefiner::clearIntermediateFrames() {
  if (impl_->intermediates.empty()) return;
  impl_->intermediates.clear();
  ++impl_->state;
}

int KeyFrameRefiner::intermediateFrameCount() const { return static_cast<int>(impl_->intermediates.size()); }

std::size_t KeyFrameRefiner::storedBytes() const {
  std::size_t bytes = 0;
  for (const StoredKeyFrame& kf : impl_->keyFrames) bytes += kf.bytes();
  return bytes;
}

void KeyFrameRefiner::reset() {
  ++impl_->state;
  impl_->keyFrames.clear();
  impl_->intermediates.clear();
  impl_->subPixel->forgetImages();
}

Device KeyFrameRefiner::device() const { return impl_->device; }
const RefinementParameters& KeyFrameRefiner::parameters() const { return impl_->parameters; }

}  // namespace tissuemosaic
