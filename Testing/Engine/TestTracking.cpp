// Camera tracking of paper III.A-C: histogram voting ranks true matches first among 85% outliers, the key-frame
// pose difference follows the paper's equation, a short synthetic scan is tracked to sub-millimetre accuracy with
// the CPU stereo stage, and a blank frame is reported as lost (then tracking resumes) instead of a made-up pose.
#include "SyntheticRandom.h"
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Stereo/StereoMatcher.h"
#include "Tracking/FrameTracker.h"
#include "Tracking/HistogramVoting.h"
#include "Tracking/KeyFrameDecision.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

using namespace tissuemosaic;

namespace {

using Pixels = std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>>;

Eigen::Matrix4d pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = R;
  T.block<3, 1>(0, 3) = t;
  return T;
}

synthetic::SyntheticScanOptions shortScan() {
  synthetic::SyntheticScanOptions options;
  options.width = 480;
  options.height = 270;
  options.frames = 16;
  options.seed = 11;
  return options;
}

}  // namespace

TEST(HistogramVoting, PutsTrueMatchesFirstAmong85PercentOutliers) {
  std::mt19937 generator(2024);
  const int inliers = 60, outliers = 340;  // 85% outliers
  Pixels from, to;
  std::vector<bool> isInlier;
  // Inliers: a small camera motion seen in a 480x270 image (shift, 1 degree roll, 1% zoom) plus 0.7 px of noise.
  const double roll = 1.0 * M_PI / 180, zoom = 1.01;
  for (int i = 0; i < inliers + outliers; ++i) {
    const Eigen::Vector2d p(synthetic::uniform(generator, 0, 480), synthetic::uniform(generator, 0, 270));
    // Interleave inliers among outliers so that input order gives no hint.
    const bool inlier = (i * inliers) / (inliers + outliers) != ((i + 1) * inliers) / (inliers + outliers);
    Eigen::Vector2d q;
    if (inlier) {
      const Eigen::Vector2d c(240, 135);
      q = c + zoom * (Eigen::Rotation2Dd(roll).toRotationMatrix() * (p - c)) + Eigen::Vector2d(14, -9) +
          Eigen::Vector2d(synthetic::uniform(generator, -0.7, 0.7), synthetic::uniform(generator, -0.7, 0.7));
    } else {
      q = Eigen::Vector2d(synthetic::uniform(generator, 0, 480), synthetic::uniform(generator, 0, 270));
    }
    from.push_back(p);
    to.push_back(q);
    isInlier.push_back(inlier);
  }
  ASSERT_EQ(std::count(isInlier.begin(), isInlier.end(), true), inliers);
  const HistogramVote vote = histogramVote(from, to, 6.0);
  ASSERT_EQ(vote.order.size(), from.size());
  int top10 = 0, topN = 0;
  for (int r = 0; r < inliers; ++r) {
    topN += isInlier[vote.order[r]];
    if (r < 10) top10 += isInlier[vote.order[r]];
  }
  EXPECT_EQ(top10, 10);
  EXPECT_GE(topN, 0.9 * inliers) << "true matches among the first " << inliers << " of the vote order";
  // Input order would put only 15% inliers first.
  EXPECT_THROW(histogramVote(from, Pixels(3), 6.0), Error);
  EXPECT_THROW(histogramVote(from, to, 0.0), Error);
}

