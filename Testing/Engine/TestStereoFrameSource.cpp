// Stereo video input: two frame folders (paired in name order, with time stamps from the frame rate), a
// side-by-side video and a video pair (MJPG AVI, which OpenCV writes itself), and bad input reported as errors.
#include "Core/Error.h"
#include "IO/StereoFrameSource.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <vector>

using namespace tissuemosaic;

namespace {

std::filesystem::path freshFolder(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("tm_frame_source_" + name);
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

/// A frame whose left and right halves differ and whose brightness encodes its index (survives JPEG).
cv::Mat eyeImage(int index, bool right) {
  cv::Mat image(120, 160, CV_8UC3, cv::Scalar(20 + 20 * index, right ? 200 : 60, 100));
  cv::circle(image, cv::Point(right ? 60 : 100, 60), 20, cv::Scalar(255, 255, 255), -1);
  return image;
}

double meanDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat difference;
  cv::absdiff(a, b, difference);
  const cv::Scalar m = cv::mean(difference);
  return (m[0] + m[1] + m[2]) / 3;
}

}  // namespace

TEST(StereoFrameSource, FrameFoldersPairByNameWithTimeStamps) {
  const auto folder = freshFolder("folders");
  std::filesystem::create_directories(folder / "left");
  std::filesystem::create_directories(folder / "right");
  for (int i = 0; i < 3; ++i) {
    cv::imwrite((folder / "left" / cv::format("%03d.png", 2 - i)).string(), eyeImage(2 - i, false));
    cv::imwrite((folder / "right" / cv::format("%03d.png", 2 - i)).string(), eyeImage(2 - i, true));
  }
  std::ofstream((folder / "left" / "notes.txt").string()) << "not a frame";
  auto source = StereoFrameSource::openFrameFolders((folder / "left").string(), (folder / "right").string(), 25.0);
  EXPECT_EQ(source->frameCount(), 3);
  EXPECT_EQ(source->frameSize(), cv::Size(160, 120));
  StereoFrame frame;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(source->next(frame));
    EXPECT_EQ(frame.index, i);
    EXPECT_DOUBLE_EQ(frame.timeS, i / 25.0);
    EXPECT_EQ(meanDifference(frame.left, eyeImage(i, false)), 0.0);
    EXPECT_EQ(meanDifference(frame.right, eyeImage(i, true)), 0.0);
  }
  EXPECT_FALSE(source->next(frame));
}

TEST(StereoFrameSource, SideBySideAndVideoPair) {
  const auto folder = freshFolder("videos");
  const int fourcc = cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
  cv::VideoWriter both((folder / "sbs.avi").string(), fourcc, 30.0, cv::Size(320, 120));
  cv::VideoWriter left((folder / "left.avi").string(), fourcc, 30.0, cv::Size(160, 120));
  cv::VideoWriter right((folder / "right.avi").string(), fourcc, 30.0, cv::Size(160, 120));
  // OpenCV's own MJPEG-in-AVI writer needs no codec library: every OpenCV this builds with has it, so a failure here
  // is a broken OpenCV, not a machine to skip.
  ASSERT_TRUE(both.isOpened() && left.isOpened() && right.isOpened()) << "OpenCV cannot write MJPG AVI here";
  for (int i = 0; i < 4; ++i) {
    cv::Mat sideBySide;
    cv::hconcat(eyeImage(i, false), eyeImage(i, true), sideBySide);
    both.write(sideBySide);
    left.write(eyeImage(i, false));
    right.write(eyeImage(i, true));
  }
  both.release();
  left.release();
  right.release();

  std::vector<std::unique_ptr<StereoFrameSource>> sources;
  sources.push_back(StereoFrameSource::openSideBySideVideo((folder / "sbs.avi").string()));
  sources.push_back(StereoFrameSource::openVideoPair((folder / "left.avi").string(), (folder / "right.avi").string()));
  for (auto& source : sources) {
    EXPECT_EQ(source->frameSize(), cv::Size(160, 120)) << source->description();
    StereoFrame frame;
    int frames = 0;
    while (source->next(frame)) {
      EXPECT_LT(meanDifference(frame.left, eyeImage(frames, false)), 4.0) << source->description();
      EXPECT_LT(meanDifference(frame.right, eyeImage(frames, true)), 4.0) << source->description();
      ++frames;
    }
    EXPECT_EQ(frames, 4) << source->description();
  }
}

