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

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace tissuemosaic {

namespace {

/// The key frame new frames are matched against: its features with depth, their world points (at the key frame's
/// refined pose), and how recently each moved with the scene (TrackingParameters::dynamicResidualPx).
struct Reference {
  int frameIndex = -1;
  std::vector<cv::Point2f> pixelsPx;
  cv::Mat descriptors;
  cv::Mat grey;
  Points3d pointsCameraMm, pointsWorldMm;
  std::vector<float> motionScore;
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();

  void place(const Eigen::Matrix4d& T_world_frame) {
    T_world_camera = T_world_frame;
    const Eigen::Matrix3d R = T_world_frame.block<3, 3>(0, 0);
    const Eigen::Vector3d t = T_world_frame.block<3, 1>(0, 3);
    pointsWorldMm.resize(pointsCameraMm.size());
    for (std::size_t i = 0; i < pointsCameraMm.size(); ++i) pointsWorldMm[i] = R * pointsCameraMm[i] + t;
  }
};

double rotationDeg(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return Eigen::AngleAxisd(Eigen::Matrix3d(a.block<3, 3>(0, 0).transpose() * b.block<3, 3>(0, 0))).angle() * 180.0 /
         M_PI;
}

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

  cv::Ptr<cv::ORB> weakOrb;                    ///< FeatureParameters::weakFastThreshold, made when first needed
  std::unique_ptr<OrbExtractor> weakExtractor;  ///< the same for TissueMosaicOrb

  /// The frame's features; a frame with fewer than weakTextureFeatures is detected again with weakFastThreshold
  /// and keeps the larger set (weak texture: dark, blurred, blood-red tissue).
  StereoFeatures detect(const cv::Mat& leftRectified) {
    const FeatureParameters& f = options.features;
    StereoFeatures found = detectWith(orb, ownExtractor.get(), leftRectified);
    if (static_cast<int>(found.keypoints.size()) >= f.weakTextureFeatures || f.weakFastThreshold >= f.fastThreshold) {
      return found;
    }
    if (ownExtractor && !weakExtractor) {
      weakExtractor = std::make_unique<OrbExtractor>(options.featureDevice, orbParameters(f, f.weakFastThreshold));
    } else if (!ownExtractor && !weakOrb) {
      weakOrb = openCvOrb(f, f.weakFastThreshold);
    }
    StereoFeatures weak = detectWith(weakOrb, weakExtractor.get(), leftRectified);
    return weak.keypoints.size() > found.keypoints.size() ? std::move(weak) : std::move(found);
  }

  StereoFeatures detectWith(const cv::Ptr<cv::ORB>& openCv, OrbExtractor* extractor, const cv::Mat& leftRectified) {
    if (!extractor) return detectFeatures(*openCv, leftRectified);
    const double scaleFactor = options.features.scaleFactor;
    return detectFeatures(
        [&](const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
          const OrbFeatures found = extractor->extract(grey);
          keypoints = toCvKeyPoints(found, scaleFactor);
          descriptors = found.descriptors;
        },
        leftRectified);
  }

  static OrbParameters orbParameters(const FeatureParameters& f, int fastThreshold) {
    OrbParameters orbParameters;
    orbParameters.maxFeatures = f.maxFeatures;
    orbParameters.levels = f.levels;
    orbParameters.scaleFactor = f.scaleFactor;
    orbParameters.fastThreshold = fastThreshold;
    orbParameters.edgeThresholdPx = f.edgeThresholdPx;
    return orbParameters;
  }
  static cv::Ptr<cv::ORB> openCvOrb(const FeatureParameters& f, int fastThreshold) {
    return cv::ORB::create(f.maxFeatures, static_cast<float>(f.scaleFactor), f.levels, f.edgeThresholdPx, 0, 2,
                           cv::ORB::HARRIS_SCORE, 31, fastThreshold);
  }

  std::vector<std::vector<cv::DMatch>> match(const cv::Mat& from, const cv::Mat& to, int k) {
    std::vector<std::vector<cv::DMatch>> knn;
    if (ownMatcher) knn = ownMatcher->match(from, to, k);
    else matcher.knnMatch(from, to, knn, k);
    return knn;
  }
  int frames = 0;
  StereoFeatures lastFeatures;       ///< of the last track() call; moving features without 3D points
  std::vector<float> lastScores;     ///< per feature of the last frame: its motion score (0: none seen)
  bool lastTracked = false;
  Reference reference;               ///< the last key frame
  int lastKeyFrameIndex = -1;
  Eigen::Matrix4d T_world_lastKeyFrame = Eigen::Matrix4d::Identity();
  bool lost = false;                 ///< the frames since the last tracked one were lost

  /// The last two tracked frames (for the constant-velocity prediction); index -1: none.
  int lastTrackedIndex = -1, previousTrackedIndex = -1;
  Eigen::Matrix4d T_world_lastTracked = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d T_world_previousTracked = Eigen::Matrix4d::Identity();

  /// The pose predicted for frame `frameIndex`: the last tracked pose moved on by the last step when the last two
  /// tracked frames and this one are consecutive (constant velocity), else the last tracked pose.
  Eigen::Matrix4d predictedPose(int frameIndex) const {
    if (previousTrackedIndex >= 0 && lastTrackedIndex - previousTrackedIndex == 1 && frameIndex - lastTrackedIndex == 1) {
      return T_world_lastTracked * (inverseRigid(T_world_previousTracked) * T_world_lastTracked);
    }
    return T_world_lastTracked;
  }

  void recordTracked(int frameIndex, const Eigen::Matrix4d& T_world_camera) {
    if (lastTrackedIndex >= 0 && lastTrackedIndex != frameIndex) {
      previousTrackedIndex = lastTrackedIndex;
      T_world_previousTracked = T_world_lastTracked;
    }
    lastTrackedIndex = frameIndex;
    T_world_lastTracked = T_world_camera;
  }

  /// The frame's features with depth become the reference (a new key frame), with their motion scores.
  void setReference(const StereoFeatures& features, const std::vector<float>& scores, const Eigen::Matrix4d& T_world_camera,
                    int frameIndex) {
    reference = Reference();
    reference.frameIndex = frameIndex;
    reference.grey = features.grey;
    std::vector<int> rows;
    for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
      if (!features.pointsCameraMm[i].allFinite()) continue;
      rows.push_back(static_cast<int>(i));
      reference.pixelsPx.push_back(features.keypoints[i].pt);
      reference.pointsCameraMm.push_back(features.pointsCameraMm[i]);
      reference.motionScore.push_back(i < scores.size() ? scores[i] : 0.0f);
    }
    reference.descriptors = descriptorRows(features.descriptors, rows);
    reference.place(T_world_camera);
    lastKeyFrameIndex = frameIndex;
    T_world_lastKeyFrame = T_world_camera;
  }

  /// What later steps see of the last frame: features that moved recently lose their 3D point.
  void clearMovingPoints() {
    const float exclude = static_cast<float>(options.tracking.dynamicExcludeScore);
    lastFeatures.moving.assign(lastFeatures.keypoints.size(), 0);
    for (std::size_t i = 0; i < lastScores.size() && i < lastFeatures.pointsCameraMm.size(); ++i) {
      if (!(lastScores[i] > exclude)) continue;
      lastFeatures.moving[i] = 1;
      if (lastFeatures.pointsCameraMm[i].allFinite()) {
        lastFeatures.pointsCameraMm[i] = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
        --lastFeatures.withDepth;
      }
    }
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
    impl_->ownExtractor = std::make_unique<OrbExtractor>(options.featureDevice, Impl::orbParameters(f, f.fastThreshold));
    impl_->ownMatcher = std::make_unique<HammingMatcher>(options.featureDevice);
  } else {
    require(options.featureDevice == Device::Cpu, "tracker: OpenCV's ORB runs on the CPU only");
    impl_->orb = Impl::openCvOrb(f, f.fastThreshold);
  }
}

