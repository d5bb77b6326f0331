// The guided ZNCC search (StereoSearch::Guided, GuidedSearchKernels.h) on the CPU: its accuracy against the
// exhaustive search on synthetic pairs with ground truth (issue 51's rule), the whole range where the prior is missing
// or fails, and its scored cells equal to the exhaustive volume's.
#include "StereoTestUtilities.h"
#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "Stereo/DisparityScore.h"
#include "Stereo/StereoMatcher.h"
#include "Stereo/StereoPipeline.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <cstdio>
#include <vector>

using namespace tissuemosaic;

namespace {

struct SearchResult {
  DisparityScore score;
  long long cells = 0;
};

SearchResult runSearch(const synthetic::SyntheticStereoPair& pair, StereoParameters parameters, StereoSearch search) {
  parameters.search = search;
  StereoMatcher matcher(Device::Cpu, parameters);
  const cv::Mat disparity = matcher.computeDisparity(pair.leftRectified, pair.rightRectified);
  return {scoreDisparity(disparity, pair.disparityPx), matcher.lastCellsScored()};
}

/// Issue 51's rule for the guided search to be a default: density at most 0.002 lower, bad-1 at most 0.005 higher;
/// and it must score fewer cells than half of the exhaustive search's.
void expectGuidedKeepsAccuracy(const synthetic::SyntheticStereoPair& pair, const StereoParameters& parameters,
                               const char* what) {
  const SearchResult exhaustive = runSearch(pair, parameters, StereoSearch::Exhaustive);
  const SearchResult guided = runSearch(pair, parameters, StereoSearch::Guided);
  std::printf("%s: exhaustive density %.4f bad-1 %.4f cells %lld; guided density %.4f bad-1 %.4f cells %lld (%.3f)\n",
              what, exhaustive.score.density, exhaustive.score.badOver1, exhaustive.cells, guided.score.density,
              guided.score.badOver1, guided.cells, static_cast<double>(guided.cells) / exhaustive.cells);
  EXPECT_GT(exhaustive.score.density, 0.9) << what;
  EXPECT_GE(guided.score.density, exhaustive.score.density - 0.002) << what;
  EXPECT_LE(guided.score.badOver1, exhaustive.score.badOver1 + 0.005) << what;
  EXPECT_EQ(exhaustive.cells, static_cast<long long>(pair.leftRectified.total()) * parameters.disparityCount());
  EXPECT_LT(guided.cells, exhaustive.cells / 2) << what;
}

}  // namespace

TEST(StereoGuidedSearch, KeepsTheExhaustiveAccuracyOnSyntheticTissueWithFewerCells) {
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions{});
  expectGuidedKeepsAccuracy(pair, StereoParameters{}, "synthetic tissue 960x540, -20..80");
}

TEST(StereoGuidedSearch, KeepsTheExhaustiveAccuracyUnderRealisticLighting) {
  synthetic::SyntheticStereoOptions options;
  options.lighting = synthetic::SyntheticLighting::Realistic;
  const auto pair = synthetic::renderSyntheticStereoPair(options);
  expectGuidedKeepsAccuracy(pair, StereoParameters{}, "realistic lighting 960x540, -20..80");
}