TEST(KeyFrameDecision, PoseDifferenceFollowsThePaper) {
  const Eigen::Matrix4d a = pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3));
  const Eigen::Matrix4d b =
      pose(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d(1, 2, 6));
  EXPECT_NEAR(keyFramePoseDifference(a, b), 3.0 + 20 * 0.1, 1e-9);
  EXPECT_NEAR(keyFramePoseDifference(b, a), 3.0 + 20 * 0.1, 1e-9);
  // A small negative yaw is small, not nearly 2 pi (Euler angle differences wrap).
  const Eigen::Matrix4d c = pose(Eigen::AngleAxisd(M_PI - 0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                                 Eigen::Vector3d(1, 2, 3));
  const Eigen::Matrix4d d = pose(Eigen::AngleAxisd(-M_PI + 0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                                 Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(keyFramePoseDifference(c, d), 20 * 0.02, 1e-9);

  TrackingParameters p;  // 50 inliers, 10 frames, threshold 10
  EXPECT_FALSE(isKeyFrame(49, 100, 100.0, p));
  EXPECT_TRUE(isKeyFrame(50, 10, 0.0, p));
  EXPECT_FALSE(isKeyFrame(50, 9, 10.0, p));
  EXPECT_TRUE(isKeyFrame(50, 9, 10.5, p));
}

namespace {

/// Tracks the short synthetic scan with CPU stereo and checks the trajectory against its ground truth: the
/// requirement bars (ATE <= 1 mm, rotation <= 0.6 deg) and regression bars near twice the extractor's values measured
/// when they were set (2026-11-25).
void trackShortScan(const FrameTrackerOptions& options, const char* label, double regressionAteMm,
                    double regressionDeg) {
  const synthetic::SyntheticScan scan(shortScan());
  StereoMatcher matcher(Device::Cpu, StereoParameters{});
  FrameTracker tracker(scan.geometry(), options, scan.T_world_camera(0));
  double sum2 = 0, worstMm = 0, worstDeg = 0, pathMm = 0;
  int keyFrames = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    // As the reconstruction pipeline gives it: without the pixels near a highlight.
    matcher.computeDisparity(frame.leftRectified, frame.rightRectified);
    const cv::Mat disparity = matcher.lastDisparityAwayFromHighlights();
    const TrackResult result = tracker.track(frame.leftRectified, disparity);
    ASSERT_TRUE(result.tracked) << "frame " << k << " lost: " << result.failureReason;
    EXPECT_EQ(result.initial, k == 0);
    keyFrames += result.keyFrame;
    if (k > 0) {
      EXPECT_GE(result.inliers, 50) << "frame " << k;
      pathMm += (scan.T_world_camera(k).block<3, 1>(0, 3) - scan.T_world_camera(k - 1).block<3, 1>(0, 3)).norm();
    }
    const Eigen::Matrix4d truth = frame.T_world_camera;
    const double e = (result.T_world_camera.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).norm();
    const double deg = Eigen::AngleAxisd(Eigen::Matrix3d(truth.block<3, 3>(0, 0).transpose() *
                                                         result.T_world_camera.block<3, 3>(0, 0)))
                           .angle() * 180 / M_PI;
    sum2 += e * e;
    worstMm = std::max(worstMm, e);
    worstDeg = std::max(worstDeg, deg);
  }
  const double ateMm = std::sqrt(sum2 / scan.frameCount());
  std::printf("[ tracking, %s ] %d frames, path %.1f mm: ATE RMS %.3f mm, max %.3f mm, max rotation error %.3f deg, "
              "%d key frames\n", label, scan.frameCount(), pathMm, ateMm, worstMm, worstDeg, keyFrames);
  EXPECT_GT(pathMm, 5.0) << "the camera should actually move";
  EXPECT_LE(ateMm, 1.0);
  EXPECT_LE(ateMm, regressionAteMm);
  // OpenCV's ORB with the default 1000 features reaches 0.55 deg on one frame of this clip (0.36 deg with 2000).
  EXPECT_LE(worstDeg, 0.6);
  EXPECT_LE(worstDeg, regressionDeg);
  EXPECT_EQ(keyFrames, 2);  // the first frame and frame 10 (min gap 10)
}

}  // namespace

// Measured: ATE 0.449 mm, 0.552 deg (twice those lie beyond the requirement bars: 1.0 mm binds, and 0.6 deg).
TEST(FrameTracker, TracksASyntheticScanWithSubMillimetreError) {
  trackShortScan(FrameTrackerOptions{}, "OpenCV ORB", 2 * 0.449, 0.6);
}

// The extractor that the GPU runs, here on the CPU (CPU and CUDA give identical features: TestOrbCuda.cpp).
TEST(FrameTracker, TracksASyntheticScanWithTheSingleSourceOrb) {
  FrameTrackerOptions options;
  options.extractor = FeatureExtractor::TissueMosaicOrb;
  trackShortScan(options, "TissueMosaic ORB", 2 * 0.145, 2 * 0.161);  // measured: ATE 0.145 mm, 0.161 deg
}

TEST(FrameTracker, ReportsABlankFrameAsLostAndResumes) {
  synthetic::SyntheticScanOptions options = shortScan();
  options.frames = 3;
  const synthetic::SyntheticScan scan(options);
  FrameTracker tracker(scan.geometry(), FrameTrackerOptions{}, scan.T_world_camera(0));
  const synthetic::SyntheticScanFrame first = scan.renderFrame(0);
  ASSERT_TRUE(tracker.track(first.leftRectified, first.disparityPx).tracked);

  // A blank frame (lens covered): no features, so no matches; the tracker must say so, not guess a pose.
  const cv::Mat blank(first.leftRectified.size(), CV_8UC3, cv::Scalar(90, 90, 160));
  const cv::Mat noDisparity(first.disparityPx.size(), CV_32F, cv::Scalar(std::nanf("")));
  const TrackResult lost = tracker.track(blank, noDisparity);
  EXPECT_FALSE(lost.tracked);
  EXPECT_FALSE(lost.keyFrame);
  EXPECT_EQ(lost.matches, 0);
  EXPECT_NE(lost.failureReason.find("too few feature matches"), std::string::npos) << lost.failureReason;

  // The next good frame is matched against the last tracked one (frame 0) and tracked again.
  const synthetic::SyntheticScanFrame third = scan.renderFrame(2);
  const TrackResult resumed = tracker.track(third.leftRectified, third.disparityPx);
  ASSERT_TRUE(resumed.tracked) << resumed.failureReason;
  EXPECT_EQ(resumed.frameIndex, 2);
  EXPECT_LT((resumed.T_world_camera.block<3, 1>(0, 3) - third.T_world_camera.block<3, 1>(0, 3)).norm(), 0.5);

  // Misuse throws: a frame of the wrong size.
  EXPECT_THROW(tracker.track(cv::Mat(10, 10, CV_8UC3, cv::Scalar(0)), cv::Mat(10, 10, CV_32F)), Error);
}

// The pipeline computes a frame's disparity beside its tracking: the tracker asks for it only after matching and the
// pose, once per frame on every path (first frame, tracked, lost), and tracks exactly as with the disparity given.
TEST(FrameTracker, AsksForTheDisparityOncePerFrameAndTracksTheSame) {
  synthetic::SyntheticScanOptions options = shortScan();
  options.frames = 4;
  const synthetic::SyntheticScan scan(options);
  FrameTrackerOptions trackerOptions;
  trackerOptions.extractor = FeatureExtractor::TissueMosaicOrb;
  FrameTracker given(scan.geometry(), trackerOptions, scan.T_world_camera(0));
  FrameTracker asked(scan.geometry(), trackerOptions, scan.T_world_camera(0));
  std::vector<cv::Mat> lefts, disparities;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    lefts.push_back(frame.leftRectified);
    disparities.push_back(frame.disparityPx);
  }
  // Frame 2 is blank (lens covered): lost, but its disparity is still asked for.
  lefts[2] = cv::Mat(lefts[0].size(), CV_8UC3, cv::Scalar(90, 90, 160));
  disparities[2] = cv::Mat(lefts[0].size(), CV_32F, cv::Scalar(std::nanf("")));
  for (int k = 0; k < scan.frameCount(); ++k) {
    int calls = 0;
    std::size_t pointsAsked = 0;
    const TrackResult a = given.track(lefts[k], disparities[k]);
    const TrackResult b = asked.track(lefts[k], [&](const std::vector<cv::Point2f>& pointsPx) {
      ++calls;
      pointsAsked = pointsPx.size();
      return sampleDisparityMap(disparities[k], disparities[k].size(), pointsPx);
    });
    EXPECT_EQ(calls, 1) << "frame " << k;
    EXPECT_EQ(pointsAsked, asked.lastFeatures().keypoints.size()) << "frame " << k << ": the disparity at each feature";
    EXPECT_EQ(a.tracked, b.tracked) << "frame " << k;
    EXPECT_EQ(b.tracked, k != 2) << "frame " << k << ": " << b.failureReason;
    EXPECT_EQ(a.keyFrame, b.keyFrame);
    EXPECT_EQ(a.inliers, b.inliers);
    EXPECT_EQ(a.featuresWithDepth, b.featuresWithDepth);
    EXPECT_GT(b.featuresWithDepth, k == 2 ? -1 : 100);
    EXPECT_TRUE(a.T_world_camera == b.T_world_camera) << "frame " << k;
    ASSERT_EQ(given.lastFeatures().pointsCameraMm.size(), asked.lastFeatures().pointsCameraMm.size());
    for (std::size_t i = 0; i < given.lastFeatures().pointsCameraMm.size(); ++i) {
      const Eigen::Vector3d p = given.lastFeatures().pointsCameraMm[i], q = asked.lastFeatures().pointsCameraMm[i];
      EXPECT_TRUE((p.array() == q.array()).all() || (!p.allFinite() && !q.allFinite())) << "feature " << i;
    }
  }
  // The stage computing the disparity failed: its error reaches the caller.
  EXPECT_THROW(asked.track(lefts[3], [](const std::vector<cv::Point2f>&) -> std::vector<float> {
                 throw Error("stereo failed");
               }), Error);
  // A source that samples too few points is misuse, not a silent lift of the wrong features.
  EXPECT_THROW(asked.track(lefts[3], [](const std::vector<cv::Point2f>&) { return std::vector<float>(3, 20.0f); }),
               Error);
}

TEST(FrameTracker, RefusesAStartPoseThatIsNotARigidTransform) {
  synthetic::SyntheticScanOptions options = shortScan();
  options.frames = 1;
  const synthetic::SyntheticScan scan(options);
  Eigen::Matrix4d mirrored = scan.T_world_camera(0);
  mirrored.col(0) *= -1.0;  // orthonormal, but a reflection: determinant -1
  EXPECT_THROW(FrameTracker(scan.geometry(), FrameTrackerOptions{}, mirrored), Error);
  Eigen::Matrix4d scaled = scan.T_world_camera(0);
  scaled.block<3, 3>(0, 0) *= 1.01;
  EXPECT_THROW(FrameTracker(scan.geometry(), FrameTrackerOptions{}, scaled), Error);
  EXPECT_NO_THROW(FrameTracker(scan.geometry(), FrameTrackerOptions{}, scan.T_world_camera(0)));
}
