// R1PPnP / DynamicR1PPnP (paper III.B) against synthetic ground truth, degenerate input, the tracking parameters
// file round trip, and the `bench pnp` JSON.
#include "Core/Error.h"
#include "Tracking/PnpBenchmark.h"
#include "Tracking/PnpSolver.h"
#include "Tracking/TrackingParameters.h"

#include <Eigen/Geometry>
#include <opencv2/core/persistence.hpp>
#include <tbb/task_arena.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace tissuemosaic;

namespace {

void expectPose(const PnpResult& result, const Eigen::Matrix4d& truth, double maxDeg, double maxMm) {
  ASSERT_TRUE(result.success) << result.failureReason;
  double rotationDeg = 0, centreMm = 0;
  poseDifference(result.T_camera_world, truth, rotationDeg, centreMm);
  EXPECT_LT(rotationDeg, maxDeg);
  EXPECT_LT(centreMm, maxMm);
}

}  // namespace

TEST(PnpSolver, ExactRecoveryWithoutNoise) {
  const TrackingParameters parameters;
  for (double outlierRatio : {0.0, 0.5}) {
    const SyntheticPnpCase scene = makeSyntheticPnpCase(7, 300, outlierRatio, 0.0);
    const PnpResult r1 = solveR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.intrinsics, parameters);
    expectPose(r1, scene.T_camera_world, 1e-6, 1e-6);
    // DynamicR1PPnP: exact only without outliers, since an outlier's distractor candidates (repeating texture,
    // within 40 px) can fall inside H of the true projection and are then rightly taken as inliers.
    if (outlierRatio == 0.0) {
      const PnpResult dynamic =
          solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics, parameters);
      expectPose(dynamic, scene.T_camera_world, 1e-6, 1e-6);
    }
    // Every true inlier is found, and every reported R1PPnP inlier is a true one (outliers are random pixels).
    int trueInliers = 0;
    for (unsigned char flag : scene.isInlier) trueInliers += flag;
    EXPECT_GE(static_cast<int>(r1.inlierIndices.size()), trueInliers);
    EXPECT_LE(static_cast<int>(r1.inlierIndices.size()), trueInliers + 2);
    EXPECT_LT(r1.rmsInlierErrorPx, 1e-3 + (outlierRatio > 0 ? 5.0 : 0.0));
  }
}

TEST(PnpSolver, TranslationAndRotationMatchTheReturnedConvention) {
  // X_camera = R X_world + t: the inliers must reproject onto their pixels with the returned matrix.
  const SyntheticPnpCase scene = makeSyntheticPnpCase(11, 200, 0.3, 0.0);
  const PnpResult r = solveR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.intrinsics, TrackingParameters());
  ASSERT_TRUE(r.success);
  for (int i : r.inlierIndices) {
    const Eigen::Vector3d c = r.rotation() * scene.pointsMm[i] + r.translationMm();
    const Eigen::Vector2d px(scene.intrinsics.fxPx * c.x() / c.z() + scene.intrinsics.cxPx,
                             scene.intrinsics.fyPx * c.y() / c.z() + scene.intrinsics.cyPx);
    EXPECT_LT((px - scene.pixelsPx[i]).norm(), 5.0);
  }
}

TEST(PnpSolver, SucceedsAtNinetyPercentOutliers) {
  const TrackingParameters parameters;
  int r1Successes = 0, dynamicSuccesses = 0;
  const int trials = 50;
  for (int trial = 0; trial < trials; ++trial) {
    const SyntheticPnpCase scene = makeSyntheticPnpCase(5000 + trial, 500, 0.9, 1.0);
    double rotationDeg = 0, centreMm = 0;
    const PnpResult r1 = solveR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.intrinsics, parameters);
    poseDifference(r1.T_camera_world, scene.T_camera_world, rotationDeg, centreMm);
    r1Successes += r1.success && rotationDeg < 1.0 && centreMm < 2.0;
    const PnpResult dynamic =
        solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics, parameters);
    poseDifference(dynamic.T_camera_world, scene.T_camera_world, rotationDeg, centreMm);
    dynamicSuccesses += dynamic.success && rotationDeg < 1.0 && centreMm < 2.0;
  }
  EXPECT_GE(r1Successes, 49) << "R1PPnP success rate " << r1Successes / double(trials);
  EXPECT_GE(dynamicSuccesses, 45) << "DynamicR1PPnP success rate " << dynamicSuccesses / double(trials);
}

