// vtkTissueMosaicStereoLogic on a pair with exact ground truth: a textured fronto-parallel plane whose right view
// is the left view shifted by a known disparity.
#include "vtkTissueMosaicStereoLogic.h"

#include "Core/Device.h"

#include <gtest/gtest.h>

#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr int kTrueDisparityPx = 8;

/// Left and right views of a plane at disparity kTrueDisparityPx: left x shows what right x - d shows.
void makePlanePair(cv::Mat& left, cv::Mat& right) {
  cv::RNG rng(12345);
  cv::Mat texture(kHeight, kWidth + kTrueDisparityPx, CV_8UC3);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(texture, texture, cv::Size(3, 3), 0.8);
  left = texture(cv::Rect(0, 0, kWidth, kHeight)).clone();
  right = texture(cv::Rect(kTrueDisparityPx, 0, kWidth, kHeight)).clone();
}

tissuemosaic::RectifiedGeometry makeGeometry() {
  tissuemosaic::RectifiedGeometry geometry;
  geometry.imageSize = cv::Size(kWidth, kHeight);
  geometry.focalPx = 200;
  geometry.cxLeftPx = 80;
  geometry.cyPx = 60;
  geometry.doffsPx = 2;
  geometry.baselineMm = 5;
  // The same mapping as cv::stereoRectify's Q: W = (d + doffs) / B, Z = f / W.
  geometry.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -geometry.cxLeftPx, 0, 1, 0, -geometry.cyPx, 0, 0, 0,
                geometry.focalPx, 0, 0, 1.0 / geometry.baselineMm, geometry.doffsPx / geometry.baselineMm);
  return geometry;
}

}  // namespace

TEST(StereoLogic, ReconstructionMatchesDisparityImageAndDepth) {
  cv::Mat left, right;
  makePlanePair(left, right);
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  logic->SetDeviceChoiceToCpu();
  logic->SetRectifiedGeometry(makeGeometry());
  vtkPolyData* output = logic->GetReconstruction();
  ASSERT_TRUE(logic->ComputeReconstruction(left, right)) << logic->GetLastErrorText();
  EXPECT_TRUE(logic->GetLastErrorText().empty());
  EXPECT_EQ(logic->GetReconstruction(), output) << "the output object must be updated in place";

  // The matcher itself: the plane's disparity is recovered away from the borders.
  const cv::Mat& disparity = logic->GetLastDisparityPx();
  ASSERT_EQ(disparity.type(), CV_32F);
  ASSERT_EQ(disparity.size(), left.size());
  int interior = 0, interiorGood = 0, finite = 0;
  double minDisparity = 1e9, maxDisparity = -1e9;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const float d = disparity.at<float>(y, x);
      if (std::isfinite(d)) {
        ++finite;
        minDisparity = std::min<double>(minDisparity, d);
        maxDisparity = std::max<double>(maxDisparity, d);
      }
      if (x >= 20 && x < kWidth - 10 && y >= 10 && y < kHeight - 10) {
        ++interior;
        if (std::isfinite(d) && std::abs(d - kTrueDisparityPx) <= 1.0f) ++interiorGood;
      }
    }
  }
  EXPECT_GT(interiorGood, 0.95 * interior);

  // One point and one vertex per finite disparity.
  ASSERT_EQ(output->GetNumberOfPoints(), finite);
  EXPECT_EQ(output->GetNumberOfVerts(), finite);

  // Depth bounds are those of the disparity extremes; the plane lies at f B / (d + doffs).
  const tissuemosaic::RectifiedGeometry geometry = makeGeometry();
  double bounds[6];
  output->GetBounds(bounds);
  EXPECT_NEAR(bounds[4], geometry.depthMm(maxDisparity), 1e-3 * bounds[4]);
  EXPECT_NEAR(bounds[5], geometry.depthMm(minDisparity), 1e-3 * bounds[5]);
  std::vector<double> depthsMm;
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i) depthsMm.push_back(output->GetPoint(i)[2]);
  std::nth_element(depthsMm.begin(), depthsMm.begin() + depthsMm.size() / 2, depthsMm.end());
  EXPECT_NEAR(depthsMm[depthsMm.size() / 2], geometry.depthMm(kTrueDisparityPx), 0.01 * 100.0);

  // Colours: every point projects back onto the left pixel whose colour (BGR -> RGB) it carries.
  auto* colors = vtkUnsignedCharArray::SafeDownCast(output->GetPointData()->GetArray("RGB"));
  ASSERT_NE(colors, nullptr);
  ASSERT_EQ(colors->GetNumberOfComponents(), 3);
  int wrongColors = 0, offPixel = 0;
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i) {
    const double* p = output->GetPoint(i);
    const double u = p[0] * geometry.focalPx / p[2] + geometry.cxLeftPx;
    const double v = p[1] * geometry.focalPx / p[2] + geometry.cyPx;
    const int x = static_cast<int>(std::lround(u)), y = static_cast<int>(std::lround(v));
    if (std::abs(u - x) > 1e-2 || std::abs(v - y) > 1e-2 || x < 0 || y < 0 || x >= kWidth || y >= kHeight) {
      ++offPixel;
      continue;
    }
    const cv::Vec3b bgr = left.at<cv::Vec3b>(y, x);
    if (colors->GetValue(3 * i) != bgr[2] || colors->GetValue(3 * i + 1) != bgr[1] ||
        colors->GetValue(3 * i + 2) != bgr[0]) {
      ++wrongColors;
    }
  }
  EXPECT_EQ(offPixel, 0);
  EXPECT_EQ(wrongColors, 0);
}