FrameTracker::~FrameTracker() = default;

int FrameTracker::frameCount() const { return impl_->frames; }
const FrameTrackerOptions& FrameTracker::options() const { return impl_->options; }

TrackResult FrameTracker::track(const cv::Mat& leftRectified, const cv::Mat& disparityPx) {
  const cv::Size size = impl_->geometry.imageSize;
  return track(leftRectified, [&disparityPx, size](const std::vector<cv::Point2f>& pointsPx) {
    return sampleDisparityMap(disparityPx, size, pointsPx);
  });
}

TrackResult FrameTracker::track(const cv::Mat& leftRectified, const DisparitySource& disparityPx,
                                const PoseCheck& check) {
  Impl& s = *impl_;
  require(leftRectified.size() == s.geometry.imageSize,
          "tracker: frame size " + std::to_string(leftRectified.cols) + "x" + std::to_string(leftRectified.rows) +
              " differs from the rig's " + std::to_string(s.geometry.imageSize.width) + "x" +
              std::to_string(s.geometry.imageSize.height));
  TrackResult result;
  result.frameIndex = s.frames++;
  const auto start = std::chrono::steady_clock::now();
  s.lastFeatures = s.detect(leftRectified);
  s.lastScores.assign(s.lastFeatures.keypoints.size(), 0.0f);
  result.timesMs.extract = millisecondsSince(start);
  s.lastTracked = false;
  const StereoFeatures& features = s.lastFeatures;
  result.features = static_cast<int>(features.keypoints.size());
  // Matching and the pose need only the reference's depth: this frame's disparity is waited for at the end, to
  // lift the features for the frames after it (and for the refiner), on every path out.
  bool lifted = false;
  const auto liftWithDisparity = [&] {
    if (lifted) return;
    lifted = true;
    const std::vector<float> disparities = disparityPx(keypointPositions(s.lastFeatures));
    const auto liftStart = std::chrono::steady_clock::now();
    liftFeatures(s.lastFeatures, disparities, s.geometry);
    result.featuresWithDepth = s.lastFeatures.withDepth;
    const double liftMs = millisecondsSince(liftStart);
    result.timesMs.extract += liftMs;
    result.timesMs.orbVoting += liftMs;
  };

  if (s.reference.frameIndex < 0) {  // the first frame defines the start
    result.timesMs.orbVoting = millisecondsSince(start);
    liftWithDisparity();
    result.tracked = result.initial = result.keyFrame = true;
    result.T_world_camera = s.T_world_start;
    s.setReference(features, s.lastScores, s.T_world_start, result.frameIndex);
    s.recordTracked(result.frameIndex, s.T_world_start);
    s.lastTracked = true;
    return result;
  }

  // Key-frame features (with depth) against all current ones: the best match is the primary, the next ones are
  // DynamicR1PPnP's candidates.
  const FeatureParameters& fp = s.options.features;
  const TrackingParameters& tp = s.options.tracking;
  auto partStart = std::chrono::steady_clock::now();
  std::vector<std::vector<cv::DMatch>> knn;
  if (!s.reference.descriptors.empty() && !features.descriptors.empty())
    knn = s.match(s.reference.descriptors, features.descriptors, 1 + fp.candidatesPerFeature);
  result.timesMs.match = millisecondsSince(partStart);
  partStart = std::chrono::steady_clock::now();
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
  // Every locked match, and which reference and current feature it joins.
  struct Match {
    int reference, current;
    Eigen::Vector3d worldMm;
    Eigen::Vector2d fromPx, toPx;
    std::vector<CandidateMatch> candidates;
  };
  std::vector<Match> all;
  for (std::size_t i = 0; i < knn.size(); ++i) {
    if (firstQuery[i] < 0 || !answers[firstQuery[i]].locked) continue;
    const SubPixelMatchQuery& primary = queries[firstQuery[i]];
    const cv::Point2f to = answers[firstQuery[i]].toPx;
    Match match;
    match.reference = knn[i][0].queryIdx;
    match.current = knn[i][0].trainIdx;
    match.worldMm = s.reference.pointsWorldMm[match.reference];
    match.fromPx = Eigen::Vector2d(primary.fromPx.x, primary.fromPx.y);
    match.toPx = Eigen::Vector2d(to.x, to.y);
    for (int q = firstQuery[i] + 1; q < firstQuery[i] + queryCount[i]; ++q) {
      if (!answers[q].locked) continue;
      CandidateMatch candidate;
      candidate.pixelPx = Eigen::Vector2d(answers[q].toPx.x, answers[q].toPx.y);
      match.candidates.push_back(candidate);
    }
    all.push_back(std::move(match));
  }
  // The pose from the key-frame features that have not moved recently, while enough of them are left.
  const int needed = std::max(tp.minInliers, 4);
  const auto moving = [&](const Match& m) { return s.reference.motionScore[m.reference] > tp.dynamicExcludeScore; };
  const int still = static_cast<int>(std::count_if(all.begin(), all.end(), [&](const Match& m) { return !moving(m); }));
  const bool leaveOutMoving = still >= std::max(2 * needed, 30);
  Points3d points;
  Pixels2d pixels, fromPx;
  std::vector<std::vector<CandidateMatch>> candidates;
  for (const Match& m : all) {
    if (leaveOutMoving && moving(m)) {
      ++result.movingMatches;
      continue;
    }
    points.push_back(m.worldMm);
    fromPx.push_back(m.fromPx);
    pixels.push_back(m.toPx);
    candidates.push_back(m.candidates);
  }
  result.matches = static_cast<int>(points.size());
  result.timesMs.subPixel = millisecondsSince(partStart);
  partStart = std::chrono::steady_clock::now();
  const HistogramVote vote = histogramVote(fromPx, pixels, fp.voteBinPx);
  result.timesMs.vote = millisecondsSince(partStart);
  result.timesMs.orbVoting = millisecondsSince(start);

  const auto lost = [&](const std::string& why) {
    liftWithDisparity();
    result.tracked = false;
    result.failureReason = why;
    s.lost = true;
    return result;
  };
  if (result.matches < needed) {
    return lost("too few feature matches with the last key frame (" + std::to_string(result.matches) + ", need " +
                std::to_string(needed) + ")");
  }
  const PinholeIntrinsics intrinsics = s.geometry.leftIntrinsics();
  const auto pnpStart = std::chrono::steady_clock::now();
  // The pose predicted from the last two tracked frames starts the first hypothesis near its answer.
  const Eigen::Matrix4d T_camera_world_guess = inverseRigid(s.predictedPose(result.frameIndex));
  PnpResult pnp =
      solveDynamicR1Ppnp(points, pixels, candidates, intrinsics, tp, vote.order, &T_camera_world_guess);
  // Polished last on the matches that sit where the pose projects them (within a few times this frame's own
  // matching noise): points a little off, which the scene moved, would bend the pose toward their own motion.
  double fitPx = tp.dynamicResidualPx;
  pnp = polishOnFittingMatches(points, pixels, candidates, intrinsics, pnp, tp.dynamicResidualPx, tp.minInliers, &fitPx);
  result.timesMs.pnp = millisecondsSince(pnpStart);
  if (!pnp.success) return lost(pnp.failureReason);
  result.inliers = static_cast<int>(pnp.inlierIndices.size());
  result.rmsErrorPx = pnp.rmsInlierErrorPx;
  const Eigen::Matrix4d T_world_camera = inverseRigid(pnp.T_camera_world);

  // A step far beyond what a hand-held scope does between frames is a wrong pose, not motion.
  const int steps = std::max(1, result.frameIndex - s.lastTrackedIndex);
  const double stepMm = (T_world_camera.block<3, 1>(0, 3) - s.T_world_lastTracked.block<3, 1>(0, 3)).norm() / steps;
  const double stepDeg = rotationDeg(s.T_world_lastTracked, T_world_camera) / steps;
  result.stepMmPerFrame = stepMm;
  result.stepDegPerFrame = stepDeg;
  if (stepMm > s.options.maxStepMm || stepDeg > s.options.maxStepDeg) {
    return lost(cv::format("implausible pose jump (%.1f mm, %.1f deg per frame)", stepMm, stepDeg));
  }

  liftWithDisparity();
  if (check) {
    const std::string refused = check(T_world_camera);
    if (!refused.empty()) return lost(refused);
  }
  result.tracked = true;
  result.relocalised = s.lost;
  s.lost = false;
  result.T_world_camera = T_world_camera;

  // Motion evidence: each matched key-frame feature whose match (primary or candidate) lands off its projection, or
  // whose depth here is not the depth the pose predicts for it.
  const Eigen::Matrix3d R = pnp.T_camera_world.block<3, 3>(0, 0);
  const Eigen::Vector3d t = pnp.T_camera_world.block<3, 1>(0, 3);
  const double limit2 = fitPx * fitPx;
  const double focalBaseline = s.geometry.focalPx * s.geometry.baselineMm;
  // The depth test's bound follows the frame's own stereo noise: real in-vivo stereo differs from the predicted
  // depth by more than a pixel of disparity on most still tissue, and a fixed bound there flagged most of the view.
  const auto predictedCamera = [&](const Match& m) { return Eigen::Vector3d(R * m.worldMm + t); };
  const auto disparityDifferencePx = [&](const Match& m) {
    const Eigen::Vector3d c = predictedCamera(m);
    const Eigen::Vector3d& measured = s.lastFeatures.pointsCameraMm[m.current];
    if (!(c.z() > 1e-9) || !measured.allFinite() || !(measured.z() > 0)) return std::numeric_limits<double>::quiet_NaN();
    return focalBaseline * std::abs(1.0 / measured.z() - 1.0 / c.z());
  };
  double depthLimitPx = tp.dynamicDisparityPx;
  if (tp.dynamicDisparityPx > 0) {
    std::vector<double> differences;
    for (const Match& m : all) {
      const double d = disparityDifferencePx(m);
      if (std::isfinite(d)) differences.push_back(d);
    }
    if (!differences.empty()) {
      std::nth_element(differences.begin(), differences.begin() + differences.size() / 2, differences.end());
      depthLimitPx = std::max(depthLimitPx, kFitMedianFactor * differences[differences.size() / 2]);
    }
  }
  for (float& score : s.reference.motionScore) score *= static_cast<float>(tp.dynamicScoreDecay);
  for (const Match& m : all) {
    const Eigen::Vector3d c = predictedCamera(m);
    double u = 0, v = 0;
    bool off = !(c.z() > 1e-9);
    if (!off) {
      intrinsics.project(c.x(), c.y(), c.z(), u, v);
      const Eigen::Vector2d projected(u, v);
      double error2 = (projected - m.toPx).squaredNorm();
      for (const CandidateMatch& candidate : m.candidates) error2 = std::min(error2, (projected - candidate.pixelPx).squaredNorm());
      off = tp.dynamicResidualPx > 0 && error2 > limit2;
      if (!off && tp.dynamicDisparityPx > 0) off = disparityDifferencePx(m) > depthLimitPx;
    }
    float& score = s.reference.motionScore[m.reference];
    if (off) score = 1.0f;
    s.lastScores[m.current] = std::max(s.lastScores[m.current], score);
  }

  const double difference = keyFramePoseDifference(T_world_camera, s.T_world_lastKeyFrame);
  result.keyFrame = isKeyFrame(result.inliers, result.frameIndex - s.lastKeyFrameIndex, difference, tp);
  s.recordTracked(result.frameIndex, T_world_camera);
  if (result.keyFrame) s.setReference(features, s.lastScores, T_world_camera, result.frameIndex);
  s.clearMovingPoints();
  s.lastTracked = true;
  return result;
}