TEST(PnpSolver, APoseGuessGivesTheSamePoseInFewerIterations) {
  const TrackingParameters parameters;
  int plainIterations = 0, warmIterations = 0;
  const int trials = 20;
  for (int trial = 0; trial < trials; ++trial) {
    const SyntheticPnpCase scene = makeSyntheticPnpCase(900 + trial, 800, 0.3, 1.0);
    const PnpResult plain =
        solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics, parameters);
    // The previous frame of a scan: about 1 mm and 0.5 degrees away from the truth.
    Eigen::Matrix4d guess = scene.T_camera_world;
    guess.block<3, 3>(0, 0) = Eigen::AngleAxisd(0.5 * M_PI / 180, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix() *
                              guess.block<3, 3>(0, 0);
    guess.block<3, 1>(0, 3) += Eigen::Vector3d(0.6, -0.5, 0.6);
    const PnpResult warm = solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics,
                                              parameters, {}, &guess);
    ASSERT_TRUE(plain.success && warm.success) << plain.failureReason << warm.failureReason;
    // Both as close to the truth as 1 px noise allows (they may settle on inlier sets that differ by a match or two).
    double rotationDeg = 0, centreMm = 0, plainDeg = 0, plainMm = 0;
    poseDifference(warm.T_camera_world, scene.T_camera_world, rotationDeg, centreMm);
    poseDifference(plain.T_camera_world, scene.T_camera_world, plainDeg, plainMm);
    EXPECT_LT(rotationDeg, std::max(0.05, 1.5 * plainDeg)) << "trial " << trial;
    EXPECT_LT(centreMm, std::max(0.1, 1.5 * plainMm)) << "trial " << trial;
    plainIterations += plain.innerIterations;
    warmIterations += warm.innerIterations;
    // A wrong guess (far from the truth) costs iterations, never the answer.
    Eigen::Matrix4d wrong = scene.T_camera_world;
    wrong.block<3, 1>(0, 3) += Eigen::Vector3d(40, -30, 20);
    const PnpResult misled = solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics,
                                                parameters, {}, &wrong);
    ASSERT_TRUE(misled.success) << misled.failureReason;
    poseDifference(misled.T_camera_world, scene.T_camera_world, rotationDeg, centreMm);
    EXPECT_LT(rotationDeg, 1.0);
    EXPECT_LT(centreMm, 2.0);
  }
  std::printf("re-weighting iterations over %d solves: %d from the weak-perspective start, %d from the guess\n", trials,
              plainIterations, warmIterations);
  EXPECT_LT(warmIterations, 0.7 * plainIterations) << "the guess should shorten the iterations";
  Eigen::Matrix4d notFinite = Eigen::Matrix4d::Identity();
  notFinite(0, 3) = std::numeric_limits<double>::quiet_NaN();
  const SyntheticPnpCase scene = makeSyntheticPnpCase(1, 100, 0.0, 0.0);
  EXPECT_THROW(solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics, parameters, {},
                                  &notFinite),
               Error);
}