TEST(StereoLogic, FailsWithoutGeometryAndOnSizeMismatch) {
  cv::Mat left, right;
  makePlanePair(left, right);
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  logic->SetDeviceChoiceToCpu();
  EXPECT_FALSE(logic->ComputeReconstruction(left, right));
  EXPECT_NE(logic->GetLastErrorText().find("calibration"), std::string::npos) << logic->GetLastErrorText();

  logic->SetRectifiedGeometry(makeGeometry());
  ASSERT_TRUE(logic->ComputeReconstruction(left, right)) << logic->GetLastErrorText();
  EXPECT_GT(logic->GetReconstruction()->GetNumberOfPoints(), 0);
  const cv::Mat smallLeft = left(cv::Rect(0, 0, 100, 80)).clone();
  EXPECT_FALSE(logic->ComputeReconstruction(smallLeft, right));
  EXPECT_FALSE(logic->GetLastErrorText().empty());
  EXPECT_EQ(logic->GetReconstruction()->GetNumberOfPoints(), 0) << "a failure must clear the previous result";
  EXPECT_TRUE(logic->GetLastDisparityPx().empty());
}

TEST(StereoLogic, InvalidParametersAreRefusedAndTheOldOnesKept) {
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  tissuemosaic::StereoParameters parameters;
  parameters.minDisparityPx = 90;  // above maxDisparityPx = 80
  EXPECT_FALSE(logic->SetStereoParameters(parameters));
  EXPECT_NE(logic->GetLastErrorText().find("maxDisparityPx"), std::string::npos) << logic->GetLastErrorText();
  EXPECT_EQ(logic->GetStereoParameters().minDisparityPx, -20);

  parameters = {};
  parameters.znccWindowPx = 9;
  EXPECT_TRUE(logic->SetStereoParameters(parameters));
  EXPECT_EQ(logic->GetStereoParameters().znccWindowPx, 9);
  EXPECT_TRUE(logic->GetLastErrorText().empty());
}

TEST(StereoLogic, DeviceChoiceIsClampedAndCudaNeverFallsBackSilently) {
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  logic->SetDeviceChoice(7);
  EXPECT_EQ(logic->GetDeviceChoice(), vtkTissueMosaicStereoLogic::DeviceCuda);
  if (tissuemosaic::cudaAvailable()) GTEST_SKIP() << "CUDA is available here: nothing to refuse";
  cv::Mat left, right;
  makePlanePair(left, right);
  logic->SetRectifiedGeometry(makeGeometry());
  logic->SetDeviceChoiceToCuda();
  EXPECT_FALSE(logic->ComputeReconstruction(left, right));
  EXPECT_FALSE(logic->GetLastErrorText().empty());
  logic->SetDeviceChoiceToAuto();
  EXPECT_TRUE(logic->ComputeReconstruction(left, right)) << logic->GetLastErrorText();
}

TEST(StereoLogic, ChoosesAndReportsTheDisparityRange) {
  cv::Mat left, right;
  makePlanePair(left, right);
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  logic->SetDeviceChoiceToCpu();
  logic->SetRectifiedGeometry(makeGeometry());
  // Automatic, the default: measured from this pair, around the plane's 8 px.
  ASSERT_TRUE(logic->ComputeReconstruction(left, right)) << logic->GetLastErrorText();
  const tissuemosaic::DisparityRange automatic = logic->GetLastDisparityRange();
  EXPECT_TRUE(automatic.contains(kTrueDisparityPx)) << automatic.text();
  EXPECT_LE(automatic.count(), 24) << automatic.text();
  EXPECT_EQ(logic->GetLastDisparityRangeText().rfind("auto: " + automatic.text(), 0), 0u)
      << logic->GetLastDisparityRangeText();

  // A working distance through the geometry: f B = 1000 px mm, doffs 2 px: 80..200 mm are 3..10.5 px.
  tissuemosaic::StereoParameters parameters;
  parameters.disparityRangeMode = tissuemosaic::DisparityRangeMode::WorkingDistance;
  parameters.workingDistanceNearMm = 80;
  parameters.workingDistanceFarMm = 200;
  ASSERT_TRUE(logic->SetStereoParameters(parameters));
  ASSERT_TRUE(logic->ComputeReconstruction(left, right)) << logic->GetLastErrorText();
  EXPECT_EQ(logic->GetLastDisparityRange(), (tissuemosaic::DisparityRange{0, 11}));
  EXPECT_EQ(logic->GetLastDisparityRangeText(), "working distance 80..200 mm: 0..11 px");

  // A featureless pair cannot have an automatic range: the reason is given, and nothing is kept.
  ASSERT_TRUE(logic->SetStereoParameters(tissuemosaic::StereoParameters{}));
  const cv::Mat grey(kHeight, kWidth, CV_8UC3, cv::Scalar::all(90));
  EXPECT_FALSE(logic->ComputeReconstruction(grey, grey));
  EXPECT_NE(logic->GetLastErrorText().find("left-right feature matches"), std::string::npos)
      << logic->GetLastErrorText();
  EXPECT_TRUE(logic->GetLastDisparityPx().empty());
  EXPECT_TRUE(logic->GetLastDisparityRangeText().empty());
}