TEST(StereoFrameSource, BadInputIsReported) {
  const auto folder = freshFolder("bad");
  std::filesystem::create_directories(folder / "left");
  std::filesystem::create_directories(folder / "right");
  std::filesystem::create_directories(folder / "empty");
  cv::imwrite((folder / "left" / "0.png").string(), eyeImage(0, false));
  cv::imwrite((folder / "left" / "1.png").string(), eyeImage(1, false));
  cv::imwrite((folder / "right" / "0.png").string(), eyeImage(0, true));
  EXPECT_THROW(StereoFrameSource::openFrameFolders((folder / "nothing").string(), (folder / "right").string(), 30), Error);
  EXPECT_THROW(StereoFrameSource::openFrameFolders((folder / "empty").string(), (folder / "right").string(), 30), Error);
  EXPECT_THROW(StereoFrameSource::openFrameFolders((folder / "left").string(), (folder / "right").string(), 30), Error);
  std::ofstream((folder / "corrupt.avi").string()) << "not a video";
  EXPECT_THROW(StereoFrameSource::openSideBySideVideo((folder / "corrupt.avi").string()), Error);
  EXPECT_THROW(StereoFrameSource::openVideoPair((folder / "missing.avi").string(), (folder / "corrupt.avi").string()), Error);
}

namespace {

/// Issue 32: videos of a pair with unequal frame counts, and a video cut short, were read silently in part.
TEST(StereoFrameSource, UnequalAndTruncatedVideosAreReported) {
  const auto folder = freshFolder("short-videos");
  const int fourcc = cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
  const auto writeVideo = [&](const std::string& name, int frames, bool rightEye, cv::Size size) {
    cv::VideoWriter writer((folder / name).string(), fourcc, 30.0, size);
    ASSERT_TRUE(writer.isOpened()) << "OpenCV cannot write MJPG AVI here";
    for (int i = 0; i < frames; ++i) {
      cv::Mat image = eyeImage(i, rightEye);
      if (size.width != image.cols) cv::hconcat(eyeImage(i, false), eyeImage(i, true), image);
      writer.write(image);
    }
  };
  writeVideo("left6.avi", 6, false, {160, 120});
  writeVideo("right3.avi", 3, true, {160, 120});
  writeVideo("sbs6.avi", 6, false, {320, 120});
  const auto messageOf = [](const std::function<void()>& action) {
    try {
      action();
    } catch (const Error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string unequal = messageOf([&] {
    StereoFrameSource::openVideoPair((folder / "left6.avi").string(), (folder / "right3.avi").string());
  });
  EXPECT_NE(unequal.find("has 6 frames but the right video"), std::string::npos) << unequal;
  EXPECT_NE(unequal.find("has 3"), std::string::npos) << unequal;

  // The side-by-side video cut after its first third: its header still declares 6 frames.
  const auto bytes = std::filesystem::file_size(folder / "sbs6.avi");
  std::filesystem::copy_file(folder / "sbs6.avi", folder / "cut.avi");
  std::filesystem::resize_file(folder / "cut.avi", bytes / 3);
  const std::string cut = messageOf([&] {
    auto source = StereoFrameSource::openSideBySideVideo((folder / "cut.avi").string());
    StereoFrame frame;
    while (source->next(frame)) {
    }
  });
  EXPECT_NE(cut.find("its header declares cannot be read (the file is truncated or corrupt)"), std::string::npos)
      << cut;
  // The whole video reads to its end without complaint (the control).
  auto whole = StereoFrameSource::openSideBySideVideo((folder / "sbs6.avi").string());
  StereoFrame frame;
  int frames = 0;
  while (whole->next(frame)) ++frames;
  EXPECT_EQ(frames, 6);
}

}  // namespace