TrackResult FrameTracker::acceptRelocalisation(const Eigen::Matrix4d& T_world_camera, int inliers) {
  Impl& s = *impl_;
  require(s.frames > 0 && !s.lastTracked, "tracker: only a frame that was lost can be relocalised");
  require(isRigidTransform(T_world_camera), "tracker: the relocalised pose is not a rigid transform");
  TrackResult result;
  result.frameIndex = s.frames - 1;
  result.tracked = result.keyFrame = result.relocalised = true;
  result.T_world_camera = T_world_camera;
  result.inliers = inliers;
  result.features = static_cast<int>(s.lastFeatures.keypoints.size());
  result.featuresWithDepth = s.lastFeatures.withDepth;
  // A fresh start from here: no velocity across the gap, no motion seen yet.
  s.previousTrackedIndex = -1;
  s.lastTrackedIndex = -1;
  s.recordTracked(result.frameIndex, T_world_camera);
  s.lastScores.assign(s.lastFeatures.keypoints.size(), 0.0f);
  s.setReference(s.lastFeatures, s.lastScores, T_world_camera, result.frameIndex);
  s.lost = false;
  s.lastTracked = true;
  return result;
}

Eigen::Matrix4d FrameTracker::predictedPose() const { return impl_->predictedPose(impl_->frames - 1); }

