// Each section II stage on inputs whose answer can be checked by hand or by brute force.
#include "Core/ParallelFor.h"
#include "StereoTestUtilities.h"
#include "Stereo/StereoKernels.h"
#include "Stereo/StereoPipeline.h"
#include "Stereo/StereoMatcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

using namespace tissuemosaic;
using namespace tissuemosaic::stereo;

namespace {

Image<int16_t> discreteImage(int width, int height, int16_t value) {
  Image<int16_t> image(Device::Cpu, width, height);
  for (int64_t i = 0; i < image.view().pixelCount(); ++i) image.view()[i] = value;
  return image;
}

/// Brute-force chessboard window sum of I or I*J with replicated borders.
double bruteForceWindowSum(const cv::Mat& a, const cv::Mat& b, int x, int y, int shift, int r) {
  double sum = 0;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if ((dx + dy) % 2 != 0) continue;
      const int yy = std::clamp(y + dy, 0, a.rows - 1);
      sum += a.at<float>(yy, std::clamp(x + dx, 0, a.cols - 1)) * b.at<float>(yy, std::clamp(x + dx - shift, 0, b.cols - 1));
    }
  }
  return sum;
}

}  // namespace

TEST(StereoStages, ChessboardWindowHas61PixelsFor11x11) {
  EXPECT_EQ(chessboardPixelCount(5), 61);
  EXPECT_EQ(chessboardPixelCount(1), 5);
}

TEST(StereoStages, CostVolumeMatchesBruteForceZncc) {
  const cv::Mat texture = test::randomTexture(64, 40, 3);
  const cv::Mat other = test::randomTexture(64, 40, 4);
  cv::Mat left, right;
  texture.convertTo(left, CV_32F);
  other.convertTo(right, CV_32F);
  cv::Mat shifted;
  test::shiftedView(texture, 3).convertTo(shifted, CV_32F);
  right = 0.5 * right + 0.5 * shifted;
  right.convertTo(right, CV_8U);
  right.convertTo(right, CV_32F);
  // Every radius has its own unrolled scoring loop on the CPU: odd and even radii, the paper's 5, the largest.
  for (const int r : {1, 2, 5, 8, 9}) {
  SCOPED_TRACE("radius " + std::to_string(r));
  const int minD = -2, count = 9, n = chessboardPixelCount(r);

  Image<float> l(Device::Cpu, 64, 40), rr(Device::Cpu, 64, 40);
  l.buffer().upload(left.ptr<float>());
  rr.buffer().upload(right.ptr<float>());
  Image<float> ce(Device::Cpu, 64, 40), co(Device::Cpu, 64, 40), ce2(Device::Cpu, 64, 40), co2(Device::Cpu, 64, 40);
  Image<float> sumL(Device::Cpu, 64, 40), normL(Device::Cpu, 64, 40), sumR(Device::Cpu, 64, 40), normR(Device::Cpu, 64, 40);
  for (auto [image, sum, norm] : {std::tuple{&l, &sumL, &normL}, std::tuple{&rr, &sumR, &normR}}) {
    parallelFor<CpuBackend>(64 * 40, WindowColumnSums{image->view(), ce.view(), co.view(), ce2.view(), co2.view(), r});
    parallelFor<CpuBackend>(64 * 40, WindowStatistics{ce.view(), co.view(), ce2.view(), co2.view(), sum->view(), norm->view(), r, 1.0f});
  }
  Buffer<int16_t> volume(Device::Cpu, count * 64 * 40);
  Image<int16_t> best(Device::Cpu, 64, 40), rightBest(Device::Cpu, 64, 40);
  const VolumeLayout layout = VolumeLayout::rowMajor(64, count);
  computeZnccVolumeCpu(ZnccVolumeInputs{l.view(), rr.view(), sumL.view(), normL.view(), sumR.view(), normR.view(), r, minD,
                                        count, volume.data(), layout, best.view(), rightBest.view()});

  for (int y : {0, 7, 20, 39}) {
    for (int x : {0, 5, 31, 63}) {
      for (int i = 0; i < count; ++i) {
        const int d = minD + i;
        const int16_t q = volume.data()[layout.index(x, y, i)];
        if (x - d < 0 || x - d >= 64) {
          EXPECT_EQ(q, kNoZncc);
          continue;
        }
        const double sLR = bruteForceWindowSum(left, right, x, y, d, r);
        const double sL = bruteForceWindowSum(left, cv::Mat::ones(left.size(), CV_32F), x, y, 0, r);
        const double sR = bruteForceWindowSum(cv::Mat::ones(left.size(), CV_32F), right, x, y, d, r);
        const double sLL = bruteForceWindowSum(left, left, x, y, 0, r);
        const double sRR = bruteForceWindowSum(right, right, x - d, y, 0, r);
        const double spreadL = n * sLL - sL * sL, spreadR = n * sRR - sR * sR;
        if (std::min(spreadL, spreadR) <= static_cast<double>(n) * n) {  // grey-level std <= 1: textureless
          EXPECT_EQ(q, kNoZncc) << "x " << x << " y " << y << " d " << d;
          continue;
        }
        const double zncc = (n * sLR - sL * sR) / std::sqrt(spreadL * spreadR);
        EXPECT_NEAR(q / kZnccScale, zncc, 1.0 / kZnccScale) << "x " << x << " y " << y << " d " << d;
      }
    }
  }
  // Winners: left pixel x over its row of the volume; right pixel xr over the left pixels xr + d.
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 64; ++x) {
      int16_t bestLeft = kNoZncc, bestLeftD = kNoDisparity, bestRight = kNoZncc, bestRightD = kNoDisparity;
      for (int i = 0; i < count; ++i) {
        const int16_t q = volume.data()[layout.index(x, y, i)];
        if (q > bestLeft) bestLeft = q, bestLeftD = static_cast<int16_t>(minD + i);
        const int xl = x + minD + i;
        if (xl < 0 || xl >= 64) continue;
        const int16_t qr = volume.data()[layout.index(xl, y, i)];
        if (qr > bestRight) bestRight = qr, bestRightD = static_cast<int16_t>(minD + i);
      }
      ASSERT_EQ(best.view().at(x, y), bestLeftD);
      ASSERT_EQ(rightBest.view().at(x, y), bestRightD);
    }
  }
  }
}

