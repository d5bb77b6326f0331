// The guided ZNCC search (StereoSearch::Guided) on CUDA against the CPU (ctest label "cuda"; skipped with a message
// where no GPU exists): the same kernels on exact integer sums, so the same winners, candidate windows, fallbacks and
// final disparities, bit for bit.
#include "StereoTestUtilities.h"
#include "Core/Error.h"
#include "Stereo/StereoMatcher.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace tissuemosaic;

namespace {

long countDifferent(const cv::Mat& a, const cv::Mat& b) {
  long different = 0;
  for (int i = 0; i < a.rows * a.cols; ++i) {
    const float x = a.at<float>(i), y = b.at<float>(i);
    different += !((std::isnan(x) && std::isnan(y)) || x == y);
  }
  return different;
}

}  // namespace

TEST(StereoGuidedSearchCuda, MatchesCpuBitForBit) {
  if (!cudaAvailable()) {
    std::printf("no usable CUDA device: %s\n", cudaUnavailableReason().c_str());
    GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  }
  for (const auto lighting : {synthetic::SyntheticLighting::Standard, synthetic::SyntheticLighting::Realistic}) {
    synthetic::SyntheticStereoOptions options;
    options.lighting = lighting;
    const auto pair = synthetic::renderSyntheticStereoPair(options);
    const char* what = synthetic::syntheticLightingName(lighting);
    StereoParameters parameters;
    parameters.search = StereoSearch::Guided;
    StereoMatcher cpu(Device::Cpu, parameters), gpu(Device::Cuda, parameters);
    // Twice on one matcher: the second frame reuses the half-resolution working set.
    for (int frame = 0; frame < 2; ++frame) {
      const cv::Mat cpuDisparity = cpu.computeDisparity(pair.leftRectified, pair.rightRectified);
      const cv::Mat gpuDisparity = gpu.computeDisparity(pair.leftRectified, pair.rightRectified);
      const long winners = countDifferent(cpu.lastZnccDisparity(), gpu.lastZnccDisparity());
      const long filled = countDifferent(cpu.lastFilledDisparity(), gpu.lastFilledDisparity());
      const long final = countDifferent(cpuDisparity, gpuDisparity);
      std::printf("%s frame %d: winners differing %ld, filled %ld, final %ld; cells cpu %lld gpu %lld\n", what, frame,
                  winners, filled, final, cpu.lastCellsScored(), gpu.lastCellsScored());
      EXPECT_EQ(winners, 0) << what;
      EXPECT_EQ(filled, 0) << what;
      EXPECT_EQ(final, 0) << what;
      EXPECT_EQ(cpu.lastCellsScored(), gpu.lastCellsScored()) << what;
      EXPECT_LT(cpu.lastCellsScored(), static_cast<long long>(pair.leftRectified.total()) * parameters.disparityCount());
    }
  }
}

TEST(StereoGuidedSearchCuda, MatchesCpuBitForBitAtHdWithAWideRange) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions::wideDisparity(1920, 1080));
  StereoParameters parameters;
  parameters.search = StereoSearch::Guided;
  parameters.setFixedDisparityRange(60, 315);
  StereoMatcher cpu(Device::Cpu, parameters), gpu(Device::Cuda, parameters);
  const cv::Mat cpuDisparity = cpu.computeDisparity(pair.leftRectified, pair.rightRectified);
  const cv::Mat gpuDisparity = gpu.computeDisparity(pair.leftRectified, pair.rightRectified);
  EXPECT_EQ(countDifferent(cpu.lastZnccDisparity(), gpu.lastZnccDisparity()), 0);
  EXPECT_EQ(countDifferent(cpuDisparity, gpuDisparity), 0);
  EXPECT_EQ(cpu.lastCellsScored(), gpu.lastCellsScored());
}
