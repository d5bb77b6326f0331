// Live video (IO/LiveVideoCapture): a GStreamer pipeline that plays frames at 30 fps into appsink, read by a consumer
// slower than the source: it gets the newest frame each time, the frames it missed are counted as dropped, and an
// interrupt stops a waiting read at once. Needs OpenCV's GStreamer backend and gstreamer1.0-plugins-good (setup.sh).
#include "Core/Error.h"
#include "IO/LiveVideoCapture.h"
#include "IO/StereoFrameSource.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio/registry.hpp>

#include <chrono>
#include <filesystem>
#include <thread>

namespace tissuemosaic {
namespace {

constexpr int kFrames = 45;

/// Side-by-side frames whose top-left pixels encode the frame index (PNG keeps them exactly).
std::string writePackedFrames(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "LiveVideo" / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat left(60, 80, CV_8UC3, cv::Scalar(40, 80, 120)), right(60, 80, CV_8UC3, cv::Scalar(200, 80, 40));
    left.at<cv::Vec3b>(0, 0) = cv::Vec3b(static_cast<uchar>(i), 0, 0);
    right.at<cv::Vec3b>(0, 0) = cv::Vec3b(static_cast<uchar>(i), 255, 255);
    cv::Mat packed;
    cv::hconcat(left, right, packed);
    cv::imwrite((folder / cv::format("%04d.png", i)).string(), packed);
  }
  return folder.string();
}

std::string pipelinePlaying(const std::string& folder, int lastIndex) {
  return "multifilesrc location=" + folder + "/%04d.png index=0 stop-index=" + std::to_string(lastIndex) +
         " caps=image/png,framerate=30/1 ! pngdec ! videoconvert ! video/x-raw,format=BGR ! appsink";
}

bool gstreamerAvailable() { return cv::videoio_registry::hasBackend(cv::CAP_GSTREAMER); }

TEST(LiveVideoCapture, InputKinds) {
  EXPECT_EQ(videoInputKind("/dev/video0"), VideoInputKind::Device);
  EXPECT_EQ(videoInputKind("v4l2src ! videoconvert ! appsink"), VideoInputKind::GStreamerPipeline);
  EXPECT_EQ(videoInputKind("clip.mp4"), VideoInputKind::File);
  EXPECT_THROW(LiveVideoCapture("/dev/video-none-such", 1.0), Error);
}

TEST(LiveVideoCapture, SlowConsumerGetsTheNewestFrameAndDropsAreCounted) {
  if (!gstreamerAvailable()) GTEST_SKIP() << "this OpenCV has no GStreamer backend";
  const std::string folder = writePackedFrames("slow");
  auto source = StereoFrameSource::openStereoVideo(pipelinePlaying(folder, kFrames - 1), VideoLayout::SideBySide);
  EXPECT_TRUE(source->isLive());
  EXPECT_EQ(source->frameSize(), cv::Size(80, 60));
  std::vector<int> seen;
  StereoFrame frame;
  while (source->next(frame)) {
    const int index = frame.left.at<cv::Vec3b>(0, 0)[0];
    EXPECT_EQ(frame.right.at<cv::Vec3b>(0, 0)[0], index) << "both eyes come from one packed frame";
    EXPECT_EQ(frame.right.at<cv::Vec3b>(0, 0)[1], 255);
    seen.push_back(index);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a reconstruction at 10 fps, the source at 30
  }
  ASSERT_GE(seen.size(), 3u);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]) << "never an older frame";
  EXPECT_EQ(seen.back(), kFrames - 1) << "the last frame is the newest";
  // Every frame the pipeline played was either returned or counted as dropped.
  EXPECT_EQ(static_cast<long long>(seen.size()) + source->droppedFrames(), kFrames);
  EXPECT_GT(source->droppedFrames(), kFrames / 3) << "at a third of the source's rate, most frames are dropped";
}

TEST(LiveVideoCapture, InterruptEndsAWaitAtOnce) {
  if (!gstreamerAvailable()) GTEST_SKIP() << "this OpenCV has no GStreamer backend";
  const std::string folder = writePackedFrames("interrupt");
  // loop=true plays for ever: only the interrupt ends it.
  auto source = StereoFrameSource::openStereoVideo(
      "multifilesrc location=" + folder + "/%04d.png index=0 stop-index=" + std::to_string(kFrames - 1) +
          " loop=true caps=image/png,framerate=30/1 ! pngdec ! videoconvert ! video/x-raw,format=BGR ! appsink",
      VideoLayout::SideBySide);
  StereoFrame frame;
  ASSERT_TRUE(source->next(frame));
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    source->interrupt();
  });
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  while (source->next(frame)) ++frames;
  stopper.join();
  EXPECT_GT(frames, 0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

TEST(LiveVideoCapture, FramesThatCannotHoldTwoEyesAreRefused) {
  if (!gstreamerAvailable()) GTEST_SKIP() << "this OpenCV has no GStreamer backend";
  // Video files cannot hold odd sizes (FFmpeg's writers round them), a pipeline can.
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "LiveVideo" / "odd";
  std::filesystem::create_directories(folder);
  cv::imwrite((folder / "0000.png").string(), cv::Mat(47, 64, CV_8UC3, cv::Scalar(1, 2, 3)));
  const std::string pipeline = pipelinePlaying(folder.string(), 0);
  EXPECT_NO_THROW(StereoFrameSource::openStereoVideo(pipeline, VideoLayout::SideBySide));
  for (VideoLayout layout : {VideoLayout::TopBottom, VideoLayout::TopBottomHalf, VideoLayout::RowInterlaced}) {
    try {
      StereoFrameSource::openStereoVideo(pipeline, layout);
      ADD_FAILURE() << videoLayoutName(layout) << ": no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("height must be even"), std::string::npos) << e.what();
    }
  }
}

TEST(LiveVideoCapture, BrokenPipelineIsAClearError) {
  if (!gstreamerAvailable()) GTEST_SKIP() << "this OpenCV has no GStreamer backend";
  try {
    LiveVideoCapture capture("nosuchelement ! appsink", 2.0);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("GStreamer pipeline"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tissuemosaic