TEST(StereoStages, BandedCpuWindowStatisticsEqualThePerPixelFunctors) {
  // Both ends of the radius range (1: no quads; 9: the widest window) and odd and even radii (odd ones add a pair).
  for (int radius : {1, 2, 5, 8, 9}) {
    const cv::Mat texture = test::randomTexture(77, 45, 7 + radius);
    cv::Mat grey;
    texture.convertTo(grey, CV_32F);
    const int w = grey.cols, h = grey.rows;
    Image<float> image(Device::Cpu, w, h);
    image.buffer().upload(grey.ptr<float>());
    Image<float> ce(Device::Cpu, w, h), co(Device::Cpu, w, h), ce2(Device::Cpu, w, h), co2(Device::Cpu, w, h);
    Image<float> sum(Device::Cpu, w, h), norm(Device::Cpu, w, h), bandSum(Device::Cpu, w, h), bandNorm(Device::Cpu, w, h);
    parallelFor<CpuBackend>(w * h, WindowColumnSums{image.view(), ce.view(), co.view(), ce2.view(), co2.view(), radius});
    parallelFor<CpuBackend>(w * h, WindowStatistics{ce.view(), co.view(), ce2.view(), co2.view(), sum.view(), norm.view(), radius, 1.0f});
    computeWindowStatisticsCpu(image.view(), bandSum.view(), bandNorm.view(), radius, 1.0f);
    for (int i = 0; i < w * h; ++i) {
      ASSERT_EQ(bandSum.view()[i], sum.view()[i]) << "radius " << radius << " pixel " << i;
      ASSERT_EQ(bandNorm.view()[i], norm.view()[i]) << "radius " << radius << " pixel " << i;
    }
  }
}