TEST(StereoGuidedSearch, MissingPriorGivesTheWholeRange) {
  // A half-resolution map with a hole (no estimate) and a block whose doubled disparities lie beyond the range.
  const int coarseWidth = 20, coarseHeight = 10, width = 40, height = 20, minPx = -10, maxPx = 60;
  std::vector<int16_t> coarse(coarseWidth * coarseHeight, 12);
  for (int y = 0; y < coarseHeight; ++y) {
    for (int x = 0; x < coarseWidth; ++x) {
      if (x >= 4 && x < 8) coarse[y * coarseWidth + x] = stereo::kNoDisparity;
      if (x >= 14) coarse[y * coarseWidth + x] = 40;  // 80 px: beyond maxPx even with the margin
    }
  }
  std::vector<int16_t> low(width * height), high(width * height);
  const stereo::CandidateWindows windows{{coarse.data(), coarseWidth, coarseHeight}, {low.data(), width, height},
                                         {high.data(), width, height}, minPx, maxPx, stereo::kGuidedWindowMarginPx};
  parallelFor<CpuBackend>(static_cast<int64_t>(width) * height, windows);
  for (int y = 0; y < height; ++y) {
    // Inside the hole (every 3x3 half-resolution neighbour missing): the whole range.
    for (int x = 12; x <= 13; ++x) {
      EXPECT_EQ(low[y * width + x], minPx) << x << "," << y;
      EXPECT_EQ(high[y * width + x], maxPx) << x << "," << y;
    }
    // Where the prior lies beyond the range: the whole range.
    for (int x = 32; x < width; ++x) {
      EXPECT_EQ(low[y * width + x], minPx) << x << "," << y;
      EXPECT_EQ(high[y * width + x], maxPx) << x << "," << y;
    }
    // Where it is known: 2 x 12 +- the margin, and the narrow window even beside the hole (x 6: neighbours 2..4).
    for (int x : {0, 5, 6, 20}) {
      EXPECT_EQ(low[y * width + x], 24 - stereo::kGuidedWindowMarginPx) << x << "," << y;
      EXPECT_EQ(high[y * width + x], 24 + stereo::kGuidedWindowMarginPx) << x << "," << y;
    }
    // Beside the beyond-range block: its neighbours widen the window up to the range's end.
    EXPECT_EQ(low[y * width + 26], 24 - stereo::kGuidedWindowMarginPx);
    EXPECT_EQ(high[y * width + 26], maxPx);
  }
}

TEST(StereoGuidedSearch, FailedWindowsFallBackToTheWholeRangeAndScoresEqualTheExhaustiveVolume) {
  // A wrong prior (windows 3..6 px below the true 8 px): winners land on the window's upper edge, the pixel falls
  // back to the whole range, and its winner is the exhaustive search's. Every cell the guided search
  // scores holds the exhaustive volume's score, bit for bit.
  const int width = 150, height = 60, r = 5, minPx = -6, count = 30;
  const cv::Mat texture = test::randomTexture(width, height, 4, 3.0);  // smooth: a wide correlation peak
  cv::Mat leftMat, rightMat;
  texture.convertTo(leftMat, CV_32F);
  test::shiftedView(texture, 8.0).convertTo(rightMat, CV_32F);
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> left(leftMat.ptr<float>(), leftMat.ptr<float>() + n);
  std::vector<float> right(rightMat.ptr<float>(), rightMat.ptr<float>() + n);
  std::vector<float> sumL(n), normL(n), sumR(n), normR(n);
  stereo::computeWindowStatisticsCpu({left.data(), width, height}, {sumL.data(), width, height},
                                     {normL.data(), width, height}, r, 1.0f);
  stereo::computeWindowStatisticsCpu({right.data(), width, height}, {sumR.data(), width, height},
                                     {normR.data(), width, height}, r, 1.0f);
  const auto layout = stereo::VolumeLayout::rowMajor(width, count);
  std::vector<int16_t> exhaustiveVolume(n * count), exhaustiveLeft(n), exhaustiveRight(n);
  stereo::computeZnccVolumeCpu({{left.data(), width, height}, {right.data(), width, height},
                                {sumL.data(), width, height}, {normL.data(), width, height},
                                {sumR.data(), width, height}, {normR.data(), width, height}, r, minPx, count,
                                exhaustiveVolume.data(), layout, {exhaustiveLeft.data(), width, height},
                                {exhaustiveRight.data(), width, height}, nullptr});

  std::vector<int16_t> volume(n * count), low(n, 3), high(n, 6), winners(n), rightWinners(n);
  std::vector<uint8_t> fellBack(n);
  stereo::ScoreGuidedCells score{{left.data(), width, height},  {right.data(), width, height},
                                 {sumL.data(), width, height},  {normL.data(), width, height},
                                 {sumR.data(), width, height},  {normR.data(), width, height},
                                 r, minPx, count, volume.data(), layout, {low.data(), width, height},
                                 {high.data(), width, height}, {winners.data(), width, height},
                                 {fellBack.data(), width, height}, false};
  parallelFor<CpuBackend>(static_cast<int64_t>(n), score);
  // The window pass: scores inside the windows are the exhaustive ones, the cells outside hold kNoZncc.
  long windowCellsDifferent = 0, outsideScored = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int i = 0; i < count; ++i) {
        const int16_t q = volume[layout.index(x, y, i)];
        if (i >= 3 - minPx && i <= 6 - minPx) windowCellsDifferent += q != exhaustiveVolume[layout.index(x, y, i)];
        else outsideScored += q != stereo::kNoZncc;
      }
    }
  }
  EXPECT_EQ(windowCellsDifferent, 0);
  EXPECT_EQ(outsideScored, 0);
  score.fallbackPass = true;
  parallelFor<CpuBackend>(static_cast<int64_t>(n), score);
  parallelFor<CpuBackend>(static_cast<int64_t>(n), stereo::RightWinnersFromVolume{volume.data(), layout, minPx, count,
                                                                                  {rightWinners.data(), width, height}});
  long fell = 0, textured = 0, fellBackDifferent = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (exhaustiveLeft[k] == stereo::kNoDisparity) continue;
    ++textured;
    if (!fellBack[k]) continue;
    ++fell;
    fellBackDifferent += winners[k] != exhaustiveLeft[k];
    const int x = static_cast<int>(k % width), y = static_cast<int>(k / width);
    for (int i = 0; i < count; ++i) {
      fellBackDifferent += volume[layout.index(x, y, i)] != exhaustiveVolume[layout.index(x, y, i)];
    }
  }
  std::printf("wrong prior: %ld of %ld pixels with a winner fell back\n", fell, textured);
  EXPECT_GT(fell, 0.9 * textured);
  EXPECT_EQ(fellBackDifferent, 0);
  // Right-view winners where every left pixel of a right pixel's candidates fell back: the exhaustive ones.
  long rightChecked = 0, rightDifferent = 0;
  for (int y = 0; y < height; ++y) {
    for (int xr = 0; xr < width; ++xr) {
      bool all = true;
      for (int i = 0; i < count && all; ++i) {
        const int x = xr + minPx + i;
        if (x >= 0 && x < width) all = fellBack[static_cast<std::size_t>(y) * width + x] != 0;
      }
      if (!all) continue;
      ++rightChecked;
      rightDifferent += rightWinners[static_cast<std::size_t>(y) * width + xr] !=
                        exhaustiveRight[static_cast<std::size_t>(y) * width + xr];
    }
  }
  EXPECT_GT(rightChecked, 0);
  EXPECT_EQ(rightDifferent, 0);
}

