// StereoRig: calibration files, rectification and disparity to 3D, against points projected with OpenCV.
#include "Core/Error.h"
#include "Core/StereoRig.h"
#include "IO/Calibration/CalibrationFile.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

namespace tissuemosaic {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

std::string outputPath(const std::string& name) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/StereoRig";
  std::filesystem::create_directories(folder);
  return folder + "/" + name;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
}

/// A laparoscope-like rig: 5 mm baseline, slightly different intrinsics, a small relative rotation, distortion.
StereoCalibration syntheticCalibration(bool withDistortion = true) {
  StereoCalibration c;
  c.imageSize = {640, 480};
  c.K1 = (cv::Mat_<double>(3, 3) << 800, 0, 322.5, 0, 805, 241.0, 0, 0, 1);
  c.K2 = (cv::Mat_<double>(3, 3) << 810, 0, 315.0, 0, 812, 236.5, 0, 0, 1);
  c.D1 = withDistortion ? (cv::Mat_<double>(1, 5) << -0.12, 0.05, 0.001, -0.0005, 0.0)
                        : cv::Mat(cv::Mat::zeros(1, 5, CV_64F));
  c.D2 = withDistortion ? (cv::Mat_<double>(1, 5) << -0.10, 0.04, -0.0008, 0.0004, 0.0)
                        : cv::Mat(cv::Mat::zeros(1, 5, CV_64F));
  cv::Mat rvec = (cv::Mat_<double>(3, 1) << 0.01, -0.03, 0.005);  // slight toe-in and roll
  cv::Rodrigues(rvec, c.R);
  c.T = (cv::Mat_<double>(3, 1) << -5.0, 0.05, 0.1);
  return c;
}

TEST(StereoRig, CalibrationYamlAndXmlRoundTrip) {
  const StereoCalibration original = syntheticCalibration();
  for (const std::string name : {"calib_roundtrip.yml", "calib_roundtrip.xml"}) {
    const std::string path = outputPath(name);
    writeStereoCalibration(original, path);
    const StereoCalibration read = readStereoCalibration(path);
    EXPECT_EQ(read.imageSize, original.imageSize) << name;
    for (auto [a, b] : {std::pair{read.K1, original.K1}, {read.D1, original.D1}, {read.K2, original.K2},
                        {read.D2, original.D2}, {read.R, original.R}, {read.T, original.T}}) {
      ASSERT_EQ(a.size(), b.size()) << name;
      ASSERT_EQ(a.type(), CV_64F) << name;
      EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << name;  // FileStorage writes doubles exactly
    }
  }
}

TEST(StereoRig, CalibrationAsStereoCalibrateWritesItWithImageWidthHeight) {
  // What a typical calibration script writes: column distortion vectors, floats, image_width/image_height.
  const StereoCalibration reference = syntheticCalibration();
  const std::string path = outputPath("calib_script.yaml");
  {
    cv::FileStorage storage(path, cv::FileStorage::WRITE);
    cv::Mat d1 = reference.D1.t(), d2 = reference.D2.t();
    storage << "image_width" << 640 << "image_height" << 480;
    storage << "K1" << reference.K1 << "D1" << d1 << "K2" << reference.K2 << "D2" << d2;
    storage << "R" << reference.R << "T" << reference.T;
  }
  const StereoCalibration read = readStereoCalibration(path);
  EXPECT_EQ(read.imageSize, cv::Size(640, 480));
  EXPECT_EQ(read.D1.size(), cv::Size(5, 1));
  EXPECT_EQ(cv::norm(read.D1, reference.D1, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(read.T, reference.T, cv::NORM_INF), 0.0);
}

/// Writes `reference` as YAML with one key changed by `edit`, and expects read() to throw an Error containing
/// `expected` (and the file's path).
void expectReadError(const std::string& name, const std::function<void(cv::FileStorage&)>& write,
                     const std::string& expected) {
  const std::string path = outputPath(name);
  {
    cv::FileStorage storage(path, cv::FileStorage::WRITE);
    write(storage);
  }
  try {
    readStereoCalibration(path);
    ADD_FAILURE() << name << ": no Error thrown";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(expected), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find(path), std::string::npos) << name << ": " << message;
  }
}