TEST(StereoStages, ZnccFindsIntegerShiftOfTexture) {
  const cv::Mat left = test::randomTexture(160, 100, 11);
  const cv::Mat right = test::shiftedView(left, 7);
  StereoParameters parameters;
  parameters.minDisparityPx = -5;
  parameters.maxDisparityPx = 20;
  StereoMatcher matcher(Device::Cpu, parameters);
  const cv::Mat disparity = matcher.computeDisparity(left, right);
  const cv::Mat zncc = matcher.lastZnccDisparity();
  int checked = 0;
  for (int y = 0; y < 100; ++y) {
    for (int x = 50; x < 145; ++x) {  // windows and the smoothing radius clear of the image's side borders
      ASSERT_EQ(zncc.at<float>(y, x), 7.0f) << x << "," << y;
      ASSERT_NEAR(disparity.at<float>(y, x), 7.0f, 0.05) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 9000);
}

TEST(StereoStages, WinnersNearTheRangesEndsAreDropped) {
  // One winner per candidate of the range -3..6; the left-right check off.
  const int minDisparity = -3, maxDisparity = 6, w = maxDisparity - minDisparity + 1;
  Image<int16_t> winners = discreteImage(w, 1, 0);
  for (int x = 0; x < w; ++x) winners.view().at(x, 0) = static_cast<int16_t>(minDisparity + x);
  winners.view().at(4, 0) = kNoDisparity;
  const Image<int16_t> right = discreteImage(w, 1, kNoDisparity);
  for (const int margin : {-1, 0, 1, 2}) {
    Image<int16_t> kept(Device::Cpu, w, 1);
    parallelFor<CpuBackend>(w, KeepWinners{winners.view(), right.view(), kept.view(), minDisparity, maxDisparity,
                                           margin, -1});
    for (int x = 0; x < w; ++x) {
      const int16_t d = winners.view().at(x, 0);
      const bool nearEnd = margin >= 0 && (x <= margin || w - 1 - x <= margin);
      EXPECT_EQ(kept.view().at(x, 0), nearEnd ? kNoDisparity : d) << "margin " << margin << ", d " << d;
    }
  }
}

TEST(StereoStages, ASurfaceBeyondTheRangeLeavesNoEstimateAtItsEnd) {
  // A smooth texture (as tissue or an instrument's shaft): its correlation falls off with the distance from the true
  // shift, so over a range that stops short of a band's true disparity the best candidate is the range's end, in
  // every pixel of the band. The band (rows 40..79) lies at 23 px, beyond the range 0..20; the rest at 7 px.
  const int width = 200, height = 120;
  const cv::Mat left = test::randomTexture(width, height, 5, 3.0);
  cv::Mat right = test::shiftedView(left, 7);
  test::shiftedView(left, 23).rowRange(40, 80).copyTo(right.rowRange(40, 80));
  const auto endEstimates = [&](int marginPx, int& atEnd, int& elsewhere) {
    StereoParameters parameters;
    parameters.minDisparityPx = 0;
    parameters.maxDisparityPx = 20;
    parameters.rangeEndMarginPx = marginPx;
    StereoMatcher matcher(Device::Cpu, parameters);
    const cv::Mat disparity = matcher.computeDisparity(left, right);
    atEnd = elsewhere = 0;
    for (int y = 50; y < 70; ++y) {  // the band's rows whose windows and radii stay inside it
      for (int x = 60; x < width - 20; ++x) {
        const float d = disparity.at<float>(y, x);
        if (std::isfinite(d) && d >= 18.0f) ++atEnd;
        if (std::isfinite(d) && d < 18.0f) ++elsewhere;
      }
    }
  };
  int atEnd = 0, elsewhere = 0;
  endEstimates(-1, atEnd, elsewhere);
  EXPECT_GT(atEnd, 1000) << "without the rule the band sits at the range's end";
  endEstimates(1, atEnd, elsewhere);
  EXPECT_EQ(atEnd, 0);
}

TEST(StereoStages, OutlierRemovalDropsSpikeKeepsSlopeAndStep) {
  const int w = 60, h = 40;
  Image<int16_t> input = discreteImage(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) input.view().at(x, y) = static_cast<int16_t>(x / 10 + (x >= 30 ? 20 : 0));  // slope + step
  input.view().at(15, 20) = 40;  // isolated spike
  Image<int16_t> output(Device::Cpu, w, h);
  parallelFor<CpuBackend>(w * h, RemoveOutliers{input.view(), output.view(), 10, 2.5f});
  EXPECT_EQ(output.view().at(15, 20), kNoDisparity);
  int kept = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) kept += output.view().at(x, y) == input.view().at(x, y);
  EXPECT_EQ(kept, w * h - 1);  // both sides of the step keep a smooth ray
}

TEST(StereoStages, OutlierRemovalDropsSmallWrongPatch) {
  const int w = 60, h = 60;
  Image<int16_t> input = discreteImage(w, h, 10);
  for (int y = 28; y < 31; ++y)
    for (int x = 28; x < 31; ++x) input.view().at(x, y) = 30;  // a 3x3 blob of a wrong disparity
  Image<int16_t> output(Device::Cpu, w, h);
  parallelFor<CpuBackend>(w * h, RemoveOutliers{input.view(), output.view(), 10, 2.5f});
  for (int y = 28; y < 31; ++y)
    for (int x = 28; x < 31; ++x) EXPECT_EQ(output.view().at(x, y), kNoDisparity);
  EXPECT_EQ(output.view().at(5, 5), 10);
}

