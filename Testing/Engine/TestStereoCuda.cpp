// The CUDA stereo path against the CPU path (ctest label "cuda"; skipped with a message where no GPU exists).
// Both run the same per-pixel functions on exact integer window sums, so the ZNCC winners and the discrete maps
// after outlier removal and hole filling must be identical, and the refined disparities agree within 0.5 px on at
// least 99.5% of pixels (the bar); in practice they are bit-identical too.
#include "StereoTestUtilities.h"
#include "Core/Error.h"
#include "Core/Buffer.h"
#include "Stereo/StereoMatcher.h"
#include "Stereo/StereoPipeline.h"
#include "Tracking/StereoFeatures.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <tuple>
#include <random>
#include <vector>

using namespace tissuemosaic;

namespace {

struct Agreement {
  double within05 = 0;  ///< share of pixels where both agree within 0.5 px (NaN on both counts as agreement)
  long differentDiscrete = 0;
};

long countDifferent(const cv::Mat& a, const cv::Mat& b) {
  long different = 0;
  for (int i = 0; i < a.rows * a.cols; ++i) {
    const float x = a.at<float>(i), y = b.at<float>(i);
    const bool same = (std::isnan(x) && std::isnan(y)) || x == y;
    different += !same;
  }
  return different;
}

double shareWithin(const cv::Mat& a, const cv::Mat& b, float tolerance) {
  long agree = 0;
  for (int i = 0; i < a.rows * a.cols; ++i) {
    const float x = a.at<float>(i), y = b.at<float>(i);
    agree += (std::isnan(x) && std::isnan(y)) || std::abs(x - y) <= tolerance;
  }
  return static_cast<double>(agree) / (a.rows * a.cols);
}

void compareBackends(const cv::Mat& left, const cv::Mat& right, const StereoParameters& parameters, const char* what) {
  StereoMatcher cpu(Device::Cpu, parameters);
  StereoMatcher gpu(Device::Cuda, parameters);
  const cv::Mat cpuDisparity = cpu.computeDisparity(left, right);
  const cv::Mat gpuDisparity = gpu.computeDisparity(left, right);
  const long znccDifferent = countDifferent(cpu.lastZnccDisparity(), gpu.lastZnccDisparity());
  const long filledDifferent = countDifferent(cpu.lastFilledDisparity(), gpu.lastFilledDisparity());
  const double within = shareWithin(cpuDisparity, gpuDisparity, 0.5f);
  const long finalDifferent = countDifferent(cpuDisparity, gpuDisparity);
  std::printf("%s: ZNCC winners differing %ld, filled differing %ld, final within 0.5 px %.6f (bit-different %ld)\n",
              what, znccDifferent, filledDifferent, within, finalDifferent);
  EXPECT_EQ(znccDifferent, 0);
  EXPECT_EQ(filledDifferent, 0);
  EXPECT_GE(within, 0.995);
}

bool requireCuda() {
  if (cudaAvailable()) return true;
  std::printf("no usable CUDA device: %s\n", cudaUnavailableReason().c_str());
  return false;
}

}  // namespace

TEST(StereoCuda, MatchesCpuOnSyntheticTissuePair) {
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions{});
  compareBackends(pair.leftRectified, pair.rightRectified, StereoParameters{}, "synthetic tissue 960x540, -20..80");
}

