// The whole reconstruction (paper sections II-III) on a shortened synthetic scan, against its ground truth: the
// issue's accuracy bar (model RMSE <= 0.5 mm to the true surface, key-frame ATE <= 1 mm, tracking never lost), the
// timing table's stages, the one parameter object's file round trip, and misuse reported as errors.
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "Reconstruction/TimingTable.h"
#include "Stereo/DisparityRangeEstimator.h"
#include "StereoTestUtilities.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

using namespace tissuemosaic;

TEST(ReconstructionPipeline, ShortSyntheticScanMeetsTheAccuracyBar) {
  synthetic::SyntheticScanOptions options;  // 960x540, the resolution
  options.frames = 36;
  options.seed = 7;
  const synthetic::SyntheticScan scan(options);
  ReconstructionPipeline pipeline(scan.geometry(), ReconstructionParameters{}, Device::Cpu, scan.T_world_camera(0));
  TimingTable timing;
  int lost = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    const FrameResult result = pipeline.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    lost += !result.tracked;
    if (k > 0) timing.add(result);
  }
  EXPECT_EQ(lost, 0);
  ASSERT_GE(pipeline.keyFrames().size(), 3u);

  double positionError2 = 0;
  for (const KeyFramePose& k : pipeline.keyFrames()) {
    positionError2 += (k.T_world_camera.block<3, 1>(0, 3) - scan.T_world_camera(k.frameIndex).block<3, 1>(0, 3)).squaredNorm();
  }
  const double ateMm = std::sqrt(positionError2 / pipeline.keyFrames().size());
  // Requirement: the 1 mm; regression: twice the 0.071 mm measured when the bound was set (2026-11-25).
  EXPECT_LE(ateMm, 1.0);
  EXPECT_LE(ateMm, 2 * 0.071);

  const ModelPoints model = pipeline.modelSnapshot();
  ASSERT_GT(model.size(), 100000u);
  ASSERT_EQ(model.cloud.normals.size(), model.size());
  ASSERT_EQ(model.cloud.colorsRgb.size(), model.size());
  double distance2 = 0;
  std::vector<double> distances;
  for (const cv::Point3f& p : model.cloud.pointsMm) {
    const double d = scan.surface().distanceMm(p.x, p.y, p.z);
    distance2 += d * d;
    distances.push_back(d);
  }
  std::sort(distances.begin(), distances.end());
  const auto at = [&](double q) { return distances[static_cast<std::size_t>(q * (distances.size() - 1))]; };
  std::printf("distances: p50 %.3f p90 %.3f p99 %.3f p999 %.3f max %.3f mm\n", at(0.5), at(0.9), at(0.99), at(0.999), at(1.0));
  const double rmseMm = std::sqrt(distance2 / model.size());
  // Requirement: the 0.5 mm; regression: twice the 0.322 mm measured then lies beyond it, so it binds.
  EXPECT_LE(rmseMm, 0.5);
  std::printf("short scan: %zu key frames, ATE %.3f mm, model %zu points, RMSE %.3f mm\n", pipeline.keyFrames().size(),
              ateMm, model.size(), rmseMm);

  // Key frames ran every stage; other frames no refinement or fusion.
  const std::vector<double> key = timing.medians(true), other = timing.medians(false);
  const auto& names = TimingTable::stageNames();
  for (std::size_t i = 1; i < names.size(); ++i) {
    if (names[i] == "deformation") EXPECT_EQ(key[i], 0.0) << "fusion.deformation is off by default";
    else EXPECT_GT(key[i], 0.0) << names[i];
  }
  EXPECT_EQ(other[5], 0.0);  // refinement
  EXPECT_EQ(other[6], 0.0);  // TSDF
}