TEST(StereoStages, RadialFillingInterpolatesARampAndSkipsEdges) {
  const int w = 80, h = 60;
  Image<int16_t> input = discreteImage(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) input.view().at(x, y) = static_cast<int16_t>(x / 4);
  for (int y = 25; y < 35; ++y)
    for (int x = 35; x < 45; ++x) input.view().at(x, y) = kNoDisparity;
  Image<int16_t> output(Device::Cpu, w, h);
  parallelFor<CpuBackend>(w * h, FillHolesRadial{input.view(), output.view(), 50, 2, 2.5f});
  for (int y = 25; y < 35; ++y)
    for (int x = 35; x < 45; ++x) EXPECT_NEAR(output.view().at(x, y), x / 4.0, 1.0) << x << "," << y;

  // A hole on a depth edge of 20 px: no line may interpolate across it, so pixels whose lines all cross stay empty.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) input.view().at(x, y) = x < 40 ? 10 : 30;
  for (int y = 0; y < h; ++y)
    for (int x = 38; x < 42; ++x) input.view().at(x, y) = kNoDisparity;
  parallelFor<CpuBackend>(w * h, FillHolesRadial{input.view(), output.view(), 50, 2, 2.5f});
  for (int y = 0; y < h; ++y) EXPECT_EQ(output.view().at(39, y), kNoDisparity);
}

TEST(StereoStages, CpuRadialSweepsEqualTheRayWalks) {
  // Random hole patterns of several densities, with image borders and radii shorter than the holes.
  for (int density : {2, 5, 9}) {
    const int w = 83, h = 57;
    Image<int16_t> input(Device::Cpu, w, h);
    std::mt19937 random(density);
    for (int64_t i = 0; i < w * h; ++i) {
      input.view()[i] = static_cast<int>(random() % 10) < density ? kNoDisparity : static_cast<int16_t>(random() % 40);
    }
    // Every line count: the walks stop early once too few lines remain, the sweeps never do.
    for (int radius : {3, 12, 50}) {
      for (int minLines = 1; minLines <= 4; ++minLines) {
        Image<int16_t> walked(Device::Cpu, w, h);
        parallelFor<CpuBackend>(w * h, FillHolesRadial{input.view(), walked.view(), radius, minLines, 2.5f});
        // One sweep per direction, and directions cut into bands of rows (bands start radius rows early).
        for (int rowBands : {1, 3, 7}) {
          Image<int16_t> swept(Device::Cpu, w, h);
          Buffer<int16_t> distance(Device::Cpu, 8 * w * h), value(Device::Cpu, 8 * w * h);
          fillHolesRadialCpu(input.view(), swept.view(), radius, minLines, 2.5f, distance.data(), value.data(),
                             rowBands);
          int filled = 0;
          for (int64_t i = 0; i < w * h; ++i) {
            ASSERT_EQ(swept.view()[i], walked.view()[i]) << "density " << density << " radius " << radius << " lines "
                                                         << minLines << " bands " << rowBands << " pixel " << i;
            filled += input.view()[i] == kNoDisparity && walked.view()[i] != kNoDisparity;
          }
          if (minLines <= 2) EXPECT_GT(filled, 0);
        }
      }
    }
  }
}

