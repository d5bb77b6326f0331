#include "Tracking/FrameTracker.h"

#include "Core/Error.h"
#include "Core/RigidTransform.h"
#include "Core/Stopwatch.h"
#include "Tracking/HistogramVoting.h"
#include "Tracking/KeyFrameDecision.h"
#include "Tracking/OrbFeatures.h"
#include "Tracking/PnpSolver.h"
#include "Tracking/SubPixelMatch.h"

#include <Eigen/Geometry>
#include <opencv2/features2d.hpp>

#include <chrono>
#include <cmath>

namespace tissuemosaic {

namespace {

/// The frame new frames are matched against: its features with depth, their world points, and its pose.
struct Reference {
  int frameIndex = -1;
  std::vector<cv::Point2f> pixelsPx;
  cv::Mat descriptors;
  cv::Mat grey;
  Points3d pointsWorldMm;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
};

}  // namespace

void FrameTrackerOptions::validate() const {
  tracking.validate();
  features.validate();
  require(maxStepMm > 0 && std::isfinite(maxStepMm), "tracker: maxStepMm must be a positive number of mm");
  require(maxStepDeg > 0 && maxStepDeg <= 180, "tracker: maxStepDeg must be in (0, 180]");
}

struct FrameTracker::Impl {
  RectifiedGeometry geometry;
  FrameTrackerOptions options;
  Eigen::Matrix4d T_world_start;
  cv::Ptr<cv::ORB> orb;
  cv::BFMatcher matcher{cv::NORM_HAMMING, false};
  std::unique_ptr<OrbExtractor> ownExtractor;  ///< FeatureExtractor::TissueMosaicOrb
  std::unique_ptr<HammingMatcher> ownMatcher;
  std::shared_ptr<SubPixelMatcher> subPixel;

  StereoFeatures detect(const cv::Mat& leftRectified) {
    if (!ownExtractor) return detectFeatures(*orb, leftRectified);
    const double scaleFactor = options.features.scaleFactor;
    return detectFeatures(
        [&](const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
          const OrbFeatures found = ownExtractor->extract(grey);
          keypoints = toCvKeyPoints(found, scaleFactor);
          descriptors = found.descriptors;
        },
        leftRectified);
  }

  std::vector<std::vector<cv::DMatch>> match(const cv::Mat& from, const cv::Mat& to, int k) {
    std::vector<std::vector<cv::DMatch>> knn;
    if (ownMatcher) knn = ownMatcher->match(from, to, k);
    else matcher.knnMatch(from, to, knn, k);
    return knn;
  }
  int frames = 0;
  StereoFeatures lastFeatures;     ///< of the last track() call
  bool lastTracked = false;
  Reference reference;
  int lastKeyFrameIndex = -1;
  Eigen::Matrix4d T_world_lastKeyFrame = Eigen::Matrix4d::Identity();

  /// The reference before the current one (for the constant-velocity prediction); index -1: none.
  int previousReferenceIndex = -1;
  Eigen::Matrix4d T_world_previousReference = Eigen::Matrix4d::Identity();

  /// The pose predicted for frame `frameIndex`: the reference's pose moved on by the motion from the previous
  /// reference when both steps are one frame (constant velocity), else the reference's pose.
  Eigen::Matrix4d predictedPose(int frameIndex) const {
    if (previousReferenceIndex >= 0 && reference.frameIndex - previousReferenceIndex == 1 &&
        frameIndex - reference.frameIndex == 1) {
      return reference.T_world_camera * (inverseRigid(T_world_previousReference) * reference.T_world_camera);
    }
    return reference.T_world_camera;
  }