TEST(StereoCuda, MatchesCpuBitForBitWithHighlights) {
  // Highlight seeds, their margins and the re-selection that leaves highlights their filled values: the realistic
  // look (glints, bright tissue, clipping) and the standard look (one large highlight), final disparities and the
  // explanation's counts identical.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  for (const auto lighting : {synthetic::SyntheticLighting::Realistic, synthetic::SyntheticLighting::Standard}) {
    synthetic::SyntheticStereoOptions options;
    options.lighting = lighting;
    const auto pair = synthetic::renderSyntheticStereoPair(options);
    const char* what = synthetic::syntheticLightingName(lighting);
    compareBackends(pair.leftRectified, pair.rightRectified, StereoParameters{}, what);
    StereoMatcher cpu(Device::Cpu, StereoParameters{});
    StereoMatcher gpu(Device::Cuda, StereoParameters{});
    StereoExplanation cpuCounts, gpuCounts;
    const cv::Mat cpuDisparity = cpu.computeDisparity(pair.leftRectified, pair.rightRectified, nullptr, &cpuCounts);
    const cv::Mat gpuDisparity = gpu.computeDisparity(pair.leftRectified, pair.rightRectified, nullptr, &gpuCounts);
    std::printf("%s: cpu %s\n     gpu %s\n", what, cpuCounts.json().c_str(), gpuCounts.json().c_str());
    EXPECT_EQ(countDifferent(cpuDisparity, gpuDisparity), 0) << what;
    // What tracking and fusion leave out: the same pixels.
    const cv::Mat cpuNear = cpu.lastHighlightNeighbourhood(), gpuNear = gpu.lastHighlightNeighbourhood();
    EXPECT_GT(cv::countNonZero(cpuNear), 0) << what;
    EXPECT_EQ(cv::countNonZero(cpuNear != gpuNear), 0) << what;
    // The disparity they take, masked on each device: the same bits (NaN where the neighbourhood is).
    const cv::Mat cpuKept = cpu.lastDisparityAwayFromHighlights(), gpuKept = gpu.lastDisparityAwayFromHighlights();
    EXPECT_EQ(countDifferent(cpuKept, gpuKept), 0) << what;
    EXPECT_EQ(cv::countNonZero(cpuKept == cpuKept), cv::countNonZero((cpuDisparity == cpuDisparity) & (cpuNear == 0)))
        << what;
    EXPECT_GT(cpuCounts.highlight, 0) << what;
    EXPECT_EQ(cpuCounts.json(), gpuCounts.json()) << what;
  }
}

TEST(StereoCuda, SamplesTheTrackingDisparityWhereItLiesLikeTheHost) {
  // The pipeline lifts the tracker's features with samples taken on the GPU instead of downloading the map: the
  // same floats as the host rule on the same map, at sub-pixel points, halves, pixel centres, next to holes and
  // highlights, on the border and outside the image.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  synthetic::SyntheticStereoOptions options;
  options.lighting = synthetic::SyntheticLighting::Realistic;  // highlights: NaN neighbourhoods in the map
  const auto pair = synthetic::renderSyntheticStereoPair(options);
  StereoMatcher gpu(Device::Cuda, StereoParameters{});
  gpu.match(pair.leftRectified, pair.rightRectified);
  const cv::Mat map = gpu.lastDisparityAwayFromHighlights();
  std::mt19937 random(5);
  std::uniform_real_distribution<float> x(-3.0f, map.cols + 3.0f), y(-3.0f, map.rows + 3.0f);
  std::vector<cv::Point2f> points;
  for (int i = 0; i < 20000; ++i) points.emplace_back(x(random), y(random));
  for (int i = 0; i < 2000; ++i) points.emplace_back(std::floor(x(random)) + 0.5f, std::floor(y(random)) + 0.5f);
  for (int i = 0; i < 2000; ++i) points.emplace_back(std::floor(x(random)), std::floor(y(random)));
  for (const cv::Point2f corner : {cv::Point2f(0, 0), cv::Point2f(map.cols - 1.0f, map.rows - 1.0f),
                                   cv::Point2f(map.cols - 0.5f, 3.2f), cv::Point2f(-0.5f, -0.5f)}) {
    points.push_back(corner);
  }
  const std::vector<float> onDevice = gpu.sampleLastDisparityAwayFromHighlights(points);
  const std::vector<float> onHost = sampleDisparityMap(map, map.size(), points);
  ASSERT_EQ(onDevice.size(), points.size());
  long different = 0, missing = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    different += std::memcmp(&onDevice[i], &onHost[i], sizeof(float)) != 0;
    missing += std::isnan(onHost[i]);
  }
  std::printf("%zu samples: %ld without an estimate, %ld differing\n", points.size(), missing, different);
  EXPECT_EQ(different, 0);
  EXPECT_GT(missing, 100) << "outside points and highlight neighbourhoods must be among them";
  EXPECT_LT(missing, static_cast<long>(points.size() / 2));
  EXPECT_TRUE(gpu.sampleLastDisparityAwayFromHighlights({}).empty());
}

