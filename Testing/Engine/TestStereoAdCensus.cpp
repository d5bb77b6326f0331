// The AD-Census matcher's steps (AdCensusKernels.h) on inputs checked by hand or by brute force, and the whole
// method on a pair with a known shift.
#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "StereoTestUtilities.h"
#include "Stereo/AdCensusKernels.h"
#include "Stereo/StereoMatcher.h"
#include "Stereo/StereoPipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

using namespace tissuemosaic;
using namespace tissuemosaic::stereo;

namespace {

ImageView<const uint8_t> view(const std::vector<uint8_t>& pixels, int width, int height) {
  return {pixels.data(), width, height};
}

/// Random grey image with flat patches (so that arms vary from 0 to their longest).
std::vector<uint8_t> patchyGrey(int width, int height, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<uint8_t> grey(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int patch = ((x / 5) * 7 + (y / 4) * 13 + static_cast<int>(seed)) % 5;
      grey[static_cast<std::size_t>(y) * width + x] =
          static_cast<uint8_t>(patch < 3 ? 40 * patch + 30 : std::uniform_int_distribution<int>(0, 255)(random));
    }
  return grey;
}

}  // namespace

TEST(StereoAdCensus, CensusBitsFollowTheWindowOrder) {
  // 3x3 window on a 3x3 image: neighbours darker than the centre (50) set their bit, first pixel highest.
  const std::vector<uint8_t> grey = {10, 90, 20,   //
                                     60, 50, 40,   //
                                     50, 70, 30};
  std::vector<uint64_t> census(9);
  CensusTransform{view(grey, 3, 3), census.data(), 1, 1}(4);
  // order: (-1,-1)=10 (-0,-1)=90 (1,-1)=20 (-1,0)=60 (1,0)=40 (-1,1)=50 (0,1)=70 (1,1)=30
  EXPECT_EQ(census[4], 0b10101001u);
  // The corner pixel (0,0) = 10 sees replicated borders: nothing is darker than 10.
  CensusTransform{view(grey, 3, 3), census.data(), 1, 1}(0);
  EXPECT_EQ(census[0], 0u);
}

TEST(StereoAdCensus, ArmsStopAtStepsAndAtTheStricterLongRule) {
  // One row: 100 for x < 6, then 200; a slow ramp after x = 6 (steps of 1 grey level).
  const int width = 40;
  std::vector<uint8_t> grey(width);
  for (int x = 0; x < width; ++x) grey[x] = static_cast<uint8_t>(x < 6 ? 100 : 200 + (x - 6));
  const CrossArms arms{view(grey, width, 1), nullptr, 34, 17, 20, 6};
  EXPECT_EQ(arms.reach(2, 0, 1, 0), 3);   // x = 3, 4, 5; x = 6 is 100 levels brighter
  EXPECT_EQ(arms.reach(2, 0, -1, 0), 2);  // the image ends
  EXPECT_EQ(arms.reach(6, 0, -1, 0), 0);
  // From x = 6 the ramp differs from the anchor by s at step s: within the first 17 steps only tau1 = 20 applies,
  // beyond them the difference must stay below tau2 = 6, which step 18 (difference 18) fails.
  EXPECT_EQ(arms.reach(6, 0, 1, 0), 17);
  EXPECT_EQ(arms.reach(0, 0, 0, 1), 0);  // one row: no vertical reach
}