TEST(StereoStages, CpuOutlierSweepsEqualTheRayWalks) {
  // Ramps with random jumps and holes: rays that stay smooth, break early, break just beyond the radius, or see too
  // few estimates; image borders; every band split of the sweeps.
  for (int density : {1, 4, 7}) {
    const int w = 91, h = 64;
    Image<int16_t> input(Device::Cpu, w, h);
    std::mt19937 random(100 + density);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const bool hole = static_cast<int>(random() % 10) < density;
        const int jump = random() % 8 == 0 ? static_cast<int>(random() % 12) - 6 : 0;
        input.view().at(x, y) = hole ? kNoDisparity : static_cast<int16_t>(x / 3 - y / 4 + jump);
      }
    }
    for (int radius : {1, 4, 10, 30}) {
      for (float maxStep : {0.0f, 2.5f, 6.0f}) {
        Image<int16_t> walked(Device::Cpu, w, h);
        parallelFor<CpuBackend>(w * h, RemoveOutliers{input.view(), walked.view(), radius, maxStep});
        int kept = 0, removed = 0;
        for (int64_t i = 0; i < w * h; ++i) {
          kept += walked.view()[i] != kNoDisparity;
          removed += input.view()[i] != kNoDisparity && walked.view()[i] == kNoDisparity;
        }
        for (int rowBands : {1, 3, 7}) {
          Image<int16_t> swept(Device::Cpu, w, h);
          Buffer<uint8_t> passes(Device::Cpu, 8 * w * h);
          removeOutliersCpu(input.view(), swept.view(), radius, maxStep, passes.data(), rowBands);
          for (int64_t i = 0; i < w * h; ++i) {
            ASSERT_EQ(swept.view()[i], walked.view()[i]) << "density " << density << " radius " << radius << " step "
                                                         << maxStep << " bands " << rowBands << " pixel " << i;
          }
        }
        if (radius == 10 && maxStep == 2.5f) {  // the paper's test: the comparison covers both answers
          EXPECT_GT(kept, w * h / 10) << "density " << density;
          EXPECT_GT(removed, w * h / 100) << "density " << density;
        }
      }
    }
  }
}

TEST(StereoStages, CpuReselectionRowsEqualThePerPixelRule) {
  // Random cost volume (with kNoZncc and non-positive scores), discrete map with holes, smoothed map and correction
  // sums; candidates clipped at both ends of the range; segments of every length up to the CPU block.
  const int w = 150, h = 7, disparities = 30, minDisparity = -4, search = 5;
  std::mt19937 random(11);
  Buffer<int16_t> volume(Device::Cpu, static_cast<std::size_t>(w) * h * disparities);
  for (std::size_t i = 0; i < volume.size(); ++i) {
    const int pick = static_cast<int>(random() % 10);
    volume.data()[i] = pick == 0 ? kNoZncc : (pick == 1 ? static_cast<int16_t>(-static_cast<int>(random() % 500))
                                                        : static_cast<int16_t>(1 + random() % kZnccMax));
  }
  const VolumeLayout layout = VolumeLayout::rowMajor(w, disparities);
  Image<int16_t> discrete(Device::Cpu, w, h);
  Image<float> current(Device::Cpu, w, h);
  std::vector<int64_t> sums(w * h);
  std::vector<int> counts(w * h);
  std::uniform_real_distribution<float> disparity(minDisparity - 8.0f, minDisparity + disparities + 8.0f);
  for (int64_t i = 0; i < w * h; ++i) {
    discrete.view()[i] = random() % 6 == 0 ? kNoDisparity : static_cast<int16_t>(minDisparity + random() % disparities);
    current.view()[i] = disparity(random);
    counts[i] = random() % 7 == 0 ? 0 : static_cast<int>(1 + random() % 900);
    sums[i] = static_cast<int64_t>(random() % 2000000) - 1000000;
  }
  Image<int16_t> expectedDiscrete(Device::Cpu, w, h), rowsDiscrete(Device::Cpu, w, h);
  Image<float> expectedCurrent(Device::Cpu, w, h), rowsCurrent(Device::Cpu, w, h);
  expectedDiscrete.buffer().copyFrom(discrete.buffer());
  rowsDiscrete.buffer().copyFrom(discrete.buffer());
  expectedCurrent.buffer().copyFrom(current.buffer());
  rowsCurrent.buffer().copyFrom(current.buffer());
  const ReselectDiscrete perPixel{volume.data(), layout, minDisparity, disparities, search, 0.01f,
                                  expectedCurrent.view(), expectedDiscrete.view()};
  for (int64_t i = 0; i < w * h; ++i) perPixel(i, sums[i], counts[i]);
  const ReselectDiscreteRows rows{
      {volume.data(), layout, minDisparity, disparities, search, 0.01f, rowsCurrent.view(), rowsDiscrete.view()}};
  int changed = 0;
  for (int y = 0; y < h; ++y) {
    for (int x0 = 0, length = 1 + y * 9; x0 < w; x0 += length) {
      const int columns = std::min({length, w - x0, 64});
      const int64_t first = static_cast<int64_t>(y) * w + x0;
      rows.consumeRow(first, sums.data() + first, counts.data() + first, columns);
      length = columns;
    }
  }
  for (int64_t i = 0; i < w * h; ++i) {
    ASSERT_EQ(rowsDiscrete.view()[i], expectedDiscrete.view()[i]) << "pixel " << i;
    const float a = rowsCurrent.view()[i], b = expectedCurrent.view()[i];
    ASSERT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << "pixel " << i << ": " << a << " vs " << b;
    changed += expectedDiscrete.view()[i] != discrete.view()[i];
  }
  EXPECT_GT(changed, w * h / 4);  // the rule re-selected many pixels
}

