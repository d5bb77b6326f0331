// Image loading: images as written by OpenCV, and clear errors instead of empty Mats.
#include "Core/Error.h"
#include "IO/ImageFile.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

namespace tissuemosaic {
namespace {

std::string outputPath(const std::string& name) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/ImageFile";
  std::filesystem::create_directories(folder);
  return folder + "/" + name;
}

void expectError(const std::function<void()>& call, const std::string& expected) {
  try {
    call();
    ADD_FAILURE() << "no Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(ImageFile, LoadsWhatOpenCvWrote) {
  cv::Mat image(20, 30, CV_8UC3);
  cv::randu(image, 0, 256);
  const std::string path = outputPath("image.png");
  ASSERT_TRUE(cv::imwrite(path, image));
  const cv::Mat read = loadImage(path);
  ASSERT_EQ(read.size(), image.size());
  EXPECT_EQ(cv::norm(read, image, cv::NORM_INF), 0.0);  // PNG is lossless
  EXPECT_EQ(loadImage(path, cv::IMREAD_GRAYSCALE).type(), CV_8UC1);
}

TEST(ImageFile, MissingOrCorruptFilesGiveErrors) {
  const std::string missing = outputPath("no_such_image.png");
  expectError([&] { loadImage(missing); }, "cannot read image '" + missing + "': file does not exist");
  const std::string corrupt = outputPath("corrupt.png");
  {
    std::ofstream file(corrupt, std::ios::binary);
    file << "\x89PNG\r\n\x1a\n this is not really a png";
  }
  expectError([&] { loadImage(corrupt); }, "cannot read image '" + corrupt + "': the file is not a readable image");
  const std::string text = outputPath("text.jpg");
  {
    std::ofstream file(text);
    file << "hello";
  }
  expectError([&] { loadImage(text); }, "not a readable image (corrupt or unsupported format)");
  expectError([&] { loadImage(TM_TEST_OUTPUT_DIR); }, "folder");
}

TEST(ImageFile, PairMustHaveOneSize) {
  const std::string left = outputPath("pair_left.png"), right = outputPath("pair_right.png"),
                    other = outputPath("pair_other.png");
  ASSERT_TRUE(cv::imwrite(left, cv::Mat(24, 32, CV_8UC3, cv::Scalar(1, 2, 3))));
  ASSERT_TRUE(cv::imwrite(right, cv::Mat(24, 32, CV_8UC3, cv::Scalar(4, 5, 6))));
  ASSERT_TRUE(cv::imwrite(other, cv::Mat(24, 33, CV_8UC3)));
  const ImagePair pair = loadImagePair(left, right);
  EXPECT_EQ(pair.left.at<cv::Vec3b>(0, 0), cv::Vec3b(1, 2, 3));
  EXPECT_EQ(pair.right.at<cv::Vec3b>(23, 31), cv::Vec3b(4, 5, 6));
  expectError([&] { loadImagePair(left, other); }, "left '" + left + "' is 32x24 but right '" + other + "' is 33x24");
  expectError([&] { loadImagePair(left, outputPath("gone.png")); }, "does not exist");
}

// Issue 32: libjpeg decodes a JPEG cut short into a half-grey image with only a warning; a header declaring a
// 20000x20000 image ended in std::bad_alloc. Both are errors that say so; the whole JPEG still loads.
TEST(ImageFile, TruncatedJpegAndHugeImagesAreRefused) {
  cv::Mat image(120, 160, CV_8UC3);
  cv::randu(image, 0, 256);
  const std::string whole = outputPath("whole.jpg"), cut = outputPath("cut.jpg");
  ASSERT_TRUE(cv::imwrite(whole, image));
  EXPECT_EQ(loadImage(whole).size(), image.size());
  std::filesystem::copy_file(whole, cut, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::resize_file(cut, std::filesystem::file_size(whole) / 2);
  expectError([&] { loadImage(cut); }, "cannot read image '" + cut + "': the JPEG file is truncated");
  // Trailing zero padding after the end-of-image marker is common and harmless.
  std::filesystem::copy_file(whole, outputPath("padded.jpg"), std::filesystem::copy_options::overwrite_existing);
  std::ofstream(outputPath("padded.jpg"), std::ios::binary | std::ios::app) << std::string(16, '\0');
  EXPECT_EQ(loadImage(outputPath("padded.jpg")).size(), image.size());

  // A PNG whose header says 20000x20000 (a 1x1 image with its IHDR size rewritten; its checksum no longer matters,
  // the size is refused before decoding).
  std::vector<uchar> png;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(1, 1, CV_8UC3, cv::Scalar::all(0)), png));
  const auto putBigEndian = [&](std::size_t at, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) png[at + i] = static_cast<uchar>(value >> (24 - 8 * i));
  };
  putBigEndian(16, 20000);
  putBigEndian(20, 20000);
  const std::string huge = outputPath("huge.png");
  std::ofstream(huge, std::ios::binary).write(reinterpret_cast<const char*>(png.data()),
                                              static_cast<std::streamsize>(png.size()));
  expectError([&] { loadImage(huge); }, "its header declares 20000x20000 pixels, more than the 67 megapixels");

  // The same for a BMP (fuzz_image: OpenCV allocated 2.4 GB for one before finding its data missing); a BMP within the
  // limit still reads, whichever way its rows run (a negative height: top-down).
  std::vector<uchar> bmp;
  ASSERT_TRUE(cv::imencode(".bmp", image, bmp));
  const std::string bmpPath = outputPath("image.bmp");
  const auto writeBmp = [&](std::int32_t width, std::int32_t height) {
    std::vector<uchar> bytes = bmp;
    for (int i = 0; i < 4; ++i) {
      bytes[18 + i] = static_cast<uchar>(static_cast<std::uint32_t>(width) >> (8 * i));
      bytes[22 + i] = static_cast<uchar>(static_cast<std::uint32_t>(height) >> (8 * i));
    }
    std::ofstream(bmpPath, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                   static_cast<std::streamsize>(bytes.size()));
  };
  writeBmp(160, 120);
  EXPECT_EQ(loadImage(bmpPath).size(), image.size());
  writeBmp(30000, -30000);
  expectError([&] { loadImage(bmpPath); }, "its header declares 30000x30000 pixels, more than the 67 megapixels");
}

}  // namespace
}  // namespace tissuemosaic