TEST(StereoGuidedSearch, PairsTooSmallForAHalfResolutionWindowAreSearchedExhaustively) {
  // 18x16: the half-resolution pair (9x8) holds no 11x11 window, so there is no prior at all: the whole range at
  // every pixel, the exhaustive result bit for bit.
  const cv::Mat left = test::randomTexture(18, 16, 2);
  const cv::Mat right = test::shiftedView(left, 3.0);
  StereoParameters parameters;
  parameters.setFixedDisparityRange(-2, 9);
  StereoMatcher exhaustive(Device::Cpu, parameters);
  parameters.search = StereoSearch::Guided;
  StereoMatcher guided(Device::Cpu, parameters);
  const cv::Mat a = exhaustive.computeDisparity(left, right), b = guided.computeDisparity(left, right);
  EXPECT_EQ(guided.lastCellsScored(), exhaustive.lastCellsScored());
  EXPECT_EQ(cv::countNonZero(a == a), cv::countNonZero(b == b));
  EXPECT_EQ(cv::countNonZero((a == a) != (b == b)), 0);
  EXPECT_EQ(cv::countNonZero((a != b) & (a == a)), 0);
}

TEST(StereoGuidedSearch, ParameterFileRoundTripsTheSearch) {
  StereoParameters parameters;
  parameters.search = StereoSearch::Guided;
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/StereoGuidedSearch";
  std::filesystem::create_directories(folder);
  const std::string path = folder + "/guided-search.yml";
  parameters.writeFile(path);
  EXPECT_EQ(StereoParameters::readFile(path).search, StereoSearch::Guided);
  EXPECT_THROW(parseStereoSearch("fast"), Error);
}