namespace {

/// The CPU's box sums (row prefix sums, then column blocks), one column per task, and the GPU's direct per-pixel
/// sums of `value` over radius r must all equal the brute-force sums of reference(x, y) (nullopt: no value).
template <class Value, class Reference>
void expectBoxSumsMatchBruteForce(const Value& value, int w, int h, int r, const Reference& reference) {
  SCOPED_TRACE("radius " + std::to_string(r) + ", " + std::to_string(w) + "x" + std::to_string(h));
  Buffer<int64_t> rowSum(Device::Cpu, w * h), boxSum(Device::Cpu, w * h);
  Buffer<int> rowCount(Device::Cpu, w * h), boxCount(Device::Cpu, w * h);
  parallelFor<CpuBackend>(h, BoxRowSums<Value>{value, w, r, rowSum.data(), rowCount.data()}, 1);
  parallelFor<CpuBackend>(w, BoxColumnSums<1, StoreBoxSums>{rowSum.data(), rowCount.data(), w, h, r, {boxSum.data(), boxCount.data()}}, 1);
  // Blocks of columns (the CPU's choice) give bit-identical sums to one column per task (the GPU's).
  Buffer<int64_t> blockSum(Device::Cpu, w * h);
  Buffer<int> blockCount(Device::Cpu, w * h);
  using Blocks = BoxColumnSums<8, StoreBoxSums>;
  parallelFor<CpuBackend>(Blocks::taskCount(w), Blocks{rowSum.data(), rowCount.data(), w, h, r, {blockSum.data(), blockCount.data()}}, 1);
  // And the GPU's direct per-pixel sums give the same again.
  Buffer<int64_t> directRow(Device::Cpu, w * h), directSum(Device::Cpu, w * h);
  Buffer<int> directRowCount(Device::Cpu, w * h), directCount(Device::Cpu, w * h);
  parallelFor<CpuBackend>(w * h, BoxRowSumsDirect<Value>{value, w, r, directRow.data(), directRowCount.data()});
  parallelFor<CpuBackend>(w * h, BoxColumnSumsDirect<StoreBoxSums>{directRow.data(), directRowCount.data(), w, h, r, {directSum.data(), directCount.data()}});
  for (int i = 0; i < w * h; ++i) {
    ASSERT_EQ(blockSum.data()[i], boxSum.data()[i]);
    ASSERT_EQ(blockCount.data()[i], boxCount.data()[i]);
    ASSERT_EQ(directSum.data()[i], boxSum.data()[i]);
    ASSERT_EQ(directCount.data()[i], boxCount.data()[i]);
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      int64_t sum = 0;
      int count = 0;
      for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy) {
        for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx) {
          if (const std::optional<int64_t> v = reference(xx, yy)) sum += *v, ++count;
        }
      }
      ASSERT_EQ(boxCount.data()[y * w + x], count) << "at " << x << ", " << y;
      ASSERT_EQ(boxSum.data()[y * w + x], sum) << "at " << x << ", " << y;
    }
  }
}

}  // namespace

TEST(StereoStages, BoxSumsMatchBruteForce) {
  const int w = 37, h = 23;
  Image<int16_t> input(Device::Cpu, w, h);
  std::mt19937 random(5);
  for (int64_t i = 0; i < w * h; ++i) input.view()[i] = random() % 5 == 0 ? kNoDisparity : static_cast<int16_t>(random() % 50);
  const auto reference = [&](int x, int y) -> std::optional<int64_t> {
    const int16_t d = input.view().at(x, y);
    return d == kNoDisparity ? std::nullopt : std::optional<int64_t>(d);
  };
  // Radii with windows inside the rows, windows wider than half a row, and wider than the whole image.
  for (const int r : {0, 1, 4, 17, 18, 40}) {
    expectBoxSumsMatchBruteForce(DiscreteDisparityValue{input.view()}, w, h, r, reference);
  }
}