TEST(StereoAdCensus, AggregationRoundEqualsBruteForceCrossSums) {
  const int width = 23, height = 17, count = 5, minDisparity = -1;
  const VolumeGeometry g{width, height, minDisparity, count};
  const std::vector<uint8_t> left = patchyGrey(width, height, 1), right = patchyGrey(width, height, 2);
  std::vector<uint8_t> leftArms(4 * width * height), rightArms(4 * width * height);
  parallelFor<CpuBackend>(g.pixelCount(), CrossArms{view(left, width, height), leftArms.data(), 6, 3, 20, 6});
  parallelFor<CpuBackend>(g.pixelCount(), CrossArms{view(right, width, height), rightArms.data(), 6, 3, 20, 6});
  std::mt19937 random(7);
  std::vector<int32_t> cost(g.elementCount());
  for (auto& c : cost) c = std::uniform_int_distribution<int>(0, 2048)(random);

  for (bool horizontalFirst : {true, false}) {
    // Brute force: first-pass sums and counts over the first arm, then second-pass sums of those over the other.
    const auto at = [&](int x, int y, int i) { return (static_cast<int64_t>(y) * width + x) * count + i; };
    std::vector<int64_t> firstSum(g.elementCount()), firstCount(g.elementCount());
    std::vector<int32_t> expected(g.elementCount());
    for (int pass = 0; pass < 2; ++pass) {
      const bool horizontal = (pass == 0) == horizontalFirst;
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          for (int i = 0; i < count; ++i) {
            const int before = combinedArm(leftArms.data(), rightArms.data(), horizontal ? kArmLeft : kArmUp, g, x, y, i);
            const int after = combinedArm(leftArms.data(), rightArms.data(), horizontal ? kArmRight : kArmDown, g, x, y, i);
            int64_t sum = 0, n = 0;
            for (int s = -before; s <= after; ++s) {
              const int64_t e = horizontal ? at(x + s, y, i) : at(x, y + s, i);
              sum += pass == 0 ? cost[e] : firstSum[e];
              n += pass == 0 ? 1 : firstCount[e];
            }
            if (pass == 0) {
              firstSum[at(x, y, i)] = sum;
              firstCount[at(x, y, i)] = n;
            } else {
              expected[at(x, y, i)] = static_cast<int32_t>(sum / n);
            }
          }
    }
    // The kernels in both forms: the CPU's (prefix sums and windows by blocks of lines) and the GPU's (prefix sums
    // per line and disparity, windows per element).
    for (bool perLine : {true, false}) {
      std::vector<int32_t> aggregated = cost;
      std::vector<int64_t> packed(g.elementCount()), prefix(static_cast<std::size_t>(width + 1) * (height + 1) * count);
      for (int pass = 0; pass < 2; ++pass) {
        const AggregationLines lines{g, (pass == 0) == horizontalFirst};
        const PrefixAlongLines prefixPass{lines, pass == 0 ? aggregated.data() : nullptr,
                                          pass == 0 ? nullptr : packed.data(), prefix.data()};
        if (perLine) {
          for (int line = 0; line < lines.lineCount(); line += 3) {
            prefixPass.lineBlock(line, std::min(line + 3, lines.lineCount()));  // blocks of 3, the last shorter
          }
        } else {
          for (int64_t k = 0; k < static_cast<int64_t>(lines.lineCount()) * count; ++k) prefixPass(k);
        }
        const WindowAlongLines window{lines, leftArms.data(), rightArms.data(), prefix.data(),
                                      pass == 0 ? packed.data() : nullptr, pass == 0 ? nullptr : aggregated.data()};
        if (perLine) {
          for (int line = 0; line < lines.lineCount(); line += 3) {
            window.lineBlock(line, std::min(line + 3, lines.lineCount()));
          }
        } else {
          for (int64_t e = 0; e < g.elementCount(); ++e) VolumeElements<WindowAlongLines>{g, window}(e);
        }
      }
      EXPECT_EQ(aggregated, expected) << (horizontalFirst ? "horizontal first" : "vertical first")
                                      << (perLine ? ", CPU forms" : ", GPU forms");
    }
  }
}