TEST(StereoCuda, HighlightSeedsMatchCpu) {
  // The seed rule alone on random grey levels crowded near saturation (runs, rings and view tests all taken) with
  // random winners (holes among them), odd sizes, both eyes.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const int width = 131 + 57 * seed, height = 67 + 23 * seed;
    std::mt19937 random(seed);
    const auto grey = [&]() { return static_cast<float>(random() % 3 == 0 ? 200 + random() % 56 : random() % 256); };
    const auto winner = [&]() {
      return static_cast<int16_t>(random() % 9 == 0 ? stereo::kNoDisparity : static_cast<int>(random() % 40) - 5);
    };
    const std::size_t n = static_cast<std::size_t>(width) * height;
    std::vector<float> left(n), right(n);
    std::vector<int16_t> leftWinners(n), rightWinners(n);
    for (std::size_t i = 0; i < n; ++i) {
      left[i] = grey();
      right[i] = grey();
      leftWinners[i] = winner();
      rightWinners[i] = winner();
    }
    const stereo::HighlightRule rule{240.0f, 4 + static_cast<int>(seed), 6, 20.0f, 10.0f};
    std::vector<int16_t> cpuLeft(n), cpuRight(n);
    stereo::detectHighlightSeedsCpu({{left.data(), width, height}, {right.data(), width, height},
                                     {leftWinners.data(), width, height}, {rightWinners.data(), width, height},
                                     {cpuLeft.data(), width, height}, {cpuRight.data(), width, height}, rule});
    Buffer<float> leftDevice(Device::Cuda, n), rightDevice(Device::Cuda, n);
    Buffer<int16_t> leftWinnersDevice(Device::Cuda, n), rightWinnersDevice(Device::Cuda, n);
    Buffer<int16_t> leftSeedsDevice(Device::Cuda, n), rightSeedsDevice(Device::Cuda, n);
    leftDevice.upload(left.data());
    rightDevice.upload(right.data());
    leftWinnersDevice.upload(leftWinners.data());
    rightWinnersDevice.upload(rightWinners.data());
    stereo::detectHighlightSeedsCuda({{leftDevice.data(), width, height}, {rightDevice.data(), width, height},
                                      {leftWinnersDevice.data(), width, height},
                                      {rightWinnersDevice.data(), width, height},
                                      {leftSeedsDevice.data(), width, height}, {rightSeedsDevice.data(), width, height},
                                      rule});
    const std::vector<int16_t> gpuLeft = leftSeedsDevice.toHost(), gpuRight = rightSeedsDevice.toHost();
    long seeds = 0, different = 0;
    for (std::size_t i = 0; i < n; ++i) {
      seeds += (cpuLeft[i] != stereo::kNoDisparity) + (cpuRight[i] != stereo::kNoDisparity);
      different += (cpuLeft[i] != gpuLeft[i]) + (cpuRight[i] != gpuRight[i]);
    }
    std::printf("seeds %dx%d: %ld seeds on the CPU, %ld pixels differ\n", width, height, seeds, different);
    EXPECT_GT(seeds, 20) << "too few seeds for the comparison to mean much";  // 27 at the smallest size
    EXPECT_EQ(different, 0);
  }
}