TEST(StereoStages, FloatBoxSumsRoundEachValueLikeLlrint) {
  const int w = 41, h = 19;
  Image<float> input(Device::Cpu, w, h);
  std::mt19937 random(8);
  std::uniform_real_distribution<float> uniform(-60.0f, 60.0f);
  for (int64_t i = 0; i < w * h; ++i) {
    switch (random() % 8) {
      case 0: input.view()[i] = NAN; break;
      case 1: input.view()[i] = (random() % 2 ? 1 : -1) * INFINITY; break;
      case 2: input.view()[i] = (random() % 2 ? 1 : -1) * (kMaxFixedPointInput * (1.0f + uniform(random) / 100.0f)); break;
      case 3: input.view()[i] = static_cast<float>(static_cast<int>(random() % 2001) - 1000) / 131072.0f; break;  // ties
      default: input.view()[i] = uniform(random) * (random() % 2 ? 1.0f : 1e-3f);
    }
  }
  input.view()[0] = kMaxFixedPointInput;  // the bound itself is a value; the next float up is not
  input.view()[1] = -kMaxFixedPointInput;
  input.view()[2] = std::nextafter(kMaxFixedPointInput, INFINITY);
  const auto reference = [&](int x, int y) -> std::optional<int64_t> {
    const float v = input.view().at(x, y);
    if (!(std::fabs(v) <= kMaxFixedPointInput)) return std::nullopt;
    return std::llrint(static_cast<double>(v) * kFixedPointScale);
  };
  int ties = 0;
  for (int64_t i = 0; i < w * h; ++i) {
    const double scaled = static_cast<double>(input.view()[i]) * kFixedPointScale;
    ties += std::isfinite(scaled) && scaled != std::floor(scaled) && scaled - std::floor(scaled) == 0.5;
  }
  EXPECT_GT(ties, 20);  // halves occur, so round-half-even is tested against llrint
  for (const int r : {0, 3, 15, 25}) expectBoxSumsMatchBruteForce(FloatValue{input.view()}, w, h, r, reference);
  // The exact conversions at the magnitudes the bound allows.
  for (const int64_t i : {int64_t{0}, int64_t{-1}, int64_t{1} << 50, -(int64_t{1} << 50) + 3, int64_t{123456789012345}}) {
    EXPECT_EQ(int64ToDouble(i), static_cast<double>(i));
    EXPECT_EQ(roundToInt64(static_cast<double>(i) + 0.5), std::llrint(static_cast<double>(i) + 0.5));
  }
}

TEST(StereoStages, CpuRowConsumersEqualThePerPixelRules) {
  // The disc filling and the Laplacian step take row segments on the CPU (consumeRow) and single pixels on the GPU
  // (operator()): random maps with holes, radii whose boxes reach past the image, segments of every length.
  const int w = 131, h = 29;
  std::mt19937 random(31);
  Image<int16_t> discrete(Device::Cpu, w, h);
  Image<float> previous(Device::Cpu, w, h);
  for (int64_t i = 0; i < w * h; ++i) {
    discrete.view()[i] = random() % 3 == 0 ? kNoDisparity : static_cast<int16_t>(static_cast<int>(random() % 200) - 60);
    previous.view()[i] = static_cast<float>(random() % 100000) / 997.0f - 40.0f;
  }
  for (const int r : {1, 6, 20, 70}) {
    SCOPED_TRACE("radius " + std::to_string(r));
    Buffer<int64_t> rowSum(Device::Cpu, w * h);
    Buffer<int> rowCount(Device::Cpu, w * h);
    parallelFor<CpuBackend>(h, BoxRowSums<DiscreteDisparityValue>{{discrete.view()}, w, r, rowSum.data(), rowCount.data()}, 1);
    Image<int16_t> filledRows(Device::Cpu, w, h), filledPixels(Device::Cpu, w, h);
    using DiscRows = BoxColumnSums<kCpuBoxColumnBlock, FillHolesDisc>;
    parallelFor<CpuBackend>(DiscRows::taskCount(w), DiscRows{rowSum.data(), rowCount.data(), w, h, r, {discrete.view(), filledRows.view(), r, 0.4f}}, 1);
    parallelFor<CpuBackend>(w * h, BoxColumnSumsDirect<FillHolesDisc>{rowSum.data(), rowCount.data(), w, h, r, {discrete.view(), filledPixels.view(), r, 0.4f}});
    Image<float> currentRows(Device::Cpu, w, h), correctionRows(Device::Cpu, w, h);
    Image<float> currentPixels(Device::Cpu, w, h), correctionPixels(Device::Cpu, w, h);
    using StepRows = BoxColumnSums<kCpuBoxColumnBlock, LaplacianStep>;
    parallelFor<CpuBackend>(StepRows::taskCount(w), StepRows{rowSum.data(), rowCount.data(), w, h, r, {discrete.view(), previous.view(), currentRows.view(), correctionRows.view(), 0.1f}}, 1);
    parallelFor<CpuBackend>(w * h, BoxColumnSumsDirect<LaplacianStep>{rowSum.data(), rowCount.data(), w, h, r, {discrete.view(), previous.view(), currentPixels.view(), correctionPixels.view(), 0.1f}});
    int filled = 0;
    const auto same = [](float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); };
    for (int64_t i = 0; i < w * h; ++i) {
      ASSERT_EQ(filledRows.view()[i], filledPixels.view()[i]) << "pixel " << i;
      ASSERT_TRUE(same(currentRows.view()[i], currentPixels.view()[i])) << "pixel " << i;
      ASSERT_TRUE(same(correctionRows.view()[i], correctionPixels.view()[i])) << "pixel " << i;
      filled += discrete.view()[i] == kNoDisparity && filledPixels.view()[i] != kNoDisparity;
    }
    EXPECT_GT(filled, 0);
  }
}