  void setReference(const StereoFeatures& features, const Eigen::Matrix4d& T_world_camera, int frameIndex) {
    if (reference.frameIndex >= 0 && reference.frameIndex != frameIndex) {
      previousReferenceIndex = reference.frameIndex;
      T_world_previousReference = reference.T_world_camera;
    }
    reference = Reference();
    reference.frameIndex = frameIndex;
    reference.T_world_camera = T_world_camera;
    reference.grey = features.grey;
    const Eigen::Matrix3d R = T_world_camera.block<3, 3>(0, 0);
    const Eigen::Vector3d t = T_world_camera.block<3, 1>(0, 3);
    std::vector<int> rows;
    for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
      if (!features.pointsCameraMm[i].allFinite()) continue;
      rows.push_back(static_cast<int>(i));
      reference.pixelsPx.push_back(features.keypoints[i].pt);
      reference.pointsWorldMm.push_back(R * features.pointsCameraMm[i] + t);
    }
    reference.descriptors = descriptorRows(features.descriptors, rows);
  }
};

FrameTracker::FrameTracker(const RectifiedGeometry& geometry, const FrameTrackerOptions& options,
                           const Eigen::Matrix4d& T_world_startCamera)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  require(geometry.focalPx > 0 && geometry.baselineMm > 0, "tracker: the rectified geometry has no focal length or baseline");
  require(isRigidTransform(T_world_startCamera), "tracker: the start pose is not a rigid transform");
  impl_->geometry = geometry;
  impl_->options = options;
  if (options.subPixelMatcher) {
    require(options.subPixelMatcher->device() == options.featureDevice,
            "tracker: the shared sub-pixel matcher runs on another device than the features");
    impl_->subPixel = options.subPixelMatcher;
  } else {
    impl_->subPixel = std::make_shared<SubPixelMatcher>(options.featureDevice, options.features.maxRefinementShiftPx);
  }
  impl_->T_world_start = T_world_startCamera;
  const FeatureParameters& f = options.features;
  if (options.extractor == FeatureExtractor::TissueMosaicOrb) {
    OrbParameters orbParameters;
    orbParameters.maxFeatures = f.maxFeatures;
    orbParameters.levels = f.levels;
    orbParameters.scaleFactor = f.scaleFactor;
    orbParameters.fastThreshold = f.fastThreshold;
    orbParameters.edgeThresholdPx = f.edgeThresholdPx;
    impl_->ownExtractor = std::make_unique<OrbExtractor>(options.featureDevice, orbParameters);
    impl_->ownMatcher = std::make_unique<HammingMatcher>(options.featureDevice);
  } else {
    require(options.featureDevice == Device::Cpu, "tracker: OpenCV's ORB runs on the CPU only");
    impl_->orb = cv::ORB::create(f.maxFeatures, static_cast<float>(f.scaleFactor), f.levels, f.edgeThresholdPx, 0, 2,
                                 cv::ORB::HARRIS_SCORE, 31, f.fastThreshold);
  }
}

FrameTracker::~FrameTracker() = default;

int FrameTracker::frameCount() const { return impl_->frames; }
const FrameTrackerOptions& FrameTracker::options() const { return impl_->options; }

TrackResult FrameTracker::track(const cv::Mat& leftRectified, const cv::Mat& disparityPx) {
  return track(leftRectified, [&disparityPx] { return disparityPx; });
}

