// PFM files: round trip with NaN, orientation (row 0 is the top), endianness, and errors.
#include "Core/Error.h"
#include "IO/DisparityPfm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

namespace tissuemosaic {
namespace {

std::string outputPath(const std::string& name) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/DisparityPfm";
  std::filesystem::create_directories(folder);
  return folder + "/" + name;
}

std::string readBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(DisparityPfm, RoundTripKeepsValuesAndNaN) {
  cv::Mat disparity(37, 53, CV_32F);
  cv::randu(disparity, -20.0f, 80.0f);
  disparity.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  disparity.at<float>(36, 52) = std::numeric_limits<float>::quiet_NaN();
  disparity.at<float>(5, 7) = std::numeric_limits<float>::infinity();
  const std::string path = outputPath("roundtrip.pfm");
  writePfm(path, disparity);
  EXPECT_EQ(std::filesystem::file_size(path), std::string("Pf\n53 37\n-1.0\n").size() + 37 * 53 * 4);
  const cv::Mat read = readPfm(path);
  ASSERT_EQ(read.type(), CV_32FC1);
  ASSERT_EQ(read.size(), disparity.size());
  EXPECT_EQ(std::memcmp(read.ptr(), disparity.ptr(), disparity.total() * 4), 0) << "bit-exact, NaN included";
  EXPECT_TRUE(std::isnan(read.at<float>(0, 0)));
  EXPECT_TRUE(std::isnan(read.at<float>(36, 52)));
}

TEST(DisparityPfm, FileStoresBottomRowFirst) {
  // A hand-made 2x3 little-endian file: the first row in the file is the bottom of the image.
  std::string bytes = "Pf\n2 3\n-1.0\n";
  const float stored[6] = {5, 6, 3, 4, 1, 2};  // bottom row (5 6), middle (3 4), top (1 2)
  bytes.append(reinterpret_cast<const char*>(stored), sizeof(stored));
  const std::string path = outputPath("orientation.pfm");
  writeBytes(path, bytes);
  const cv::Mat read = readPfm(path);
  ASSERT_EQ(read.size(), cv::Size(2, 3));
  EXPECT_EQ(read.at<float>(0, 0), 1.0f) << "pixel (0,0) is the top-left";
  EXPECT_EQ(read.at<float>(0, 1), 2.0f);
  EXPECT_EQ(read.at<float>(2, 0), 5.0f);
  // And writePfm produces exactly these bytes from the top-down image.
  const cv::Mat image = (cv::Mat_<float>(3, 2) << 1, 2, 3, 4, 5, 6);
  const std::string written = outputPath("orientation_written.pfm");
  writePfm(written, image);
  EXPECT_EQ(readBytes(written), bytes);
}

TEST(DisparityPfm, ReadsBigEndianAndColour) {
  std::string bytes = "PF\n1 1\n1.0\n";  // positive scale: big-endian
  for (float v : {1.5f, -2.0f, 1e10f}) {
    char raw[4];
    std::memcpy(raw, &v, 4);
    std::reverse(raw, raw + 4);
    bytes.append(raw, 4);
  }
  const std::string path = outputPath("bigendian.pfm");
  writeBytes(path, bytes);
  const cv::Mat read = readPfm(path);
  ASSERT_EQ(read.type(), CV_32FC3);
  EXPECT_EQ(read.at<cv::Vec3f>(0, 0), cv::Vec3f(1.5f, -2.0f, 1e10f));
}

void expectError(const std::string& path, const std::string& expected) {
  try {
    readPfm(path);
    ADD_FAILURE() << path << ": no Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(DisparityPfm, BadFilesGiveErrors) {
  expectError(outputPath("missing.pfm"), "does not exist");
  const std::string good = outputPath("good.pfm");
  writePfm(good, cv::Mat(4, 5, CV_32F, cv::Scalar(1.0f)));
  const std::string bytes = readBytes(good);
  const std::string truncated = outputPath("truncated.pfm");
  writeBytes(truncated, bytes.substr(0, bytes.size() - 3));
  expectError(truncated, "truncated");
  const std::string wrongMagic = outputPath("wrong_magic.pfm");
  writeBytes(wrongMagic, "P5\n4 5\n255\n" + std::string(20, 'x'));
  expectError(wrongMagic, "not a PFM");
  const std::string badHeader = outputPath("bad_header.pfm");
  writeBytes(badHeader, "Pf\nfour five\n-1.0\n");
  expectError(badHeader, "malformed header");
  const std::string zeroScale = outputPath("zero_scale.pfm");
  writeBytes(zeroScale, "Pf\n1 1\n0\n" + std::string(4, '\0'));
  expectError(zeroScale, "scale");
  const std::string hugeSize = outputPath("huge.pfm");
  writeBytes(hugeSize, "Pf\n100000000 100000000\n-1.0\n");
  expectError(hugeSize, "implausible");
  // Found by fuzz_pfm (corpus/fuzz_pfm/crash-*): a plausible but huge size was allocated before the floats were
  // counted (4 TB for 2^20 x 2^20: allocation-size-too-big under ASan, cv::Exception without).
  const std::string declaredHuge = outputPath("declared_huge.pfm");
  writeBytes(declaredHuge, "Pf\n1048576 1048576\n-1.0\n" + std::string(4, '\0'));
  std::string message;
  try {
    readPfm(declaredHuge);
  } catch (const Error& error) {
    message = error.what();
  }
  EXPECT_NE(message.find("1048576x1048576 floats expected, 4 bytes found"), std::string::npos) << message;

  EXPECT_THROW(writePfm(outputPath("no_such_folder/x.pfm"), cv::Mat(2, 2, CV_32F)), Error);
  EXPECT_THROW(writePfm(outputPath("wrong_type.pfm"), cv::Mat(2, 2, CV_64F)), Error);
  EXPECT_THROW(writePfm(outputPath("empty.pfm"), cv::Mat()), Error);
}

}  // namespace
}  // namespace tissuemosaic