TEST(StereoStages, DiscFillingUsesNeighbourhoodMean) {
  const int w = 60, h = 60, r = 20;
  Image<int16_t> input = discreteImage(w, h, 12);
  input.view().at(30, 30) = kNoDisparity;
  for (int x = 0; x < w; ++x)
    for (int y = 0; y < 5; ++y) input.view().at(x, y) = kNoDisparity;  // a sparse top band stays unfilled
  for (int x = 0; x < w; x += 20) input.view().at(x, 0) = 12;
  Buffer<int64_t> rowSum(Device::Cpu, w * h), boxSum(Device::Cpu, w * h);
  Buffer<int> rowCount(Device::Cpu, w * h), boxCount(Device::Cpu, w * h);
  parallelFor<CpuBackend>(h, BoxRowSums<DiscreteDisparityValue>{{input.view()}, w, r, rowSum.data(), rowCount.data()}, 1);
  Image<int16_t> output(Device::Cpu, w, h);
  parallelFor<CpuBackend>(w, BoxColumnSums<1, FillHolesDisc>{rowSum.data(), rowCount.data(), w, h, r, {input.view(), output.view(), r, 0.5f}}, 1);
  EXPECT_EQ(output.view().at(30, 30), 12);
  EXPECT_EQ(output.view().at(30, 3), 12);  // 25 of 41 rows around it are valid: > half
  // At the top-left corner only 16 of 21x21 window rows exist; with 5 empty rows the valid share is 0.69: filled.
  EXPECT_EQ(output.view().at(0, 1), 12);
}

TEST(StereoStages, RefinementGivesSubPixelDisparityOnSlantedPlane) {
  // d = 10 + 0.05 x: ZNCC winners are integers (error up to 0.5 px); the refined map must be sub-pixel.
  const cv::Mat left = test::randomTexture(240, 120, 21, 1.2);
  const cv::Mat right = test::shiftedView(left, 10.0, 0.05, 0.0);
  StereoParameters parameters;
  parameters.minDisparityPx = 0;
  parameters.maxDisparityPx = 40;
  StereoMatcher matcher(Device::Cpu, parameters);
  const cv::Mat refined = matcher.computeDisparity(left, right);
  const cv::Mat zncc = matcher.lastZnccDisparity();
  double refinedError = 0, znccError = 0;
  int count = 0;
  for (int y = 20; y < 100; ++y) {
    for (int x = 40; x < 200; ++x) {
      const double truth = 10.0 + 0.05 * x;
      if (!std::isfinite(refined.at<float>(y, x)) || !std::isfinite(zncc.at<float>(y, x))) continue;
      refinedError += std::abs(refined.at<float>(y, x) - truth);
      znccError += std::abs(zncc.at<float>(y, x) - truth);
      ++count;
    }
  }
  ASSERT_GT(count, 12000);
  refinedError /= count;
  znccError /= count;
  std::printf("mean abs error: zncc %.3f px, refined %.3f px\n", znccError, refinedError);
  EXPECT_GT(znccError, 0.2);
  EXPECT_LT(refinedError, 0.5 * znccError);
}