TrackResult FrameTracker::track(const cv::Mat& leftRectified, const DisparitySource& disparityPx) {
  Impl& s = *impl_;
  require(leftRectified.size() == s.geometry.imageSize,
          "tracker: frame size " + std::to_string(leftRectified.cols) + "x" + std::to_string(leftRectified.rows) +
              " differs from the rig's " + std::to_string(s.geometry.imageSize.width) + "x" +
              std::to_string(s.geometry.imageSize.height));
  TrackResult result;
  result.frameIndex = s.frames++;
  const auto start = std::chrono::steady_clock::now();
  s.lastFeatures = s.detect(leftRectified);
  result.extractMs = millisecondsSince(start);
  s.lastTracked = false;
  const StereoFeatures& features = s.lastFeatures;
  result.features = static_cast<int>(features.keypoints.size());
  // Matching and the pose need only the reference's depth: this frame's disparity is waited for at the end, to
  // lift the features for the frames after it (and for the refiner), on every path out.
  const auto liftWithDisparity = [&] {
    const cv::Mat disparity = disparityPx();
    const auto liftStart = std::chrono::steady_clock::now();
    liftFeatures(s.lastFeatures, disparity, s.geometry);
    result.featuresWithDepth = s.lastFeatures.withDepth;
    const double liftMs = millisecondsSince(liftStart);
    result.extractMs += liftMs;
    result.orbVotingMs += liftMs;
  };

  if (s.reference.frameIndex < 0) {  // the first frame defines the start
    result.orbVotingMs = millisecondsSince(start);
    liftWithDisparity();
    result.tracked = result.initial = result.keyFrame = true;
    result.T_world_camera = s.T_world_start;
    s.setReference(features, s.T_world_start, result.frameIndex);
    s.lastKeyFrameIndex = result.frameIndex;
    s.T_world_lastKeyFrame = s.T_world_start;
    s.lastTracked = true;
    return result;
  }

  // Reference features (with depth) against all current ones: the best match is the primary, the next ones are
  // DynamicR1PPnP's candidates.
  const FeatureParameters& fp = s.options.features;
  auto partStart = std::chrono::steady_clock::now();
  std::vector<std::vector<cv::DMatch>> knn;
  if (!s.reference.descriptors.empty() && !features.descriptors.empty())
    knn = s.match(s.reference.descriptors, features.descriptors, 1 + fp.candidatesPerFeature);
  result.matchMs = millisecondsSince(partStart);
  partStart = std::chrono::steady_clock::now();
  Points3d points;
  Pixels2d pixels, fromPx;
  std::vector<std::vector<CandidateMatch>> candidates;
  // The primary match and the candidates within the Hamming limit, then (optionally) all of them refined to
  // sub-pixel accuracy in one call. A match whose window does not lock onto the reference window is dropped: it is
  // either wrong or too poorly textured to be located better than ORB's pixel grid.
  std::vector<SubPixelMatchQuery> queries;
  std::vector<int> firstQuery(knn.size(), -1), queryCount(knn.size(), 0);
  for (std::size_t i = 0; i < knn.size(); ++i) {
    const std::vector<cv::DMatch>& list = knn[i];
    if (list.empty() || list[0].distance > fp.maxHammingDistance) continue;
    firstQuery[i] = static_cast<int>(queries.size());
    for (std::size_t j = 0; j < list.size() && list[j].distance <= fp.maxHammingDistance; ++j) {
      SubPixelMatchQuery query;
      query.referenceImage = 0;
      query.image = 1;
      query.fromPx = s.reference.pixelsPx[list[0].queryIdx];
      query.toPx = features.keypoints[list[j].trainIdx].pt;
      queries.push_back(query);
    }
    queryCount[i] = static_cast<int>(queries.size()) - firstQuery[i];
  }
  std::vector<SubPixelMatchAnswer> answers(queries.size());
  if (fp.subPixelRefinement) {
    answers = s.subPixel->refine({s.reference.grey, features.grey}, queries, {s.reference.frameIndex, result.frameIndex});
  } else {
    for (std::size_t q = 0; q < queries.size(); ++q) answers[q] = {queries[q].toPx, true};
  }
  for (std::size_t i = 0; i < knn.size(); ++i) {
    if (firstQuery[i] < 0 || !answers[firstQuery[i]].locked) continue;
    const SubPixelMatchQuery& primary = queries[firstQuery[i]];
    const cv::Point2f to = answers[firstQuery[i]].toPx;
    points.push_back(s.reference.pointsWorldMm[knn[i][0].queryIdx]);
    fromPx.emplace_back(primary.fromPx.x, primary.fromPx.y);
    pixels.emplace_back(to.x, to.y);
    std::vector<CandidateMatch> further;
    for (int q = firstQuery[i] + 1; q < firstQuery[i] + queryCount[i]; ++q) {
      if (!answers[q].locked) continue;
      CandidateMatch candidate;
      candidate.pixelPx = Eigen::Vector2d(answers[q].toPx.x, answers[q].toPx.y);
      further.push_back(candidate);
    }
    candidates.push_back(std::move(further));
  }
  result.matches = static_cast<int>(points.size());
  result.subPixelMs = millisecondsSince(partStart);
  partStart = std::chrono::steady_clock::now();
  const HistogramVote vote = histogramVote(fromPx, pixels, fp.voteBinPx);
  result.voteMs = millisecondsSince(partStart);
  result.orbVotingMs = millisecondsSince(start);

  const auto lost = [&](const std::string& why) {
    liftWithDisparity();
    result.tracked = false;
    result.failureReason = why;
    return result;
  };
  const int needed = std::max(s.options.tracking.minInliers, 4);
  if (result.matches < needed) {
    return lost("too few feature matches with the last tracked frame (" + std::to_string(result.matches) + ", need " +
                std::to_string(needed) + ")");
  }
  const PinholeIntrinsics intrinsics = s.geometry.leftIntrinsics();
  const auto pnpStart = std::chrono::steady_clock::now();
  // The pose predicted from the last two tracked frames starts the first hypothesis near its answer.
  const Eigen::Matrix4d T_camera_world_guess = inverseRigid(s.predictedPose(result.frameIndex));
  const PnpResult pnp =
      solveDynamicR1Ppnp(points, pixels, candidates, intrinsics, s.options.tracking, vote.order, &T_camera_world_guess);
  result.pnpMs = millisecondsSince(pnpStart);
  if (!pnp.success) return lost(pnp.failureReason);
  result.inliers = static_cast<int>(pnp.inlierIndices.size());
  result.rmsErrorPx = pnp.rmsInlierErrorPx;
  const Eigen::Matrix4d T_world_camera = inverseRigid(pnp.T_camera_world);

  // A step far beyond what a hand-held scope does between frames is a wrong pose, not motion.
  const int steps = result.frameIndex - s.reference.frameIndex;
  const double stepMm =
      (T_world_camera.block<3, 1>(0, 3) - s.reference.T_world_camera.block<3, 1>(0, 3)).norm() / steps;
  const double stepDeg = Eigen::AngleAxisd(Eigen::Matrix3d(s.reference.T_world_camera.block<3, 3>(0, 0).transpose() *
                                                           T_world_camera.block<3, 3>(0, 0)))
                             .angle() * 180.0 / M_PI / steps;
  if (stepMm > s.options.maxStepMm || stepDeg > s.options.maxStepDeg) {
    return lost(cv::format("implausible pose jump (%.1f mm, %.1f deg per frame)", stepMm, stepDeg));
  }

  liftWithDisparity();
  result.tracked = true;
  result.T_world_camera = T_world_camera;
  const double difference = keyFramePoseDifference(T_world_camera, s.T_world_lastKeyFrame);
  result.keyFrame = isKeyFrame(result.inliers, result.frameIndex - s.lastKeyFrameIndex, difference, s.options.tracking);
  if (result.keyFrame) {
    s.lastKeyFrameIndex = result.frameIndex;
    s.T_world_lastKeyFrame = T_world_camera;
  }
  s.setReference(features, T_world_camera, result.frameIndex);
  s.lastTracked = true;
  return result;
}

const StereoFeatures& FrameTracker::lastFeatures() const { return impl_->lastFeatures; }

void FrameTracker::correctLastPose(const Eigen::Matrix4d& T_world_camera) {
  Impl& s = *impl_;
  require(s.lastTracked && s.reference.frameIndex == s.frames - 1,
          "tracker: only the pose of a just-tracked frame can be corrected");
  require(isRigidTransform(T_world_camera), "tracker: the corrected pose is not a rigid transform");
  if (s.lastKeyFrameIndex == s.reference.frameIndex) s.T_world_lastKeyFrame = T_world_camera;
  s.setReference(s.lastFeatures, T_world_camera, s.reference.frameIndex);
}

}  // namespace tissuemosaic
