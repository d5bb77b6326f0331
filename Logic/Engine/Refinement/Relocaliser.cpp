#include "Refinement/Relocaliser.h"

#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "Core/RigidTransform.h"
#include "Refinement/KeyFrameRefiner.h"
#include "Tracking/HistogramVoting.h"
#include "Tracking/OrbFeatures.h"
#include "Tracking/PnpSolver.h"

#include <algorithm>

namespace tissuemosaic {

namespace {
/// Hypotheses per solve: a relocalisation set has many outliers and no reliable guess, but a lost frame must not
/// take long either (the paper's 1-point RANSAC bound stops far earlier on a frame that does match).
constexpr int kMaxHypotheses = 200;
constexpr int kHypothesesAtOnce = 8;
}  // namespace

struct Relocaliser::Impl {
  RectifiedGeometry geometry;
  TrackingParameters tracking;
  FeatureParameters features;
  HammingMatcher matcher;
  int cursor = 0;  ///< the round over all stored key frames: how far it got (counted from the newest)

  Impl(const RectifiedGeometry& g, const TrackingParameters& t, const FeatureParameters& f, Device d)
      : geometry(g), tracking(t), features(f), matcher(d) {
    tracking.maxRansacIterations = std::min(tracking.maxRansacIterations, kMaxHypotheses);
    tracking.minInliers = tracking.relocalisationMinInliers;
  }
};

Relocaliser::Relocaliser(const RectifiedGeometry& geometry, const TrackingParameters& tracking,
                         const FeatureParameters& features, Device device) {
  tracking.validate();
  features.validate();
  require(geometry.focalPx > 0 && geometry.imageSize.width > 0, "relocaliser: the geometry has no focal length");
  requireUsableDevice(device, "CUDA relocalisation");
  impl_ = std::make_unique<Impl>(geometry, tracking, features, device);
}

Relocaliser::~Relocaliser() = default;

RelocalisationResult Relocaliser::relocalise(const StereoFeatures& features, const KeyFrameRefiner& refiner,
                                             const Eigen::Matrix4d& T_world_lastTracked) {
  Impl& s = *impl_;
  RelocalisationResult result;
  const int stored = refiner.keyFrameCount();
  const int wanted = std::min(s.tracking.relocalisationCandidates, stored);
  if (wanted == 0) {
    result.message = "no stored key frame to relocalise against";
    return result;
  }
  if (static_cast<int>(features.keypoints.size()) < s.tracking.relocalisationMinInliers) {
    result.message = "too few features to relocalise (" + std::to_string(features.keypoints.size()) + ")";
    return result;
  }
  // Those in view from where the camera was last, then the round over all of them.
  std::vector<int> chosen;
  for (int k : refiner.keyFramesInView(T_world_lastTracked)) {
    if (static_cast<int>(chosen.size()) >= (wanted + 1) / 2) break;
    chosen.push_back(k);
  }
  for (int tried = 0; tried < stored && static_cast<int>(chosen.size()) < wanted; ++tried) {
    const int k = stored - 1 - (s.cursor++ % stored);
    if (std::find(chosen.begin(), chosen.end(), k) == chosen.end()) chosen.push_back(k);
  }
  std::vector<std::pair<cv::Mat, cv::Mat>> pairs;
  for (int k : chosen) pairs.emplace_back(*refiner.storedKeyFrame(k).descriptors, features.descriptors);
  const auto knn = s.matcher.matchPairs(pairs, std::min(8, 1 + s.features.candidatesPerFeature));

  struct Solved {
    PnpResult pnp;
    int frameIndex = -1;
    Points3d points;  ///< the matched key-frame points (world) and this frame's pixels, for the joint polish
    Pixels2d pixels;
    std::vector<std::vector<CandidateMatch>> candidates;
  };
  std::vector<Solved> solved(chosen.size());
  const Eigen::Matrix4d T_camera_world_guess = inverseRigid(T_world_lastTracked);
  const PinholeIntrinsics intrinsics = s.geometry.leftIntrinsics();
  parallelFor<CpuBackend>(
      static_cast<int64_t>(chosen.size()),
      [&](int64_t c) {
        const StoredKeyFrameView kf = refiner.storedKeyFrame(chosen[static_cast<std::size_t>(c)]);
        Points3d points;
        Pixels2d pixels, fromPx;
        std::vector<std::vector<CandidateMatch>> candidates;
        for (const std::vector<cv::DMatch>& list : knn[static_cast<std::size_t>(c)]) {
          if (list.empty() || list[0].distance > s.features.maxHammingDistance) continue;
          points.push_back((*kf.pointsWorldMm)[static_cast<std::size_t>(list[0].queryIdx)].cast<double>());
          const cv::Point2f& from = (*kf.pixelsPx)[static_cast<std::size_t>(list[0].queryIdx)];
          const cv::Point2f& to = features.keypoints[static_cast<std::size_t>(list[0].trainIdx)].pt;
          fromPx.emplace_back(from.x, from.y);
          pixels.emplace_back(to.x, to.y);
          std::vector<CandidateMatch> further;
          for (std::size_t j = 1; j < list.size() && list[j].distance <= s.features.maxHammingDistance; ++j) {
            const cv::Point2f& p = features.keypoints[static_cast<std::size_t>(list[j].trainIdx)].pt;
            CandidateMatch candidate;
            candidate.pixelPx = Eigen::Vector2d(p.x, p.y);
            further.push_back(candidate);
          }
          candidates.push_back(std::move(further));
        }
        Solved& out = solved[static_cast<std::size_t>(c)];
        out.frameIndex = kf.frameIndex;
        if (static_cast<int>(points.size()) < s.tracking.relocalisationMinInliers) return;
        const HistogramVote vote = histogramVote(fromPx, pixels, s.features.voteBinPx);
        out.pnp = solveDynamicR1Ppnp(points, pixels, candidates, intrinsics, s.tracking, vote.order,
                                     &T_camera_world_guess, kHypothesesAtOnce);
        out.points = std::move(points);
        out.pixels = std::move(pixels);
        out.candidates = std::move(candidates);
      },
      1);
  result.keyFramesTried = static_cast<int>(chosen.size());
  const Solved* best = nullptr;
  for (const Solved& candidate : solved) {
    const int inliers = candidate.pnp.success ? static_cast<int>(candidate.pnp.inlierIndices.size()) : 0;
    if (inliers < s.tracking.relocalisationMinInliers || inliers <= result.inliers) continue;
    best = &candidate;
    result.success = true;
    result.inliers = inliers;
    result.keyFrame = candidate.frameIndex;
    result.T_world_camera = inverseRigid(candidate.pnp.T_camera_world);
  }
  if (best) {
    // One key frame's inliers fix the pose only roughly (a few dozen after the camera was out): the best pose is
    // polished on the matches of every key frame tried that sit where it projects them, within the tracker's
    // final-fit bound. At 480x270 this halves the relocalised pose's error (RobustTracking tests).
    Points3d points;
    Pixels2d pixels;
    std::vector<std::vector<CandidateMatch>> candidates;
    for (const Solved& set : solved) {
      points.insert(points.end(), set.points.begin(), set.points.end());
      pixels.insert(pixels.end(), set.pixels.begin(), set.pixels.end());
      candidates.insert(candidates.end(), set.candidates.begin(), set.candidates.end());
    }
    const double boundPx = s.tracking.dynamicResidualPx > 0 ? s.tracking.dynamicResidualPx : s.tracking.inlierThresholdPx;
    const PnpResult joint = polishPnpPose(points, pixels, candidates, intrinsics, best->pnp.T_camera_world, boundPx,
                                          s.tracking.relocalisationMinInliers);
    if (joint.success && static_cast<int>(joint.inlierIndices.size()) >= result.inliers) {
      result.inliers = static_cast<int>(joint.inlierIndices.size());
      result.T_world_camera = inverseRigid(joint.T_camera_world);
    }
  }
  if (!result.success) {
    result.message = "no stored key frame matched with " + std::to_string(s.tracking.relocalisationMinInliers) +
                     " inliers (" + std::to_string(result.keyFramesTried) + " tried)";
  }
  return result;
}

}  // namespace tissuemosaic
