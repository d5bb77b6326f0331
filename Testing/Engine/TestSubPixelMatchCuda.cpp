// Sub-pixel match refinement on CUDA against the CPU (ctest label "cuda"; skipped with a message where no GPU
// exists). Both run the same functor (SubPixelKernels.h); only floating-point contraction may differ, so the lock
// decisions must agree on nearly every match and the positions to a thousandth of a pixel.
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Tracking/SubPixelMatch.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>

using namespace tissuemosaic;

namespace {

/// A scan frame and the same frame moved by a sub-pixel shift, with a grid of matches started on the pixel grid.
struct ShiftedFrame {
  cv::Mat grey, shifted;
  std::vector<SubPixelMatchQuery> queries;
};

ShiftedFrame shiftedScanFrame(int frame, float dx, float dy) {
  synthetic::SyntheticScanOptions options;
  options.frames = frame + 1;
  options.seed = 5;
  const synthetic::SyntheticScan scan(options);
  ShiftedFrame result;
  cv::cvtColor(scan.renderFrame(frame).leftRectified, result.grey, cv::COLOR_BGR2GRAY);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, dy);
  cv::warpAffine(result.grey, result.shifted, shift, result.grey.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  for (int y = 20; y < result.grey.rows - 20; y += 9) {
    for (int x = 20; x < result.grey.cols - 20; x += 9) {
      SubPixelMatchQuery q;
      q.fromPx = cv::Point2f(static_cast<float>(x), static_cast<float>(y));
      q.toPx = cv::Point2f(std::round(x + dx), std::round(y + dy));
      result.queries.push_back(q);
    }
  }
  return result;
}

struct Agreement {
  int lockedCpu = 0, lockDiffers = 0, bothLocked = 0, positionDiffers = 0;
};

Agreement compare(const std::vector<SubPixelMatchAnswer>& a, const std::vector<SubPixelMatchAnswer>& b) {
  Agreement result;
  EXPECT_EQ(a.size(), b.size());
  double worstPx = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    result.lockedCpu += a[i].locked;
    result.lockDiffers += a[i].locked != b[i].locked;
    if (!a[i].locked || !b[i].locked) continue;
    ++result.bothLocked;
    const double d = std::hypot(a[i].toPx.x - b[i].toPx.x, a[i].toPx.y - b[i].toPx.y);
    worstPx = std::max(worstPx, d);
    result.positionDiffers += d > 1e-3;
  }
  std::printf("%zu matches: %d locked on the CPU, lock differs on %d, positions differ > 0.001 px on %d of %d "
              "(worst %.2g px)\n", a.size(), result.lockedCpu, result.lockDiffers, result.positionDiffers,
              result.bothLocked, worstPx);
  return result;
}

}  // namespace

TEST(SubPixelMatchCuda, AgreesWithTheCpuOnAShiftedScanFrame) {
  if (!cudaAvailable()) {
    GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  }
  const ShiftedFrame frame = shiftedScanFrame(0, 0.4f, -0.3f);
  SubPixelMatcher cpu(Device::Cpu, 2.0), gpu(Device::Cuda, 2.0);
  const Agreement agreement = compare(cpu.refine({frame.grey, frame.shifted}, frame.queries),
                                      gpu.refine({frame.grey, frame.shifted}, frame.queries));
  EXPECT_GT(agreement.lockedCpu, static_cast<int>(frame.queries.size() / 3));
  EXPECT_LE(agreement.lockDiffers, static_cast<int>(0.002 * frame.queries.size()));
  EXPECT_LE(agreement.positionDiffers, static_cast<int>(0.002 * agreement.bothLocked));
}