TEST(StereoCuda, CostVolumeAndBothWinnersMatchCpuEntryForEntry) {
  // The cost volume launcher alone: every score (through each backend's layout) and both views' winners, for every
  // window radius (the paper's has its own unrolled kernel), with narrow and wide disparity ranges that reach past
  // both image borders, on odd sizes. Window statistics from the CPU, so only the volume pass differs.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const std::tuple<int, int, int, int> cases[] = {
      // radius, width, height, first disparity; disparity counts 37 and 300
      {1, 101, 37, -7}, {2, 77, 29, 3}, {3, 150, 45, -40}, {4, 64, 33, 0}, {5, 223, 61, -20},
      {6, 97, 40, 10}, {7, 131, 35, -3}, {8, 90, 47, -60}, {9, 117, 52, 5}};
  for (const auto& [r, width, height, minDisparity] : cases) {
    for (const int disparityCount : {37, 300}) {
      SCOPED_TRACE("radius " + std::to_string(r) + ", " + std::to_string(width) + "x" + std::to_string(height) +
                   ", disparities " + std::to_string(minDisparity) + " + " + std::to_string(disparityCount));
      const cv::Mat texture = test::randomTexture(width, height, static_cast<unsigned>(r));
      cv::Mat leftMat, rightMat;
      texture.convertTo(leftMat, CV_32F);
      test::shiftedView(texture, 6.0 + r, 0.03, -0.02).convertTo(rightMat, CV_32F);
      const std::size_t n = static_cast<std::size_t>(width) * height;
      std::vector<float> left(leftMat.ptr<float>(), leftMat.ptr<float>() + n);
      std::vector<float> right(rightMat.ptr<float>(), rightMat.ptr<float>() + n);
      std::vector<float> sumL(n), normL(n), sumR(n), normR(n);
      stereo::computeWindowStatisticsCpu({left.data(), width, height}, {sumL.data(), width, height},
                                         {normL.data(), width, height}, r, 1.0f);
      stereo::computeWindowStatisticsCpu({right.data(), width, height}, {sumR.data(), width, height},
                                         {normR.data(), width, height}, r, 1.0f);
      std::vector<int16_t> cpuVolume(n * disparityCount), cpuLeft(n), cpuRight(n);
      const auto cpuLayout = stereo::VolumeLayout::rowMajor(width, disparityCount);
      stereo::computeZnccVolumeCpu({{left.data(), width, height}, {right.data(), width, height},
                                    {sumL.data(), width, height}, {normL.data(), width, height},
                                    {sumR.data(), width, height}, {normR.data(), width, height}, r, minDisparity,
                                    disparityCount, cpuVolume.data(), cpuLayout, {cpuLeft.data(), width, height},
                                    {cpuRight.data(), width, height}, nullptr});

      std::vector<Buffer<float>> device;
      for (const std::vector<float>* host : {&left, &right, &sumL, &normL, &sumR, &normR}) {
        device.emplace_back(Device::Cuda, n);
        device.back().upload(host->data());
      }
      Buffer<int16_t> volume(Device::Cuda, n * disparityCount), leftWinners(Device::Cuda, n), rightWinners(Device::Cuda, n);
      Buffer<uint32_t> rightKeys(Device::Cuda, n);
      rightKeys.setZero();
      const auto gpuLayout = stereo::VolumeLayout::sliceMajor(width, height);
      const auto view = [&](int k) { return ImageView<const float>{device[k].data(), width, height}; };
      // Twice on the same keys: the launcher leaves them cleared for the next frame.
      for (int run = 0; run < 2; ++run) {
        stereo::computeZnccVolumeCuda({view(0), view(1), view(2), view(3), view(4), view(5), r, minDisparity,
                                       disparityCount, volume.data(), gpuLayout, {leftWinners.data(), width, height},
                                       {rightWinners.data(), width, height}, rightKeys.data()});
      }
      const std::vector<int16_t> gpuVolume = volume.toHost(), gpuLeft = leftWinners.toHost(),
                                 gpuRight = rightWinners.toHost();
      long differentScores = 0, scored = 0, differentWinners = 0, winners = 0;
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          for (int i = 0; i < disparityCount; ++i) {
            const int16_t expected = cpuVolume[cpuLayout.index(x, y, i)];
            differentScores += expected != gpuVolume[gpuLayout.index(x, y, i)];
            scored += expected != stereo::kNoZncc;
          }
        }
      }
      for (std::size_t k = 0; k < n; ++k) {
        differentWinners += (cpuLeft[k] != gpuLeft[k]) + (cpuRight[k] != gpuRight[k]);
        winners += (cpuLeft[k] != stereo::kNoDisparity) + (cpuRight[k] != stereo::kNoDisparity);
      }
      EXPECT_EQ(differentScores, 0);
      EXPECT_EQ(differentWinners, 0);
      EXPECT_GT(scored, static_cast<long>(n));  // the comparison covers real scores, not only "none"
      EXPECT_GT(winners, static_cast<long>(n));
    }
  }
}