// Hypotheses in waves (the refinement's matches after tracking drifted): a wrong guess and 85 % outliers need many
// hypotheses; the waves find the pose as the sequential loop does, the answer does not depend on the thread count,
// and one at a time is the sequential loop exactly.
TEST(PnpSolver, HypothesesInWavesFindThePoseWhateverTheThreadCount) {
  const TrackingParameters parameters;
  for (int trial = 0; trial < 6; ++trial) {
    const SyntheticPnpCase scene = makeSyntheticPnpCase(700 + trial, 400, 0.85, 1.0);
    Eigen::Matrix4d wrong = scene.T_camera_world;
    wrong.block<3, 1>(0, 3) += Eigen::Vector3d(30, -20, 15);
    const auto solve = [&](int atOnce) {
      return solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics, parameters, {},
                                &wrong, atOnce);
    };
    const PnpResult sequential = solve(1);
    const PnpResult waves = solve(8);
    PnpResult oneThread;
    tbb::task_arena(1).execute([&] { oneThread = solve(8); });
    expectPose(sequential, scene.T_camera_world, 1.0, 2.0);
    expectPose(waves, scene.T_camera_world, 1.0, 2.0);
    EXPECT_GT(waves.hypotheses, 1) << "trial " << trial << ": the first hypothesis alone should not do";
    EXPECT_EQ(oneThread.T_camera_world, waves.T_camera_world) << "trial " << trial;
    EXPECT_EQ(oneThread.inlierIndices, waves.inlierIndices) << "trial " << trial;
    EXPECT_EQ(oneThread.hypotheses, waves.hypotheses) << "trial " << trial;
    const PnpResult defaultCall = solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates,
                                                     scene.intrinsics, parameters, {}, &wrong);
    EXPECT_EQ(defaultCall.T_camera_world, sequential.T_camera_world) << "trial " << trial;
    EXPECT_EQ(defaultCall.hypotheses, sequential.hypotheses) << "trial " << trial;
  }
  const SyntheticPnpCase scene = makeSyntheticPnpCase(1, 100, 0.0, 0.0);
  EXPECT_THROW(solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.candidates, scene.intrinsics, parameters, {},
                                  nullptr, 0),
               Error);
}

TEST(PnpSolver, VoteOrderPutsInliersFirst) {
  // With the inliers listed first, the first hypothesis already wins and few hypotheses are needed.
  const SyntheticPnpCase scene = makeSyntheticPnpCase(21, 500, 0.9, 1.0);
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(scene.isInlier.size()); ++i) {
    if (scene.isInlier[i]) order.push_back(i);
  }
  const PnpResult r = solveR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.intrinsics, TrackingParameters(), order);
  expectPose(r, scene.T_camera_world, 1.0, 2.0);
  EXPECT_THROW(solveR1Ppnp(scene.pointsMm, scene.pixelsPx, scene.intrinsics, TrackingParameters(), {500}), Error);
}

TEST(PnpSolver, DegenerateInputIsReportedAsFailure) {
  const TrackingParameters parameters;
  const SyntheticPnpCase scene = makeSyntheticPnpCase(3, 50, 0.0, 0.0);
  auto expectFailure = [&](const Points3d& points, const Pixels2d& pixels, const PinholeIntrinsics& k) {
    PnpResult r;
    EXPECT_NO_THROW(r = solveR1Ppnp(points, pixels, k, parameters));
    EXPECT_FALSE(r.success);
    EXPECT_FALSE(r.failureReason.empty());
    EXPECT_TRUE(r.T_camera_world.isIdentity());
    EXPECT_NO_THROW(r = solveDynamicR1Ppnp(points, pixels, {}, k, parameters));
    EXPECT_FALSE(r.success);
  };
  // Fewer than 4 matches, and none.
  expectFailure(Points3d(scene.pointsMm.begin(), scene.pointsMm.begin() + 3),
                Pixels2d(scene.pixelsPx.begin(), scene.pixelsPx.begin() + 3), scene.intrinsics);
  expectFailure({}, {}, scene.intrinsics);
  // Identical points.
  expectFailure(Points3d(50, scene.pointsMm[0]), scene.pixelsPx, scene.intrinsics);
  // Collinear points.
  Points3d line;
  for (int i = 0; i < 50; ++i) line.push_back(scene.pointsMm[0] + i * Eigen::Vector3d(1, 2, 0.5));
  expectFailure(line, scene.pixelsPx, scene.intrinsics);
  // Non-finite values.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Points3d badPoints = scene.pointsMm;
  badPoints[7].y() = nan;
  expectFailure(badPoints, scene.pixelsPx, scene.intrinsics);
  Pixels2d badPixels = scene.pixelsPx;
  badPixels[3].x() = std::numeric_limits<double>::infinity();
  expectFailure(scene.pointsMm, badPixels, scene.intrinsics);
  PinholeIntrinsics badK = scene.intrinsics;
  badK.fxPx = nan;
  expectFailure(scene.pointsMm, scene.pixelsPx, badK);
  badK.fxPx = 0;
  expectFailure(scene.pointsMm, scene.pixelsPx, badK);
  // Pure noise: no pose gathers the minimum inliers.
  Pixels2d randomPixels;
  for (int i = 0; i < 50; ++i) randomPixels.emplace_back((i * 7919) % 960, (i * 104729) % 540);
  expectFailure(scene.pointsMm, randomPixels, scene.intrinsics);
  // Misuse throws.
  EXPECT_THROW(solveR1Ppnp(scene.pointsMm, Pixels2d(10), scene.intrinsics, parameters), Error);
  EXPECT_THROW(solveDynamicR1Ppnp(scene.pointsMm, scene.pixelsPx, std::vector<std::vector<CandidateMatch>>(3),
                                  scene.intrinsics, parameters),
               Error);
}