TEST(StereoRig, BadCalibrationFilesGiveErrors) {
  const StereoCalibration c = syntheticCalibration();
  // Writes every key except `skip`, with `replace` for key `replaced`.
  auto writer = [&](const std::string& skip, const std::string& replaced, cv::Mat replacement) {
    return [=](cv::FileStorage& s) {
      const std::pair<std::string, cv::Mat> keys[] = {{"K1", c.K1}, {"D1", c.D1}, {"K2", c.K2},
                                                      {"D2", c.D2}, {"R", c.R},   {"T", c.T}};
      if (skip != "imageSize") s << "imageSize" << c.imageSize;
      for (const auto& [key, value] : keys) {
        if (key == skip) continue;
        s << key << (key == replaced ? replacement : value);
      }
    };
  };
  expectReadError("bad_missing_T.yml", writer("T", "", {}), "'T' is missing");
  expectReadError("bad_missing_K2.yml", writer("K2", "", {}), "'K2' is missing");
  expectReadError("bad_shape_K1.yml", writer("", "K1", cv::Mat::eye(2, 3, CV_64F)), "K1 must be a 3x3");
  expectReadError("bad_shape_D1.yml", writer("", "D1", cv::Mat::zeros(1, 3, CV_64F)), "D1 must be 1xN");
  expectReadError("bad_shape_T.yml", writer("", "T", cv::Mat::ones(2, 1, CV_64F)), "T must be a 3x1");
  cv::Mat scaledR = c.R * 1.1;
  expectReadError("bad_rotation_scaled.yml", writer("", "R", scaledR), "R is not a rotation");
  cv::Mat mirrorR = cv::Mat::eye(3, 3, CV_64F);
  mirrorR.at<double>(2, 2) = -1;
  expectReadError("bad_rotation_mirror.yml", writer("", "R", mirrorR), "R is not a rotation");
  expectReadError("bad_zero_baseline.yml", writer("", "T", cv::Mat::zeros(3, 1, CV_64F)), "baseline");
  cv::Mat negativeFocal = c.K2.clone();
  negativeFocal.at<double>(0, 0) = -810;
  expectReadError("bad_focal_negative.yml", writer("", "K2", negativeFocal), "positive focal");
  cv::Mat zeroFocal = c.K1.clone();
  zeroFocal.at<double>(1, 1) = 0;
  expectReadError("bad_focal_zero.yml", writer("", "K1", zeroFocal), "positive focal");
  cv::Mat nanK = c.K1.clone();
  nanK.at<double>(0, 2) = std::numeric_limits<double>::quiet_NaN();
  expectReadError("bad_nan.yml", writer("", "K1", nanK), "NaN");
  expectReadError("bad_text_K1.yml", [&](cv::FileStorage& s) {
    writer("K1", "", {})(s);
    s << "K1" << "eight hundred";
  }, "'K1' is not a matrix");
}

TEST(StereoRig, CalibrationWithoutImageSizeTakesTheFrames) {
  // The size is no longer required in the file (issue 31: files as they ship); the rectifier still needs one.
  const std::string path = outputPath("no_size.yml");
  {
    const StereoCalibration c = syntheticCalibration();
    cv::FileStorage storage(path, cv::FileStorage::WRITE);
    storage << "K1" << c.K1 << "D1" << c.D1 << "K2" << c.K2 << "D2" << c.D2 << "R" << c.R << "T" << c.T;
  }
  StereoCalibration read = readStereoCalibration(path);
  EXPECT_TRUE(read.imageSize.empty());
  EXPECT_THROW(StereoRectifier{read}, Error);
  read.adoptFrameSize({640, 480}, "test frames");
  EXPECT_EQ(StereoRectifier(read).geometry().imageSize, cv::Size(640, 480));
}