TEST(ReconstructionPipeline, TheAutomaticRangeIsMeasuredEveryFewFramesBesideThemTheSameOnEveryRun) {
  // Every third frame is measured on a thread of its own and decides the range from three frames later on: no frame
  // waits for a measurement in the normal course, and the ranges depend on the frames alone.
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 180;
  options.frames = 14;
  options.supersampling = 1;
  options.distanceProfile = synthetic::WorkingDistanceProfile::Approaching;  // the range has to follow
  options.minWorkingDistanceMm = 60;
  options.maxWorkingDistanceMm = 100;
  options.fps = 10;
  const synthetic::SyntheticScan scan(options);
  ReconstructionParameters parameters;
  ASSERT_EQ(parameters.stereo.disparityRangeMode, DisparityRangeMode::Automatic);
  const DisparityRangeEstimatorOptions estimator;
  ASSERT_EQ(estimator.sampleEveryFrames, 3);
  std::vector<std::vector<DisparityRange>> runs;
  for (int run = 0; run < 2; ++run) {
    ReconstructionPipeline pipeline(scan.geometry(), parameters, Device::Cpu, scan.T_world_camera(0));
    std::vector<DisparityRange> ranges;
    for (int k = 0; k < scan.frameCount(); ++k) {
      const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
      const FrameResult result = pipeline.process(frame.leftRectified, frame.rightRectified, frame.timeS);
      ranges.push_back(result.disparityRange);
      // Measured: frame 0 before its stereo; frames 3, 6, 9 beside the frames after them, applied at 6, 9 and 12.
      const bool applies = k == 0 || (k >= 6 && k % 3 == 0);
      EXPECT_EQ(result.disparityRangeMs > 0, applies) << "frame " << k;
      if (k > 0 && k % 3 != 0) EXPECT_EQ(result.disparityRange, ranges[k - 1]) << "frame " << k;
      // The true disparities of the frame lie within its range.
      double low = 1e9, high = -1e9;
      for (int v = 0; v < frame.depthMm.rows; v += 4) {
        for (int u = 0; u < frame.depthMm.cols; u += 4) {
          const float z = frame.depthMm.at<float>(v, u);
          if (!std::isfinite(z)) continue;
          const double d = scan.geometry().focalPx * scan.geometry().baselineMm / z;
          low = std::min(low, d);
          high = std::max(high, d);
        }
      }
      EXPECT_LE(result.disparityRange.minPx, low) << "frame " << k;
      EXPECT_GE(result.disparityRange.maxPx, high) << "frame " << k;
    }
    runs.push_back(ranges);
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_NE(runs[0].front(), runs[0].back()) << "the approach should have moved the range";
}

TEST(ReconstructionPipeline, WithoutTheFrameDisparityTheSameFramesGiveTheSameResults) {
  // `reconstruct` and the benchmark keep no per-frame map (setFrameDisparityKept(false)): the surface of a key frame
  // is then measured from the matcher's own map. Poses and model must be those of a pipeline that downloads every
  // map, and the map must still come on demand.
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 180;
  options.frames = 12;
  options.supersampling = 1;
  const synthetic::SyntheticScan scan(options);
  ReconstructionPipeline kept(scan.geometry(), ReconstructionParameters{}, Device::Cpu, scan.T_world_camera(0));
  ReconstructionPipeline notKept(scan.geometry(), ReconstructionParameters{}, Device::Cpu, scan.T_world_camera(0));
  notKept.setFrameDisparityKept(false);
  EXPECT_THROW(notKept.downloadLastDisparity(), Error);
  int keyFrames = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    const FrameResult a = kept.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    const FrameResult b = notKept.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    ASSERT_FALSE(a.disparityPx.empty());
    EXPECT_TRUE(b.disparityPx.empty()) << "frame " << k;
    EXPECT_TRUE(test::sameDisparity(a.disparityPx, notKept.downloadLastDisparity())) << "frame " << k;
    ASSERT_EQ(a.keyFrame, b.keyFrame) << "frame " << k;
    EXPECT_TRUE(a.T_world_camera == b.T_world_camera) << "frame " << k;
    keyFrames += a.keyFrame;
  }
  EXPECT_GE(keyFrames, 2);
  const ModelPoints fromKept = kept.modelSnapshot(), fromNotKept = notKept.modelSnapshot();
  ASSERT_GT(fromKept.size(), 10000u);
  ASSERT_EQ(fromKept.size(), fromNotKept.size());
  EXPECT_EQ(fromKept.cloud.pointsMm, fromNotKept.cloud.pointsMm);
  EXPECT_EQ(fromKept.cloud.colorsRgb, fromNotKept.cloud.colorsRgb);
}