TEST(StereoCuda, MatchesCpuOnWideRangeAndOtherWindows) {
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions::wideDisparity());
  StereoParameters parameters;
  parameters.minDisparityPx = 50;
  parameters.maxDisparityPx = 149;
  compareBackends(pair.leftRectified, pair.rightRectified, parameters, "wide 960x540, 50..149");
  for (int window : {5, 9, 15, 19}) {
    parameters.znccWindowPx = window;
    compareBackends(pair.leftRectified, pair.rightRectified, parameters, ("window " + std::to_string(window)).c_str());
  }
}

TEST(StereoCuda, MatchesCpuOnRandomTexturesAndOddSizes) {
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const int width = 97 + 61 * seed, height = 53 + 17 * seed;
    const cv::Mat left = test::randomTexture(width, height, seed);
    const cv::Mat right = test::shiftedView(left, -3.0 + seed, 0.02 * seed, -0.01);
    StereoParameters parameters;
    parameters.minDisparityPx = -10;
    parameters.maxDisparityPx = 20 + static_cast<int>(seed);
    compareBackends(left, right, parameters, ("random texture seed " + std::to_string(seed)).c_str());
  }
}

TEST(StereoCuda, MatchesCpuFrameAfterFrameOnOneMatcher) {
  // One matcher over a sequence, as the reconstruct pipeline calls it: on CUDA each frame's grey pair is staged in
  // page-locked memory and uploaded while the host goes on, so a frame must never see the previous frame's pixels.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  synthetic::SyntheticStereoOptions options;
  options.width = 320;
  options.height = 180;
  options.seed = 3;
  const auto first = synthetic::renderSyntheticStereoPair(options);
  options.seed = 4;
  const auto second = synthetic::renderSyntheticStereoPair(options);
  cv::Mat secondGreyLeft, secondGreyRight;
  cv::cvtColor(second.leftRectified, secondGreyLeft, cv::COLOR_BGR2GRAY);
  cv::cvtColor(second.rightRectified, secondGreyRight, cv::COLOR_BGR2GRAY);
  ASSERT_EQ(first.leftRectified.type(), CV_8UC3);
  StereoMatcher cpu(Device::Cpu, StereoParameters{});
  StereoMatcher gpu(Device::Cuda, StereoParameters{});
  const std::vector<std::pair<cv::Mat, cv::Mat>> frames = {{first.leftRectified, first.rightRectified},
                                                           {second.leftRectified, second.rightRectified},
                                                           {first.leftRectified, first.rightRectified},
                                                           {secondGreyLeft, secondGreyRight}};
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat expected = cpu.computeDisparity(frames[i].first, frames[i].second);
    const cv::Mat computed = gpu.computeDisparity(frames[i].first, frames[i].second);
    std::printf("frame %zu: within 0.5 px %.6f, bit-different %ld\n", i, shareWithin(expected, computed, 0.5f),
                countDifferent(expected, computed));
    EXPECT_EQ(countDifferent(cpu.lastZnccDisparity(), gpu.lastZnccDisparity()), 0) << "frame " << i;
    EXPECT_GE(shareWithin(expected, computed, 0.5f), 0.995) << "frame " << i;
  }
  // The two scenes differ, so a frame computed from the other frame's pixels would have failed above: its share
  // within 0.5 px is below the 0.995 asked there (0.900 measured).
  EXPECT_LT(shareWithin(cpu.computeDisparity(first.leftRectified, first.rightRectified),
                        cpu.computeDisparity(second.leftRectified, second.rightRectified), 0.5f),
            0.99);
}

