// The engine's grey conversion (one helper for stereo and tracking, which each had their own) against OpenCV's.
#include "Core/Error.h"
#include "ErrorText.h"
#include "Core/PixelFormat.h"
#include "Tracking/StereoFeatures.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

namespace tissuemosaic {
namespace {

cv::Mat randomImage(int type, uint64_t seed, cv::Size size = {53, 37}) {
  cv::Mat image(size, type);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

int differingPixels(const cv::Mat& a, const cv::Mat& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_EQ(a.type(), b.type());
  return cv::countNonZero(a != b);
}

TEST(PixelFormat, GreyIsOpenCvsConversionOfEveryLayout) {
  const cv::Mat bgr = randomImage(CV_8UC3, 1), bgra = randomImage(CV_8UC4, 2);
  cv::Mat expectedFromBgr, expectedFromBgra;
  cv::cvtColor(bgr, expectedFromBgr, cv::COLOR_BGR2GRAY);
  cv::cvtColor(bgra, expectedFromBgra, cv::COLOR_BGRA2GRAY);
  EXPECT_EQ(differingPixels(toGrey8(bgr, "image"), expectedFromBgr), 0);
  EXPECT_EQ(differingPixels(toGrey8(bgra, "image"), expectedFromBgra), 0);
  // A full frame, and a view whose rows are not contiguous.
  const cv::Mat frame = randomImage(CV_8UC3, 8, {960, 540});
  cv::Mat expectedFrame;
  cv::cvtColor(frame, expectedFrame, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(differingPixels(toGrey8(frame, "image"), expectedFrame), 0);
  const cv::Rect inner(3, 5, 701, 433);
  EXPECT_EQ(differingPixels(toGrey8(frame(inner), "image"), expectedFrame(inner)), 0);

  // A continuous grey image is passed through; a grey view into a larger image comes back continuous and equal.
  const cv::Mat grey = randomImage(CV_8UC1, 3);
  EXPECT_EQ(toGrey8(grey, "image").data, grey.data);
  const cv::Mat view = grey(cv::Rect(5, 4, 30, 20));
  ASSERT_FALSE(view.isContinuous());
  const cv::Mat fromView = toGrey8(view, "image");
  EXPECT_TRUE(fromView.isContinuous());
  EXPECT_EQ(differingPixels(fromView, view), 0);
}

bool sameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(PixelFormat, RgbGivesItsBgrTwinsGreyAndColours) {
  // ReconstructionPipeline takes RGB frames in their order: their grey must be the BGR twin's bit for bit (whole,
  // in bands, and with alpha), and toContinuousBgr8 must give the BGR twin itself.
  const cv::Mat bgr = randomImage(CV_8UC3, 11, {960, 540}), bgra = randomImage(CV_8UC4, 12);
  cv::Mat rgb, rgba;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::cvtColor(bgra, rgba, cv::COLOR_BGRA2RGBA);
  EXPECT_EQ(differingPixels(toGrey8(rgb, "image", ChannelOrder::Rgb), toGrey8(bgr, "image")), 0);
  EXPECT_EQ(differingPixels(toGrey8(rgba, "image", ChannelOrder::Rgb), toGrey8(bgra, "image")), 0);
  cv::Mat banded;
  convertToGrey8(rgb, banded, "image", 8, ChannelOrder::Rgb);
  EXPECT_EQ(differingPixels(banded, toGrey8(bgr, "image")), 0);
  // The order matters: the same pixels read as BGR give another grey image.
  EXPECT_GT(differingPixels(toGrey8(rgb, "image"), toGrey8(bgr, "image")), 0);

  EXPECT_TRUE(sameImage(toContinuousBgr8(rgb, "image", ChannelOrder::Rgb), bgr));
  EXPECT_EQ(toContinuousBgr8(bgr, "image", ChannelOrder::Bgr).data, bgr.data) << "continuous BGR is not copied";
  cv::Mat bgrFromBgra;
  cv::cvtColor(bgra, bgrFromBgra, cv::COLOR_BGRA2BGR);
  EXPECT_TRUE(sameImage(toContinuousBgr8(rgba, "image", ChannelOrder::Rgb), bgrFromBgra));
  const cv::Mat view = bgr(cv::Rect(3, 5, 101, 43));
  const cv::Mat fromView = toContinuousBgr8(view, "image", ChannelOrder::Bgr);
  EXPECT_TRUE(fromView.isContinuous());
  EXPECT_TRUE(sameImage(fromView, view));
  EXPECT_THROW(toContinuousBgr8(cv::Mat(4, 4, CV_32FC3), "image", ChannelOrder::Rgb), Error);
}

TEST(PixelFormat, GreyIntoStagingMemoryWritesThatMemory) {
  // The stereo matcher converts straight into its upload staging buffer: the conversion must write the memory it
  // is given, not reallocate, and give OpenCV's pixels for every layout.
  const cv::Mat bgr = randomImage(CV_8UC3, 4), bgra = randomImage(CV_8UC4, 5), grey = randomImage(CV_8UC1, 6);
  std::vector<uint8_t> staging(static_cast<std::size_t>(bgr.total()), 0);
  for (const cv::Mat& image : {bgr, bgra, grey}) {
    // In row bands on the thread pool (the stereo matcher's for large images): the same pixels, the same memory;
    // more bands than rows are as many bands as rows.
    for (const int bands : {1, 3, 8, 10000}) {
      std::fill(staging.begin(), staging.end(), 0);
      cv::Mat view(image.rows, image.cols, CV_8UC1, staging.data());
      convertToGrey8(image, view, "image", bands);
      EXPECT_EQ(view.data, staging.data());
      EXPECT_EQ(differingPixels(cv::Mat(image.rows, image.cols, CV_8UC1, staging.data()), toGrey8(image, "image")), 0)
          << bands << " bands";
    }
  }
  // A destination of another size is reallocated, as cv::Mat::create does.
  cv::Mat small(3, 3, CV_8UC1, staging.data());
  convertToGrey8(bgr, small, "image");
  EXPECT_NE(small.data, staging.data());
  EXPECT_EQ(small.size(), bgr.size());
  EXPECT_EQ(errorOf([&] { convertToGrey8(cv::Mat(), small, "the right image"); }), "the right image is empty");
}

TEST(PixelFormat, GreyRefusesOtherImagesAndNamesThem) {
  EXPECT_EQ(errorOf([] { toGrey8(cv::Mat(), "the left image"); }), "the left image is empty");
  EXPECT_EQ(errorOf([] { toGrey8(cv::Mat(4, 4, CV_32FC1, cv::Scalar(0)), "the left image"); }),
            "the left image must be 8-bit grey, BGR or BGRA");
  EXPECT_EQ(errorOf([] { toGrey8(cv::Mat(4, 4, CV_8UC2, cv::Scalar(0)), "the left image"); }),
            "the left image must be 8-bit grey, BGR or BGRA");
}

TEST(PixelFormat, FeaturesKeepTheirOwnGreyImage) {
  // The tracker keeps each frame's grey image as the sub-pixel reference of the next frames: a grey image handed
  // in must be copied, or a caller reusing its buffer would change the reference under the tracker.
  cv::Mat grey = randomImage(CV_8UC1, 7);
  const cv::Mat before = grey.clone();
  const FeatureDetector noFeatures = [](const cv::Mat&, std::vector<cv::KeyPoint>&, cv::Mat&) {};
  const StereoFeatures features = detectFeatures(noFeatures, grey);
  EXPECT_NE(features.grey.data, grey.data);
  grey.setTo(0);
  EXPECT_EQ(differingPixels(features.grey, before), 0);
}

}  // namespace
}  // namespace tissuemosaic