TEST(ReconstructionPipeline, RgbFramesGiveTheirBgrTwinsResultsWithoutACopy) {
  // Python gives RGB frames: the pipeline reads them in that order (grey for stereo, range and tracking with the same
  // weights, the model's colours swapped where they are sampled) instead of the caller converting both frames. Every
  // pose, the ranges and the model, colours included, must be the BGR frames' bit for bit.
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 180;
  options.frames = 12;
  options.supersampling = 1;
  const synthetic::SyntheticScan scan(options);
  ReconstructionPipeline fromBgr(scan.geometry(), ReconstructionParameters{}, Device::Cpu, scan.T_world_camera(0));
  ReconstructionPipeline fromRgb(scan.geometry(), ReconstructionParameters{}, Device::Cpu, scan.T_world_camera(0));
  int keyFrames = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    cv::Mat leftRgb, rightRgb;
    cv::cvtColor(frame.leftRectified, leftRgb, cv::COLOR_BGR2RGB);
    cv::cvtColor(frame.rightRectified, rightRgb, cv::COLOR_BGR2RGB);
    const FrameResult a = fromBgr.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    const FrameResult b = fromRgb.process(leftRgb, rightRgb, frame.timeS, ChannelOrder::Rgb);
    EXPECT_EQ(a.channelOrder, ChannelOrder::Bgr);
    EXPECT_EQ(b.channelOrder, ChannelOrder::Rgb);
    EXPECT_EQ(b.leftRectified.data, leftRgb.data) << "rectified RGB frames are used as they are, not copied";
    EXPECT_TRUE(test::sameDisparity(a.disparityPx, b.disparityPx)) << "frame " << k;
    EXPECT_EQ(a.disparityRange.minPx, b.disparityRange.minPx) << "frame " << k;
    EXPECT_EQ(a.disparityRange.maxPx, b.disparityRange.maxPx) << "frame " << k;
    ASSERT_EQ(a.status, b.status) << "frame " << k;
    ASSERT_EQ(a.keyFrame, b.keyFrame) << "frame " << k;
    EXPECT_EQ(a.inliers, b.inliers) << "frame " << k;
    EXPECT_TRUE(a.T_world_camera == b.T_world_camera) << "frame " << k;
    keyFrames += a.keyFrame;
  }
  EXPECT_GE(keyFrames, 2);
  const ModelPoints bgr = fromBgr.modelSnapshot(), rgb = fromRgb.modelSnapshot();
  ASSERT_GT(bgr.size(), 10000u);
  ASSERT_EQ(bgr.size(), rgb.size());
  EXPECT_EQ(bgr.cloud.pointsMm, rgb.cloud.pointsMm);
  EXPECT_EQ(bgr.cloud.normals, rgb.cloud.normals);
  EXPECT_EQ(bgr.cloud.colorsRgb, rgb.cloud.colorsRgb);
  // The colours are the scene's, not the swapped channels': the synthetic tissue is red, not blue.
  double red = 0, blue = 0;
  for (const cv::Vec3b& c : rgb.cloud.colorsRgb) red += c[0], blue += c[2];
  EXPECT_GT(red, blue);
}

TEST(ReconstructionPipeline, RefusesMismatchedFrames) {
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 180;
  options.frames = 2;
  const synthetic::SyntheticScan scan(options);
  ReconstructionPipeline pipeline(scan.geometry(), ReconstructionParameters{}, Device::Cpu);
  const cv::Mat small(90, 160, CV_8UC3, cv::Scalar::all(100));
  const cv::Mat right(180, 320, CV_8UC3, cv::Scalar::all(100));
  EXPECT_THROW(pipeline.process(small, right, 0), Error);
  EXPECT_THROW(pipeline.process(cv::Mat(), right, 0), Error);
  EXPECT_THROW(pipeline.process(cv::Mat(180, 320, CV_32FC1, cv::Scalar(0)), right, 0), Error);
}

TEST(ReconstructionParameters, FileRoundTripAndValidation) {
  ReconstructionParameters p;
  p.stereo.maxDisparityPx = 60;
  p.features.maxFeatures = 1500;
  p.tracking.keyFramePoseThreshold = 7.5;
  p.refinement.icpWeightFactor = 0.2;
  p.fusion.truncationMm = 1.0;
  p.extractor = FeatureExtractor::OpenCvOrb;
  const std::string path = (std::filesystem::temp_directory_path() / "tm_reconstruction_parameters.yml").string();
  p.writeFile(path);
  const ReconstructionParameters q = ReconstructionParameters::readFile(path);
  EXPECT_EQ(q.stereo.maxDisparityPx, 60);
  EXPECT_EQ(q.features.maxFeatures, 1500);
  EXPECT_DOUBLE_EQ(q.tracking.keyFramePoseThreshold, 7.5);
  EXPECT_DOUBLE_EQ(q.refinement.icpWeightFactor, 0.2);
  EXPECT_DOUBLE_EQ(q.fusion.truncationMm, 1.0);
  EXPECT_EQ(q.extractor, FeatureExtractor::OpenCvOrb);

  // Missing nodes keep the defaults; a bad value names its group and parameter.
  const ReconstructionParameters defaults = ReconstructionParameters::parse("%YAML:1.0\n---\nstereo:\n   maxDisparityPx: 70\n");
  EXPECT_EQ(defaults.stereo.maxDisparityPx, 70);
  EXPECT_DOUBLE_EQ(defaults.fusion.truncationMm, FusionParameters{}.truncationMm);
  try {
    ReconstructionParameters::parse("%YAML:1.0\n---\nfusion:\n   truncationMm: -1\n");
    FAIL() << "a negative truncation was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("truncationMm"), std::string::npos) << error.what();
  }
  EXPECT_THROW(ReconstructionParameters::parse("%YAML:1.0\n---\npipeline:\n   extractor: sift\n"), Error);
  EXPECT_THROW(ReconstructionParameters::readFile("/nonexistent/parameters.yml"), Error);
}