TEST(StereoAdCensus, ScanlinePathsEqualTheRecurrenceWrittenOut) {
  const int width = 19, height = 11, count = 7, minDisparity = -2;
  const VolumeGeometry g{width, height, minDisparity, count};
  const std::vector<uint8_t> left = patchyGrey(width, height, 3), right = patchyGrey(width, height, 4);
  std::mt19937 random(11);
  std::vector<int32_t> cost(g.elementCount());
  for (auto& c : cost) c = std::uniform_int_distribution<int>(0, 2048)(random);
  const PathPenalties penalties{{1024, 256, 102}, {3072, 768, 307}};
  const int edgeGrey = 15;
  std::vector<int32_t> pathCost(g.elementCount(), -1);  // the first direction must overwrite, not add
  computeScanlinePathsCpu(ScanlineInputs{g, view(left, width, height), view(right, width, height), cost.data(),
                                         pathCost.data(), penalties, edgeGrey});
  const int directions[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  // The recurrence written out per element, each direction kept as its own volume.
  const auto at = [&](int x, int y, int i) { return (static_cast<int64_t>(y) * width + x) * count + i; };
  std::vector<int64_t> expected(g.elementCount(), 0);
  for (const auto& direction : directions) {
    const int dx = direction[0], dy = direction[1];
    std::vector<int64_t> L(g.elementCount());
    const int length = dx != 0 ? width : height, paths = dx != 0 ? height : width;
    for (int p = 0; p < paths; ++p)
      for (int s = 0; s < length; ++s) {
        const int step = (dx > 0 || dy > 0) ? s : length - 1 - s;
        const int x = dx != 0 ? step : p, y = dx != 0 ? p : step;
        if (s == 0) {
          for (int i = 0; i < count; ++i) L[at(x, y, i)] = cost[at(x, y, i)];
          continue;
        }
        const int px = x - dx, py = y - dy;
        int64_t previousMin = L[at(px, py, 0)];
        for (int i = 1; i < count; ++i) previousMin = std::min(previousMin, L[at(px, py, i)]);
        for (int i = 0; i < count; ++i) {
          const int d = minDisparity + i;
          const bool leftEdge = std::abs(left[y * width + x] - left[py * width + px]) >= edgeGrey;
          const bool inside = x - d >= 0 && x - d < width && px - d >= 0 && px - d < width;
          const bool rightEdge = !inside || std::abs(right[y * width + x - d] - right[py * width + px - d]) >= edgeGrey;
          const int edges = leftEdge + rightEdge;
          int64_t best = L[at(px, py, i)];
          if (i > 0) best = std::min<int64_t>(best, L[at(px, py, i - 1)] + penalties.small[edges]);
          if (i + 1 < count) best = std::min<int64_t>(best, L[at(px, py, i + 1)] + penalties.small[edges]);
          best = std::min<int64_t>(best, previousMin + penalties.large[edges]);
          L[at(x, y, i)] = cost[at(x, y, i)] + best - previousMin;
        }
      }
    for (int64_t e = 0; e < g.elementCount(); ++e) expected[e] += L[e];
  }
  for (int64_t e = 0; e < g.elementCount(); ++e) ASSERT_EQ(pathCost[e], expected[e]) << "element " << e;
}

TEST(StereoAdCensus, WinnersTakeTheLowestDisparityAndTheParabolaVertex) {
  const int width = 4, height = 1, count = 5, minDisparity = 1;
  const VolumeGeometry g{width, height, minDisparity, count};
  std::vector<int32_t> pathCost(g.elementCount(), 1000);
  // Pixel 3: the parabola 160 (i - 2.25)^2 + 0 sampled at i = 1, 2, 3 -> 250, 10, 90: vertex at i = 2.25.
  pathCost[3 * count + 1] = 250;
  pathCost[3 * count + 2] = 10;
  pathCost[3 * count + 3] = 90;
  // Pixel 2: a tie between i = 1 and i = 3: the lower disparity wins; the curvature there is negative: no offset.
  pathCost[2 * count + 1] = 5;
  pathCost[2 * count + 3] = 5;
  std::vector<int16_t> leftDisparity(width), rightDisparity(width);
  std::vector<float> subpixel(width);
  const AdCensusWinners winners{g, pathCost.data(), {leftDisparity.data(), width, height},
                                {rightDisparity.data(), width, height}, {subpixel.data(), width, height}};
  for (int x = 0; x < width; ++x) winners(x);
  EXPECT_EQ(leftDisparity[3], 3);
  EXPECT_FLOAT_EQ(subpixel[3], 3.25f);
  EXPECT_EQ(leftDisparity[2], 2);
  EXPECT_FLOAT_EQ(subpixel[2], 2.0f);
  // Pixel 0 costs 1000 everywhere: no winner (a uniform patch says nothing about its disparity; issue 32); its
  // sub-pixel value is minDisparity's (i = 0) without offset, dropped at the end.
  EXPECT_EQ(leftDisparity[0], kNoDisparity);
  EXPECT_FLOAT_EQ(subpixel[0], 1.0f);
  // Right pixel 0 sees left pixels 0 + d for d = 1..3 (4 and 5 fall outside): left pixel 1 at d = 1 (i = 0) costs
  // 1000, left pixel 2 at d = 2 (i = 1) costs 5, left pixel 3 at d = 3 (i = 2) costs 10 -> d = 2.
  EXPECT_EQ(rightDisparity[0], 2);
  // Right pixel 1: left pixel 2 at d = 1 (i = 0) costs 1000, left pixel 3 at d = 2 (i = 1) costs 250 -> d = 2.
  EXPECT_EQ(rightDisparity[1], 2);
  // Right pixel 3: every left pixel 3 + d is outside the image.
  EXPECT_EQ(rightDisparity[3], kNoDisparity);
}

TEST(StereoAdCensus, MedianOfNineWithReplicatedBorders) {
  std::vector<float> input = {9, 1, 5,  //
                              3, 7, 2,  //
                              8, 4, 6};
  std::vector<float> output(9);
  const Median3x3 median{{input.data(), 3, 3}, {output.data(), 3, 3}};
  for (int i = 0; i < 9; ++i) median(i);
  EXPECT_FLOAT_EQ(output[4], 5.0f);
  // Corner (0, 0): replicated window 9 9 1 / 9 9 1 / 3 3 7 -> sorted 1 1 3 3 7 9 9 9 9 -> 7.
  EXPECT_FLOAT_EQ(output[0], 7.0f);
}

TEST(StereoAdCensus, RecoversAKnownShift) {
  // A random texture and its copy shifted by 4.5 px: AD-Census finds it to within 1 px on
  // nearly every pixel with an estimate.
  const cv::Mat left = test::randomTexture(160, 96, 5);
  const cv::Mat right = test::shiftedView(left, 4.5, 0.0, 0.0);
  StereoParameters parameters;
  parameters.method = StereoMethod::AdCensus;
  parameters.minDisparityPx = -4;
  parameters.maxDisparityPx = 16;
  StereoMatcher matcher(Device::Cpu, parameters);
  const cv::Mat disparity = matcher.computeDisparity(left, right);
  long estimated = 0, within = 0, inside = 0;
  for (int y = 8; y < left.rows - 8; ++y)
    for (int x = 24; x < left.cols - 8; ++x) {
      ++inside;
      const float d = disparity.at<float>(y, x);
      if (std::isnan(d)) continue;
      ++estimated;
      within += std::abs(d - 4.5f) <= 1.0f;
    }
  std::printf("estimated %.4f, within 1 px %.4f\n", double(estimated) / inside, double(within) / estimated);
  EXPECT_GE(double(estimated) / inside, 0.95);
  EXPECT_GE(double(within) / estimated, 0.98);
}

// Issue 32: an all-black pair gave "93.8 % estimated", every value the range's minimum. Uniform images carry no
// disparity: nothing is estimated, with the left-right check on or off. A textured control keeps its estimates.
TEST(StereoAdCensus, UniformPairGivesNoEstimate) {
  for (const int leftRightMaxDifferencePx : {1, -1}) {
    StereoParameters parameters;
    parameters.method = StereoMethod::AdCensus;
    parameters.minDisparityPx = -20;
    parameters.maxDisparityPx = 40;
    parameters.leftRightMaxDifferencePx = leftRightMaxDifferencePx;
    StereoMatcher matcher(Device::Cpu, parameters);
    for (const int grey : {0, 128, 255}) {
      const cv::Mat uniform(90, 160, CV_8UC3, cv::Scalar::all(grey));
      const cv::Mat disparity = matcher.computeDisparity(uniform, uniform);
      EXPECT_EQ(cv::countNonZero(disparity == disparity), 0)
          << "grey " << grey << ", left-right check " << leftRightMaxDifferencePx;
    }
    const cv::Mat texture = test::randomTexture(160, 90, 5);
    const cv::Mat textured = matcher.computeDisparity(texture, test::shiftedView(texture, 4.5, 0.0, 0.0));
    EXPECT_GT(cv::countNonZero(textured == textured), 160 * 90 / 2);
  }
}

TEST(StereoAdCensus, WorkspaceHoldsOnlyItsMethodsBuffers) {
  // The paper's ZNCC volume (about 100 MB at 960x540) and its other buffers are not made for AD-Census, and the
  // AD-Census volumes are not made for the paper's method.
  const int width = 64, height = 48, count = 21;
  const std::size_t elements = static_cast<std::size_t>(width) * height * count;
  const StereoWorkspace adCensus(Device::Cpu, StereoMethod::AdCensus, width, height, count);
  EXPECT_EQ(adCensus.volume.size(), 0u);
  EXPECT_EQ(adCensus.columnEven.width(), 0);
  EXPECT_EQ(adCensus.rayPasses.size(), 0u);
  ASSERT_NE(adCensus.adCensus, nullptr);
  EXPECT_EQ(adCensus.adCensus->cost.size(), elements);
  EXPECT_EQ(adCensus.adCensus->pathCost.size(), elements);
  EXPECT_EQ(adCensus.smoothed.width(), width) << "the output map serves both methods";

  const StereoWorkspace paper(Device::Cpu, StereoMethod::Paper, width, height, count);
  EXPECT_EQ(paper.volume.size(), elements);
  EXPECT_EQ(paper.columnEven.width(), width);
  EXPECT_EQ(paper.adCensus, nullptr);

  // A pipeline run with parameters of another method than its workspace's is refused, not misread.
  StereoParameters parameters;
  parameters.minDisparityPx = 0;
  parameters.maxDisparityPx = count - 1;
  StereoWorkspace workspace(Device::Cpu, StereoMethod::Paper, width, height, count);
  parameters.method = StereoMethod::AdCensus;
  StereoTimingsMs timings;
  EXPECT_THROW(runStereoPipelineCpu(workspace, parameters, timings), Error);
}

TEST(StereoAdCensus, MethodNamesAndParameterChecks) {
  EXPECT_EQ(parseStereoMethod("ad-census"), StereoMethod::AdCensus);
  EXPECT_EQ(parseStereoMethod("paper"), StereoMethod::Paper);
  EXPECT_STREQ(stereoMethodName(StereoMethod::AdCensus), "ad-census");
  EXPECT_THROW(parseStereoMethod("sgm"), Error);
  StereoParameters parameters;
  parameters.censusWidthPx = 11;  // 11 x 7 - 1 = 76 bits
  EXPECT_THROW(parameters.validate(), Error);
  parameters = StereoParameters{};
  parameters.censusHeightPx = 4;
  EXPECT_THROW(parameters.validate(), Error);
  parameters = StereoParameters{};
  parameters.armMaxPx = 200;
  EXPECT_THROW(parameters.validate(), Error);
  parameters = StereoParameters{};
  parameters.pathPenaltyLarge = 0.5f;  // below pathPenaltySmall
  EXPECT_THROW(parameters.validate(), Error);
  // The method and its parameters survive a parameters file.
  parameters = StereoParameters{};
  parameters.method = StereoMethod::AdCensus;
  parameters.armMaxPx = 20;
  const std::string path = (std::filesystem::temp_directory_path() / "tm_adcensus_parameters.yml").string();
  parameters.writeFile(path);
  const StereoParameters read = StereoParameters::readFile(path);
  std::filesystem::remove(path);
  EXPECT_EQ(read.method, StereoMethod::AdCensus);
  EXPECT_EQ(read.armMaxPx, 20);
}

TEST(StereoAdCensus, SmallestImageIsTheMethodsOwnWindow) {
  // Each method refuses images smaller than its own matching window and names that window: AD-Census its 9x7
  // census window, the paper's method its 11x11 ZNCC window.
  StereoParameters parameters;
  parameters.minDisparityPx = 0;
  parameters.maxDisparityPx = 3;
  parameters.method = StereoMethod::AdCensus;
  const auto messageFor = [](const StereoParameters& p, int width, int height) -> std::string {
    const cv::Mat image = test::randomTexture(width, height, 3);
    try {
      StereoMatcher(Device::Cpu, p).computeDisparity(image, image);
    } catch (const Error& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(messageFor(parameters, 8, 40).find("census window (9x7 px)"), std::string::npos);
  EXPECT_NE(messageFor(parameters, 40, 6).find("census window (9x7 px)"), std::string::npos);
  EXPECT_EQ(messageFor(parameters, 10, 10), "") << "a 10x10 image is larger than the census window";
  parameters.method = StereoMethod::Paper;
  EXPECT_NE(messageFor(parameters, 10, 10).find("ZNCC window (11x11 px)"), std::string::npos);
  EXPECT_EQ(messageFor(parameters, 11, 11), "");
}