TEST(StereoRig, UnreadableCalibrationFilesGiveErrors) {
  auto expectMessage = [](const std::string& path, const std::string& expected) {
    try {
      readStereoCalibration(path);
      ADD_FAILURE() << path << ": no Error thrown";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  expectMessage(outputPath("no_such_calibration.yml"), "does not exist");
  const std::string garbage = outputPath("garbage_calibration.yml");
  writeText(garbage, "%YAML:1.0\nK1: [1, 2\n  : : :\n\x01\x02");
  expectMessage(garbage, "not a valid OpenCV YAML/XML");
  // OpenCV 4.6's YAML parser never returned on this text (fuzz_calibration; the input is in its corpus): yaml-cpp's
  // reading refuses it first.
  const std::string hangs = outputPath("hangs_opencv_calibration.yml");
  writeText(hangs, "%YAML:1.0\nmatrix:\n   rows: 3\n   cols: 3\n-\xdd--\nR: !!opencv-matrix\n");
  expectMessage(hangs, "line 5 starts with '-' but is no list item or number");
  const std::string notXml = outputPath("garbage_calibration.xml");
  writeText(notXml, "<?xml version=\"1.0\"?>\n<opencv_storage><K1>");
  expectMessage(notXml, "not a valid OpenCV YAML/XML");
}

TEST(StereoRig, HandWrittenPlainValuesAreAccepted) {
  const std::string path = outputPath("calib_plain.yml");
  writeText(path,
            "%YAML:1.0\n---\nimageSize: [ 640, 480 ]\n"
            "K1: [[800, 0, 320], [0, 800, 240], [0, 0, 1]]\nD1: [0, 0, 0, 0, 0]\n"
            "K2: [[800, 0, 320], [0, 800, 240], [0, 0, 1]]\nD2: [0, 0, 0, 0]\n"
            "R: [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\nT: [-5, 0, 0]\n");
  const StereoCalibration c = readStereoCalibration(path);
  EXPECT_EQ(c.K1.at<double>(0, 2), 320.0);
  EXPECT_EQ(c.D2.size(), cv::Size(4, 1));
  EXPECT_EQ(c.T.size(), cv::Size(1, 3));
  EXPECT_EQ(c.T.at<double>(0), -5.0);
  // A rig without rotation or distortion rectifies to itself: depth = f * B / d exactly.
  const StereoRectifier rectifier(c);
  EXPECT_NEAR(rectifier.geometry().baselineMm, 5.0, 1e-12);
  EXPECT_NEAR(rectifier.geometry().focalPx, 800.0, 1e-9);
  EXPECT_NEAR(rectifier.geometry().depthMm(40.0), 100.0, 1e-9);
}

TEST(StereoRig, SwappedOrVerticalRigsAreRejected) {
  StereoCalibration swapped = syntheticCalibration();
  swapped.T = (cv::Mat_<double>(3, 1) << 5.0, 0, 0);
  EXPECT_THROW(StereoRectifier{swapped}, Error);
  StereoCalibration vertical = syntheticCalibration();
  vertical.T = (cv::Mat_<double>(3, 1) << 0.1, -5.0, 0);
  EXPECT_THROW(StereoRectifier{vertical}, Error);
}

class StereoRigModes : public ::testing::TestWithParam<RectificationMode> {};

// Ground truth: points placed in the rectified left frame on whole pixels, projected with cv::projectPoints into
// the unrectified (distorted) cameras; the disparity comes from rectifying those projections.
TEST_P(StereoRigModes, DisparityToPointCloudRecoversProjectedPoints) {
  const StereoCalibration c = syntheticCalibration();
  const StereoRectifier rectifier(c, GetParam());
  const RectifiedGeometry& g = rectifier.geometry();
  ASSERT_EQ(g.imageSize, c.imageSize);
  if (GetParam() == RectificationMode::ZeroDisparityAtInfinity) EXPECT_NEAR(g.doffsPx, 0.0, 1e-9);
  EXPECT_NEAR(g.baselineMm, cv::norm(c.T), 1e-9);  // rectification only rotates: the baseline keeps its length

  std::mt19937 random(12345);
  std::uniform_int_distribution<int> column(40, 600), row(40, 440);
  std::uniform_real_distribution<double> depthMm(30.0, 150.0);
  const cv::Mat R1 = rectifier.leftRectificationRotation();
  std::vector<cv::Point2i> pixels;
  std::vector<cv::Point3d> pointsRectified, pointsLeft;
  cv::Mat used(c.imageSize, CV_8U, cv::Scalar(0));
  while (pixels.size() < 300) {
    cv::Point2i p(column(random), row(random));
    if (used.at<uchar>(p)) continue;
    used.at<uchar>(p) = 1;
    const double z = depthMm(random);
    const cv::Point3d rectified((p.x - g.cxLeftPx) * z / g.focalPx, (p.y - g.cyPx) * z / g.focalPx, z);
    cv::Mat left = R1.t() * cv::Mat(rectified);  // into the unrectified left camera frame
    pixels.push_back(p);
    pointsRectified.push_back(rectified);
    pointsLeft.emplace_back(left.at<double>(0), left.at<double>(1), left.at<double>(2));
  }
  std::vector<cv::Point2d> imageLeft, imageRight;
  cv::Mat rvecRight;
  cv::Rodrigues(c.R, rvecRight);
  cv::projectPoints(pointsLeft, cv::Mat::zeros(3, 1, CV_64F), cv::Mat::zeros(3, 1, CV_64F), c.K1, c.D1, imageLeft);
  cv::projectPoints(pointsLeft, rvecRight, c.T, c.K2, c.D2, imageRight);
  const std::vector<cv::Point2d> rectLeft = rectifier.rectifyLeftPoints(imageLeft);
  const std::vector<cv::Point2d> rectRight = rectifier.rectifyRightPoints(imageRight);

  cv::Mat disparity(c.imageSize, CV_32F, cv::Scalar(kNaN));
  cv::Mat leftImage(c.imageSize, CV_8UC3, cv::Scalar(0, 0, 0));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    ASSERT_NEAR(rectLeft[i].x, pixels[i].x, 1e-6);
    ASSERT_NEAR(rectLeft[i].y, pixels[i].y, 1e-6);
    ASSERT_NEAR(rectRight[i].y, rectLeft[i].y, 1e-6) << "rectified rows must agree";
    disparity.at<float>(pixels[i]) = static_cast<float>(rectLeft[i].x - rectRight[i].x);  // left x = right x + d
    leftImage.at<cv::Vec3b>(pixels[i]) = cv::Vec3b(static_cast<uchar>(i % 256), 7, 200);  // BGR
  }

  const ColoredPointCloud cloud = disparityToPointCloud(disparity, leftImage, g);
  ASSERT_EQ(cloud.size(), pixels.size());
  ASSERT_EQ(cloud.colorsRgb.size(), pixels.size());
  EXPECT_TRUE(cloud.normals.empty());
  // The cloud is in row-major pixel order: match by pixel.
  std::vector<std::size_t> order(pixels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return pixels[a].y != pixels[b].y ? pixels[a].y < pixels[b].y : pixels[a].x < pixels[b].x;
  });
  double worstMm = 0;
  const cv::Mat depth = disparityToDepthMm(disparity, g);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    const cv::Point3d recovered(cloud.pointsMm[k].x, cloud.pointsMm[k].y, cloud.pointsMm[k].z);
    worstMm = std::max(worstMm, cv::norm(recovered - pointsRectified[i]));
    EXPECT_EQ(cloud.colorsRgb[k], cv::Vec3b(200, 7, static_cast<uchar>(i % 256))) << "RGB from BGR";
    EXPECT_NEAR(depth.at<float>(pixels[i]), pointsRectified[i].z, 1e-3);
    EXPECT_NEAR(g.depthMm(disparity.at<float>(pixels[i])), pointsRectified[i].z, 1e-3);
  }
  EXPECT_LT(worstMm, 1e-3);
  RecordProperty("worstErrorMm", std::to_string(worstMm));
  EXPECT_EQ(cv::countNonZero(depth == depth), static_cast<int>(pixels.size())) << "NaN disparity -> NaN depth";
}