TEST(TrackingParameters, DefaultsValidateAndRoundTrip) {
  TrackingParameters p;
  EXPECT_NO_THROW(p.validate());
  EXPECT_EQ(p.inlierThresholdPx, 5.0);
  EXPECT_EQ(p.candidateEta, 2.0);
  EXPECT_EQ(p.candidateRampIterations, 5);
  EXPECT_EQ(p.keyFrameMinInliers, 50);
  EXPECT_EQ(p.keyFrameMinGapFrames, 10);
  EXPECT_EQ(p.keyFramePoseThreshold, 10.0);
  p.inlierThresholdPx = 3.5;
  p.minInliers = 20;
  cv::FileStorage out("tracking.yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  p.write(out);
  const std::string text = out.releaseAndGetString();
  cv::FileStorage in(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  const TrackingParameters back = TrackingParameters::read(in["tracking"]);
  EXPECT_EQ(back.inlierThresholdPx, 3.5);
  EXPECT_EQ(back.minInliers, 20);
  EXPECT_EQ(back.candidateEta, 2.0);
  TrackingParameters bad;
  bad.candidateEta = 0.5;  // eta must exceed 1
  EXPECT_THROW(bad.validate(), Error);
  cv::FileStorage wrongType("%YAML:1.0\ntracking:\n  minInliers: 2.5\n", cv::FileStorage::READ | cv::FileStorage::MEMORY);
  EXPECT_THROW(TrackingParameters::read(wrongType["tracking"]), Error);
}

TEST(PnpBenchmark, QuickRunPrintsOneJsonObjectWithEveryCase) {
  PnpBenchmarkOptions options;
  options.repeats = 2;
  options.quick = true;
  const std::string json = runPnpBenchmark(options);
  cv::FileStorage parsed(json, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_JSON);
  ASSERT_TRUE(parsed.isOpened());
  EXPECT_FALSE(static_cast<std::string>(parsed["device"]).empty());
  EXPECT_EQ(static_cast<int>(parsed["threads"]), 1);
  const cv::FileNode cases = parsed["cases"];
  ASSERT_TRUE(cases.isSeq());
  ASSERT_EQ(cases.size(), 8u);  // 4 methods x 2 outlier ratios x N = 200
  int r1AtHalf = 0;
  for (const cv::FileNode& c : cases) {
    const std::string method = c["method"];
    EXPECT_FALSE(method.empty());
    EXPECT_EQ(static_cast<int>(c["n"]), 200);
    const double rate = c["success_rate"], ms = c["median_ms"], ratio = c["outlier_ratio"];
    EXPECT_GE(rate, 0.0);
    EXPECT_LE(rate, 1.0);
    EXPECT_GT(ms, 0.0);
    EXPECT_TRUE(ratio == 0.5 || ratio == 0.9);
    if (method == "R1PPnP" && ratio == 0.5) r1AtHalf = static_cast<int>(rate * 2 + 0.5);
  }
  EXPECT_EQ(r1AtHalf, 2);  // 50 % outliers: both scenes solved
}