TEST(SubPixelMatchCuda, CachedDeviceImagesGiveTheSameAnswers) {
  if (!cudaAvailable()) {
    GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  }
  const ShiftedFrame a = shiftedScanFrame(0, 0.4f, -0.3f), b = shiftedScanFrame(2, -0.6f, 0.2f);
  SubPixelMatcher cpu(Device::Cpu, 2.0), gpu(Device::Cuda, 2.0);
  const auto expectedA = cpu.refine({a.grey, a.shifted}, a.queries);
  const auto expectedB = cpu.refine({b.grey, b.shifted}, b.queries);
  // The first call caches ids 1 and 2; the second uploads ids 3 and 4; the third finds 1 and 2 still cached.
  const auto first = gpu.refine({a.grey, a.shifted}, a.queries, {1, 2});
  const auto second = gpu.refine({b.grey, b.shifted}, b.queries, {3, 4});
  const auto third = gpu.refine({a.grey, a.shifted}, a.queries, {1, 2});
  for (const auto* pair : {&first, &third}) {
    const Agreement agreement = compare(expectedA, *pair);
    EXPECT_LE(agreement.lockDiffers, static_cast<int>(0.002 * a.queries.size()));
  }
  const Agreement agreement = compare(expectedB, second);
  EXPECT_LE(agreement.lockDiffers, static_cast<int>(0.002 * b.queries.size()));
  // The images can also be swapped between the slots of a call.
  const auto swapped = gpu.refine({a.shifted, a.grey}, [&] {
    auto queries = a.queries;
    for (auto& q : queries) std::swap(q.referenceImage, q.image);
    return queries;
  }(), {2, 1});
  const auto expectedSwapped = cpu.refine({a.shifted, a.grey}, [&] {
    auto queries = a.queries;
    for (auto& q : queries) std::swap(q.referenceImage, q.image);
    return queries;
  }());
  EXPECT_LE(compare(expectedSwapped, swapped).lockDiffers, static_cast<int>(0.002 * a.queries.size()));
  EXPECT_THROW(gpu.refine({a.grey, a.shifted}, a.queries, {1}), Error);
}

// With retained images, a call naming frames that earlier calls uploaded finds them on the device (the refiner
// reusing the tracker's frames); without, they are uploaded again. Same answers either way.
TEST(SubPixelMatchCuda, RetainedImagesAreNotUploadedAgain) {
  if (!cudaAvailable()) {
    GTEST_SKIP() << "no usable CUDA device: " << cudaUnavailableReason();
  }
  const ShiftedFrame a = shiftedScanFrame(0, 0.4f, -0.3f);
  EXPECT_EQ(SubPixelMatcher(Device::Cpu, 2.0).uploadedImages(), 0);
  const auto run = [&](int retained) {
    SubPixelMatcher gpu(Device::Cuda, 2.0);
    gpu.setRetainedImages(retained);
    // "Tracking": the reference (id 100) with a new frame each call, as the tracker does.
    for (int64_t frame = 1; frame <= 4; ++frame) gpu.refine({a.grey, a.shifted}, a.queries, {100, frame});
    const long long afterTracking = gpu.uploadedImages();
    EXPECT_EQ(afterTracking, retained >= 5 ? 5 : afterTracking);
    // "Refinement": the reference against the frames tracked before.
    std::vector<SubPixelMatchQuery> queries;
    for (int image = 1; image <= 4; ++image) {
      for (SubPixelMatchQuery q : a.queries) {
        q.referenceImage = 0;
        q.image = image;
        queries.push_back(q);
      }
    }
    const auto answers = gpu.refine({a.grey, a.shifted, a.shifted, a.shifted, a.shifted}, queries, {100, 1, 2, 3, 4});
    return std::make_pair(gpu.uploadedImages() - afterTracking, answers);
  };
  const auto [uploadsRetained, answersRetained] = run(6);
  const auto [uploadsDefault, answersDefault] = run(0);
  std::printf("uploads at the refinement call: %lld with 6 images retained, %lld without\n", uploadsRetained,
              uploadsDefault);
  EXPECT_EQ(uploadsRetained, 0);
  EXPECT_GE(uploadsDefault, 2);
  ASSERT_EQ(answersRetained.size(), answersDefault.size());
  long differ = 0;
  for (std::size_t i = 0; i < answersRetained.size(); ++i) {
    differ += answersRetained[i].locked != answersDefault[i].locked || answersRetained[i].toPx != answersDefault[i].toPx;
  }
  EXPECT_EQ(differ, 0);
}