TEST_P(StereoRigModes, DepthFormulaMatchesQ) {
  const StereoRectifier rectifier(syntheticCalibration(), GetParam());
  const RectifiedGeometry& g = rectifier.geometry();
  for (double d : {-10.0, 0.5, 12.25, 40.0, 95.5}) {
    if (d + g.doffsPx <= 0) continue;
    for (cv::Point2d p : {cv::Point2d(0, 0), cv::Point2d(100.5, 321), cv::Point2d(639, 479)}) {
      cv::Mat h = g.Q * (cv::Mat_<double>(4, 1) << p.x, p.y, d, 1.0);
      const double w = h.at<double>(3);
      EXPECT_NEAR(h.at<double>(2) / w, g.focalPx * g.baselineMm / (d + g.doffsPx), 1e-9);
      EXPECT_NEAR(h.at<double>(2) / w, g.depthMm(d), 1e-9);
      EXPECT_NEAR(h.at<double>(0) / w, (p.x - g.cxLeftPx) * g.depthMm(d) / g.focalPx, 1e-9);
      EXPECT_NEAR(h.at<double>(1) / w, (p.y - g.cyPx) * g.depthMm(d) / g.focalPx, 1e-9);
    }
  }
}

// The maps: rectifying an image whose pixels hold their own coordinates gives, at each rectified pixel, the
// unrectified position it samples. Reference: the rectified pixel's ray, rotated back into the unrectified camera
// (R1^T, R2^T) and projected with cv::projectPoints through the distorted camera.
TEST_P(StereoRigModes, RectifyMapsAgreeWithProjectPoints) {
  const StereoCalibration c = syntheticCalibration();
  const StereoRectifier rectifier(c, GetParam());
  const RectifiedGeometry& g = rectifier.geometry();
  cv::Mat coordinates(c.imageSize, CV_32FC2);
  for (int y = 0; y < coordinates.rows; ++y)
    for (int x = 0; x < coordinates.cols; ++x) coordinates.at<cv::Vec2f>(y, x) = cv::Vec2f(float(x), float(y));
  cv::Mat leftRectified, rightRectified;
  rectifier.rectify(coordinates, coordinates, leftRectified, rightRectified);
  ASSERT_EQ(leftRectified.size(), c.imageSize);
  ASSERT_EQ(rightRectified.size(), c.imageSize);
  std::vector<cv::Point2i> at;
  std::vector<cv::Point3d> raysLeft, raysRight;
  for (int y = 10; y < 470; y += 23)
    for (int x = 10; x < 630; x += 29) {
      at.emplace_back(x, y);
      cv::Mat left = rectifier.leftRectificationRotation().t() *
                     (cv::Mat_<double>(3, 1) << (x - g.cxLeftPx) / g.focalPx, (y - g.cyPx) / g.focalPx, 1.0);
      cv::Mat right = rectifier.rightRectificationRotation().t() *
                      (cv::Mat_<double>(3, 1) << (x - g.cxLeftPx - g.doffsPx) / g.focalPx, (y - g.cyPx) / g.focalPx, 1.0);
      raysLeft.emplace_back(left.at<double>(0), left.at<double>(1), left.at<double>(2));
      raysRight.emplace_back(right.at<double>(0), right.at<double>(1), right.at<double>(2));
    }
  std::vector<cv::Point2d> expectedLeft, expectedRight;
  const cv::Mat zero = cv::Mat::zeros(3, 1, CV_64F);
  cv::projectPoints(raysLeft, zero, zero, c.K1, c.D1, expectedLeft);
  cv::projectPoints(raysRight, zero, zero, c.K2, c.D2, expectedRight);
  // cv::remap interpolates at 1/32 px steps: a sample can be off by up to 1/64 px in x and in y.
  const double tolerancePx = 1.0 / 64 + 1e-4;
  int checked = 0;
  for (std::size_t i = 0; i < at.size(); ++i) {
    const cv::Vec2f l = leftRectified.at<cv::Vec2f>(at[i]), r = rightRectified.at<cv::Vec2f>(at[i]);
    // Only where the sample lies inside the unrectified image (alpha 0 keeps nearly all pixels valid).
    if (expectedLeft[i].x < 1 || expectedLeft[i].y < 1 || expectedLeft[i].x > 638 || expectedLeft[i].y > 478) continue;
    if (expectedRight[i].x < 1 || expectedRight[i].y < 1 || expectedRight[i].x > 638 || expectedRight[i].y > 478) continue;
    ++checked;
    EXPECT_NEAR(l[0], expectedLeft[i].x, tolerancePx);
    EXPECT_NEAR(l[1], expectedLeft[i].y, tolerancePx);
    EXPECT_NEAR(r[0], expectedRight[i].x, tolerancePx);
    EXPECT_NEAR(r[1], expectedRight[i].y, tolerancePx);
  }
  EXPECT_GT(checked, static_cast<int>(at.size() * 9 / 10));
  // Rectifying the projections of the points goes back to the pixels.
  const auto backLeft = rectifier.rectifyLeftPoints(expectedLeft);
  for (std::size_t i = 0; i < at.size(); ++i) {
    EXPECT_NEAR(backLeft[i].x, at[i].x, 1e-6);
    EXPECT_NEAR(backLeft[i].y, at[i].y, 1e-6);
  }
  cv::Mat small(100, 100, CV_8UC3);
  EXPECT_THROW(rectifier.rectify(small, small, leftRectified, rightRectified), Error);
  EXPECT_THROW(rectifier.rectify(cv::Mat(), coordinates, leftRectified, rightRectified), Error);
}