bool FrameTracker::continuesMotion(const Eigen::Matrix4d& T_world_camera) const {
  const Eigen::Matrix4d predicted = predictedPose();
  const TrackingParameters& tp = impl_->options.tracking;
  return (T_world_camera.block<3, 1>(0, 3) - predicted.block<3, 1>(0, 3)).norm() <= tp.priorStepMm &&
         rotationDeg(predicted, T_world_camera) <= tp.priorStepDeg;
}

bool FrameTracker::isLost() const { return impl_->lost; }
const Eigen::Matrix4d& FrameTracker::lastTrackedPose() const { return impl_->T_world_lastTracked; }
int FrameTracker::lastTrackedFrame() const { return impl_->lastTrackedIndex; }

const StereoFeatures& FrameTracker::lastFeatures() const { return impl_->lastFeatures; }

void FrameTracker::correctLastPose(const Eigen::Matrix4d& T_world_camera) {
  Impl& s = *impl_;
  require(s.lastTracked && s.lastTrackedIndex == s.frames - 1,
          "tracker: only the pose of a just-tracked frame can be corrected");
  require(isRigidTransform(T_world_camera), "tracker: the corrected pose is not a rigid transform");
  s.T_world_lastTracked = T_world_camera;
  if (s.reference.frameIndex == s.lastTrackedIndex) {  // a key frame: its features move with it
    s.reference.place(T_world_camera);
    s.T_world_lastKeyFrame = T_world_camera;
  }
}

}  // namespace tissuemosaic