TEST(StereoCuda, AdCensusMatchesCpuBitForBit) {
  // AD-Census works on integer costs throughout (tabulated robust functions, exact sums), so the winners and the
  // final disparities must be identical, not only close.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  StereoParameters parameters;
  parameters.method = StereoMethod::AdCensus;
  synthetic::SyntheticStereoOptions options;
  options.width = 480;
  options.height = 270;
  const auto pair = synthetic::renderSyntheticStereoPair(options);
  parameters.minDisparityPx = -10;
  parameters.maxDisparityPx = 40;
  const auto check = [&](const cv::Mat& left, const cv::Mat& right, const char* what) {
    StereoMatcher cpu(Device::Cpu, parameters);
    StereoMatcher gpu(Device::Cuda, parameters);
    const cv::Mat cpuDisparity = cpu.computeDisparity(left, right);
    const cv::Mat gpuDisparity = gpu.computeDisparity(left, right);
    const long winners = countDifferent(cpu.lastZnccDisparity(), gpu.lastZnccDisparity());
    const long final = countDifferent(cpuDisparity, gpuDisparity);
    std::printf("AD-Census %s: winners differing %ld, final differing %ld\n", what, winners, final);
    EXPECT_EQ(winners, 0) << what;
    EXPECT_EQ(final, 0) << what;
  };
  check(pair.leftRectified, pair.rightRectified, "synthetic tissue 480x270, -10..40");
  const cv::Mat left = test::randomTexture(211, 97, 9);
  parameters.minDisparityPx = -3;
  parameters.maxDisparityPx = 17;
  parameters.aggregationIterations = 3;  // a vertical-first round too
  check(left, test::shiftedView(left, 6.3, 0.01, -0.02), "random texture 211x97, -3..17");
}

TEST(StereoCuda, ScanlinePathsMatchCpuBitForBit) {
  // The GPU's warp-per-path launcher against the CPU's thread-per-path one on random costs and grey steps, for
  // disparity counts that fill one lane slot, leave lanes idle, and need 2, 4 and 16 slots per lane.
  if (!requireCuda()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const stereo::PathPenalties penalties{{1024, 256, 102}, {3072, 768, 307}};
  for (const auto& [width, height, count] : {std::tuple{37, 23, 32}, std::tuple{53, 19, 7}, std::tuple{41, 29, 101},
                                             std::tuple{23, 31, 300}}) {
    const stereo::VolumeGeometry g{width, height, -count / 4, count};
    std::mt19937 random(static_cast<unsigned>(count));
    std::vector<uint8_t> left(g.pixelCount()), right(g.pixelCount());
    for (auto* image : {&left, &right})
      for (auto& grey : *image) grey = static_cast<uint8_t>(std::uniform_int_distribution<int>(0, 40)(random));
    std::vector<int32_t> cost(g.elementCount());
    for (auto& c : cost) c = std::uniform_int_distribution<int>(0, 2048)(random);
    std::vector<int32_t> cpuPaths(g.elementCount());
    stereo::computeScanlinePathsCpu(stereo::ScanlineInputs{g, {left.data(), width, height}, {right.data(), width, height},
                                                           cost.data(), cpuPaths.data(), penalties, 15});
    Buffer<uint8_t> leftDevice(Device::Cuda, left.size()), rightDevice(Device::Cuda, right.size());
    Buffer<int32_t> costDevice(Device::Cuda, cost.size()), pathsDevice(Device::Cuda, cost.size());
    leftDevice.upload(left.data());
    rightDevice.upload(right.data());
    costDevice.upload(cost.data());
    stereo::computeScanlinePathsCuda(stereo::ScanlineInputs{g, {leftDevice.data(), width, height},
                                                            {rightDevice.data(), width, height}, costDevice.data(),
                                                            pathsDevice.data(), penalties, 15});
    std::vector<int32_t> gpuPaths(g.elementCount());
    pathsDevice.download(gpuPaths.data());
    long different = 0;
    for (std::size_t e = 0; e < gpuPaths.size(); ++e) different += gpuPaths[e] != cpuPaths[e];
    std::printf("scanline paths %dx%d x %d disparities: %ld of %zu elements differ\n", width, height, count, different,
                gpuPaths.size());
    EXPECT_EQ(different, 0) << width << "x" << height << " x " << count;
  }
}
