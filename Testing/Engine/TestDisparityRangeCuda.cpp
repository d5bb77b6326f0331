// The automatic disparity range on CUDA against the CPU (ctest label "cuda"; skipped with a message where no GPU
// exists): its ORB features are identical on both devices, so the sparse disparities and the chosen range must be
// too; and a CUDA matcher given a new range between frames matches as a fresh CUDA matcher over that range.
#include "SyntheticScan.h"

#include "Core/Device.h"
#include "Stereo/DisparityRangeEstimator.h"
#include "Stereo/StereoMatcher.h"
#include "StereoTestUtilities.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;
using test::sameDisparity;

namespace {

synthetic::SyntheticScan scan(int frames) {
  synthetic::SyntheticScanOptions options;
  options.width = 640;
  options.height = 360;
  options.frames = frames;
  options.seed = 4;
  return synthetic::SyntheticScan(options);
}

}  // namespace

TEST(DisparityRangeCuda, SameSparseDisparitiesAndRangeAsTheCpu) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const synthetic::SyntheticScan s = scan(3);
  DisparityRangeEstimator cpu(Device::Cpu), gpu(Device::Cuda);
  DisparityRange cpuRange, gpuRange;
  for (int k = 0; k < s.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = s.renderFrame(k);
    const DisparitySample a = cpu.measure(frame.leftRectified, frame.rightRectified);
    const DisparitySample b = gpu.measure(frame.leftRectified, frame.rightRectified);
    ASSERT_GT(a.matches(), 100);
    EXPECT_EQ(a.disparitiesPx, b.disparitiesPx) << "frame " << k;
    EXPECT_EQ(a.lowPx, b.lowPx);
    EXPECT_EQ(a.highPx, b.highPx);
    cpuRange = k == 0 ? cpu.wantedRange(a) : cpu.followingRange(cpuRange, a);
    gpuRange = k == 0 ? gpu.wantedRange(b) : gpu.followingRange(gpuRange, b);
    EXPECT_EQ(cpuRange, gpuRange) << "frame " << k << ": " << cpuRange.text() << " against " << gpuRange.text();
  }
}

TEST(DisparityRangeCuda, NewRangeBetweenFramesMatchesAFreshMatcher) {
  if (!cudaAvailable()) GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  const synthetic::SyntheticScanFrame frame = scan(1).renderFrame(0);
  StereoParameters p;
  p.setFixedDisparityRange(24, 55);
  StereoMatcher matcher(Device::Cuda, p);
  matcher.computeDisparity(frame.leftRectified, frame.rightRectified);
  // Moved (same count: the workspace stays), widened and narrowed (new workspaces).
  for (const DisparityRange range : {DisparityRange{32, 63}, DisparityRange{20, 71}, DisparityRange{36, 59}}) {
    matcher.setDisparityRange(range);
    StereoParameters fresh = p;
    fresh.setFixedDisparityRange(range.minPx, range.maxPx);
    StereoMatcher reference(Device::Cuda, fresh), cpu(Device::Cpu, fresh);
    const cv::Mat moved = matcher.computeDisparity(frame.leftRectified, frame.rightRectified);
    EXPECT_TRUE(sameDisparity(moved, reference.computeDisparity(frame.leftRectified, frame.rightRectified)))
        << range.text();
    EXPECT_TRUE(sameDisparity(moved, cpu.computeDisparity(frame.leftRectified, frame.rightRectified))) << range.text();
  }
}