INSTANTIATE_TEST_SUITE_P(StereoRig, StereoRigModes,
                         ::testing::Values(RectificationMode::ZeroDisparityAtInfinity,
                                           RectificationMode::KeepPrincipalPoints),
                         [](const auto& info) {
                           return info.param == RectificationMode::ZeroDisparityAtInfinity ? "ZeroDisparity"
                                                                                           : "KeepPrincipalPoints";
                         });

TEST(StereoRig, NonFiniteAndBehindCameraDisparitiesGiveNoPoint) {
  const StereoRectifier rectifier(syntheticCalibration(), RectificationMode::KeepPrincipalPoints);
  const RectifiedGeometry& g = rectifier.geometry();
  ASSERT_GT(std::abs(g.doffsPx), 1e-3) << "the toe-in must give a non-zero doffs in this mode";
  cv::Mat disparity(g.imageSize, CV_32F, cv::Scalar(kNaN));
  disparity.at<float>(10, 10) = std::numeric_limits<float>::infinity();
  disparity.at<float>(10, 11) = -std::numeric_limits<float>::infinity();
  disparity.at<float>(10, 12) = static_cast<float>(-g.doffsPx);        // at infinity
  disparity.at<float>(10, 13) = static_cast<float>(-g.doffsPx - 3.0);  // behind the camera
  const float valid = static_cast<float>(25.0 - g.doffsPx);
  disparity.at<float>(10, 14) = valid;                                 // the only valid one
  const cv::Mat depth = disparityToDepthMm(disparity, g);
  EXPECT_EQ(cv::countNonZero(depth == depth), 1);
  EXPECT_NEAR(depth.at<float>(10, 14), g.focalPx * g.baselineMm / (valid + g.doffsPx), 1e-3);
  const cv::Mat grey(g.imageSize, CV_8UC1, cv::Scalar(77));
  const ColoredPointCloud cloud = disparityToPointCloud(disparity, grey, g);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_EQ(cloud.colorsRgb[0], cv::Vec3b(77, 77, 77));
  EXPECT_NEAR(cloud.pointsMm[0].z, depth.at<float>(10, 14), 1e-4);
  EXPECT_NEAR(cloud.pointsMm[0].x, (14 - g.cxLeftPx) * depth.at<float>(10, 14) / g.focalPx, 1e-4);

  EXPECT_THROW(disparityToDepthMm(cv::Mat(g.imageSize, CV_64F, cv::Scalar(1)), g), Error);
  EXPECT_THROW(disparityToDepthMm(cv::Mat(10, 10, CV_32F, cv::Scalar(1)), g), Error);
  EXPECT_THROW(disparityToPointCloud(disparity, cv::Mat(10, 10, CV_8UC3), g), Error);
}

}  // namespace
}  // namespace tissuemosaic
