// 3D video layouts (IO/StereoVideoLayout): a synthetic scan packed into each layout, written as a lossless video
// and read back through StereoFrameSource, reconstructs to the same model as the same eyes read from frame folders.
#include "Core/Error.h"
#include "IO/StereoFrameSource.h"
#include "IO/StereoVideoLayout.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "SyntheticScan.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <filesystem>

namespace tissuemosaic {
namespace {

constexpr VideoLayout kLayouts[] = {VideoLayout::SideBySide, VideoLayout::SideBySideHalf, VideoLayout::TopBottom,
                                    VideoLayout::TopBottomHalf, VideoLayout::RowInterlaced};

std::filesystem::path freshFolder(const std::string& name) {
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "VideoLayouts" / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

TEST(StereoVideoLayout, NamesAndPackingGeometry) {
  for (VideoLayout layout : kLayouts) EXPECT_EQ(parseVideoLayout(videoLayoutName(layout)), layout);
  EXPECT_THROW(parseVideoLayout("side-by-side"), Error);
  EXPECT_EQ(eyeSizeOf({1920, 1080}, VideoLayout::SideBySide), cv::Size(960, 1080));
  EXPECT_EQ(eyeSizeOf({1920, 1080}, VideoLayout::SideBySideHalf), cv::Size(1920, 1080));
  EXPECT_EQ(eyeSizeOf({1920, 1080}, VideoLayout::TopBottom), cv::Size(1920, 540));
  EXPECT_EQ(eyeSizeOf({1920, 1080}, VideoLayout::TopBottomHalf), cv::Size(1920, 1080));
  EXPECT_EQ(eyeSizeOf({1920, 1080}, VideoLayout::RowInterlaced), cv::Size(1920, 540));
  EXPECT_THROW(eyeSizeOf({1921, 1080}, VideoLayout::SideBySide), Error);
  EXPECT_THROW(eyeSizeOf({1920, 1081}, VideoLayout::RowInterlaced), Error);

  // Distinct eyes: every layout puts each eye's pixels where it says (row-interlaced: even rows are the left eye).
  cv::Mat left(4, 6, CV_8UC3), right(4, 6, CV_8UC3);
  cv::randu(left, 0, 128);
  cv::randu(right, 128, 256);
  const cv::Mat rows = packStereoFrame(left, right, VideoLayout::RowInterlaced);
  EXPECT_EQ(cv::norm(rows.row(2), left.row(1), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(rows.row(5), right.row(2), cv::NORM_INF), 0.0);
  const cv::Mat tb = packStereoFrame(left, right, VideoLayout::TopBottom);
  EXPECT_EQ(cv::norm(tb.rowRange(4, 8), right, cv::NORM_INF), 0.0);
  for (VideoLayout layout : {VideoLayout::SideBySide, VideoLayout::TopBottom, VideoLayout::RowInterlaced}) {
    cv::Mat l, r;
    unpackStereoFrame(packStereoFrame(left, right, layout), layout, l, r);
    EXPECT_EQ(cv::norm(l, left, cv::NORM_INF), 0.0) << videoLayoutName(layout);
    EXPECT_EQ(cv::norm(r, right, cv::NORM_INF), 0.0) << videoLayoutName(layout);
  }
}

/// The model and key frames of a whole source, reconstructed on the CPU.
ModelPoints reconstruct(StereoFrameSource& source, const RectifiedGeometry& geometry, int& frames) {
  ReconstructionPipeline pipeline(geometry, ReconstructionParameters{}, Device::Cpu);
  StereoFrame frame;
  frames = 0;
  while (source.next(frame)) {
    pipeline.process(frame.left, frame.right, frame.timeS);
    ++frames;
  }
  return pipeline.modelSnapshot();
}

TEST(StereoVideoLayout, EveryLayoutRoundTripsAScanToTheFrameFoldersModel) {
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 180;
  options.frames = 6;
  options.seed = 31;
  const synthetic::SyntheticScan scan(options);
  std::vector<synthetic::SyntheticScanFrame> frames;
  for (int k = 0; k < scan.frameCount(); ++k) frames.push_back(scan.renderFrame(k));

  for (VideoLayout layout : kLayouts) {
    const std::string name = videoLayoutName(layout);
    const std::filesystem::path folder = freshFolder(name);
    std::filesystem::create_directories(folder / "left");
    std::filesystem::create_directories(folder / "right");
    const std::string video = (folder / "scan.avi").string();
    cv::VideoWriter writer;
    for (const synthetic::SyntheticScanFrame& frame : frames) {
      const cv::Mat packed = packStereoFrame(frame.leftRectified, frame.rightRectified, layout);
      if (!writer.isOpened()) {
        ASSERT_TRUE(writer.open(video, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('F', 'F', 'V', '1'), options.fps,
                                packed.size()))
            << "OpenCV cannot write lossless FFV1 AVI here";
      }
      writer.write(packed);
      // The frame folders hold the eyes as the layout carries them: whole for sbs, tb and rows; a squeezed layout
      // carries each eye at half resolution, so its folders hold the eyes squeezed and stretched back.
      cv::Mat left = frame.leftRectified, right = frame.rightRectified;
      if (layout == VideoLayout::SideBySideHalf || layout == VideoLayout::TopBottomHalf) {
        const cv::Size half = layout == VideoLayout::SideBySideHalf ? cv::Size(left.cols / 2, left.rows)
                                                                     : cv::Size(left.cols, left.rows / 2);
        cv::Mat squeezedLeft, squeezedRight;
        cv::resize(frame.leftRectified, squeezedLeft, half, 0, 0, cv::INTER_AREA);
        cv::resize(frame.rightRectified, squeezedRight, half, 0, 0, cv::INTER_AREA);
        cv::resize(squeezedLeft, left, frame.leftRectified.size(), 0, 0, cv::INTER_LINEAR);
        cv::resize(squeezedRight, right, frame.leftRectified.size(), 0, 0, cv::INTER_LINEAR);
      }
      cv::imwrite((folder / "left" / cv::format("%04d.png", frame.index)).string(), left);
      cv::imwrite((folder / "right" / cv::format("%04d.png", frame.index)).string(), right);
    }
    writer.release();

    auto fromVideo = StereoFrameSource::openStereoVideo(video, layout);
    auto fromFolders = StereoFrameSource::openFrameFolders((folder / "left").string(), (folder / "right").string(),
                                                           options.fps);
    ASSERT_EQ(fromVideo->frameSize(), scan.geometry().imageSize) << name;
    EXPECT_FALSE(fromVideo->isLive());
    int videoFrames = 0, folderFrames = 0;
    const ModelPoints viaVideo = reconstruct(*fromVideo, scan.geometry(), videoFrames);
    const ModelPoints viaFolders = reconstruct(*fromFolders, scan.geometry(), folderFrames);
    EXPECT_EQ(videoFrames, options.frames) << name;
    EXPECT_EQ(folderFrames, options.frames) << name;
    ASSERT_GT(viaFolders.size(), 10000u) << name;
    ASSERT_EQ(viaVideo.size(), viaFolders.size()) << name;
    double largestDifferenceMm = 0;
    int colourDifferences = 0;
    for (std::size_t i = 0; i < viaVideo.size(); ++i) {
      largestDifferenceMm = std::max(largestDifferenceMm,
                                     cv::norm(viaVideo.cloud.pointsMm[i] - viaFolders.cloud.pointsMm[i]));
      colourDifferences += viaVideo.cloud.colorsRgb[i] != viaFolders.cloud.colorsRgb[i];
    }
    EXPECT_EQ(largestDifferenceMm, 0.0) << name;
    EXPECT_EQ(colourDifferences, 0) << name;
  }
}

}  // namespace
}  // namespace tissuemosaic
