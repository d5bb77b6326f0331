// The synthetic stereo scene: deterministic, ground truth consistent with the calibration and the images,
// the raw pair rectifies onto the rectified renders, and the scene has what the stereo tests need
// (low-texture patches, eye-dependent highlights).
#include "SyntheticStereoScene.h"

#include "Core/Error.h"
#include "Core/StereoRig.h"
#include "IO/Calibration/CalibrationFile.h"
#include "IO/DisparityPfm.h"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <ctime>
#include <filesystem>

using namespace tissuemosaic;
using namespace tissuemosaic::synthetic;

namespace {

const SyntheticStereoPair& defaultPair() {
  static const SyntheticStereoPair pair = renderSyntheticStereoPair(SyntheticStereoOptions());
  return pair;
}

cv::Mat grey(const cv::Mat& bgr) {
  cv::Mat g;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  return g;
}

/// Standard deviation of grey values in a (2r+1)^2 window around each pixel.
cv::Mat localStd(const cv::Mat& grey8, int r) {
  cv::Mat g, mean, meanSq;
  grey8.convertTo(g, CV_32F);
  cv::boxFilter(g, mean, CV_32F, cv::Size(2 * r + 1, 2 * r + 1));
  cv::boxFilter(g.mul(g), meanSq, CV_32F, cv::Size(2 * r + 1, 2 * r + 1));
  cv::Mat var = meanSq - mean.mul(mean);
  cv::max(var, 0.0, var);
  cv::sqrt(var, var);
  return var;
}

/// Zero-mean normalised cross-correlation of the (2r+1)^2 windows at left (x, y) and right (xr, y), xr sub-pixel.
double zncc(const cv::Mat& left, const cv::Mat& right, int x, int y, double xr, int r) {
  double sl = 0, sr = 0, sll = 0, srr = 0, slr = 0;
  const int n = (2 * r + 1) * (2 * r + 1);
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const double a = left.at<uchar>(y + dy, x + dx);
      const double u = xr + dx;
      const int u0 = static_cast<int>(std::floor(u));
      const double f = u - u0;
      const double b = (1 - f) * right.at<uchar>(y + dy, u0) + f * right.at<uchar>(y + dy, u0 + 1);
      sl += a; sr += b; sll += a * a; srr += b * b; slr += a * b;
    }
  }
  const double cov = slr - sl * sr / n, vl = sll - sl * sl / n, vr = srr - sr * sr / n;
  return cov / std::sqrt(std::max(1e-9, vl * vr));
}

}  // namespace

TEST(SyntheticStereoScene, SameSeedGivesIdenticalImagesAndOtherSeedsDiffer) {
  SyntheticStereoOptions options;
  options.width = 320;
  options.height = 180;
  options.seed = 7;
  const SyntheticStereoPair a = renderSyntheticStereoPair(options);
  const SyntheticStereoPair b = renderSyntheticStereoPair(options);
  for (const auto& [x, y] : {std::pair{a.leftRectified, b.leftRectified}, {a.rightRectified, b.rightRectified},
                             {a.leftRaw, b.leftRaw}, {a.rightRaw, b.rightRaw}}) {
    ASSERT_EQ(x.size(), cv::Size(320, 180));
    EXPECT_EQ(cv::norm(x, y, cv::NORM_INF), 0.0);
  }
  EXPECT_EQ(cv::countNonZero(a.disparityPx != b.disparityPx), cv::countNonZero(a.disparityPx != a.disparityPx));

  options.seed = 8;
  const SyntheticStereoPair c = renderSyntheticStereoPair(options);
  cv::Mat difference;
  cv::absdiff(a.leftRectified, c.leftRectified, difference);
  EXPECT_GT(cv::mean(difference)[0], 5.0);
}

TEST(SyntheticStereoScene, DefaultDisparitiesFitThePaperRangeAndWideVariantSpansAbout100Px) {
  const SyntheticStereoPair& pair = defaultPair();
  const cv::Mat valid = pair.disparityPx == pair.disparityPx;
  EXPECT_GT(cv::countNonZero(valid), 0.85 * valid.total());
  double low = 0, high = 0;
  cv::minMaxLoc(pair.disparityPx, &low, &high, nullptr, nullptr, valid);
  EXPECT_GE(low, -20.0);
  EXPECT_LE(high, 80.0);
  EXPECT_GT(high - low, 5.0);  // not a flat plane

  SyntheticStereoOptions wide = SyntheticStereoOptions::wideDisparity();
  wide.supersampling = 1;
  const SyntheticStereoPair widePair = renderSyntheticStereoPair(wide);
  cv::minMaxLoc(widePair.disparityPx, &low, &high, nullptr, nullptr, widePair.disparityPx == widePair.disparityPx);
  EXPECT_GT(high - low, 85.0);
  EXPECT_LT(high - low, 130.0);
}

TEST(SyntheticStereoScene, GroundTruthAgreesWithCalibrationRectifierAndImages) {
  const SyntheticStereoPair& pair = defaultPair();
  const RectifiedGeometry& g = pair.geometry;
  const StereoRectifier rectifier(pair.calibration);
  // The rectified cameras rendered are the ones StereoRectifier derives from the written calibration.
  EXPECT_LT(cv::norm(rectifier.leftProjection(), pair.P1, cv::NORM_INF), 1e-9);
  EXPECT_LT(cv::norm(rectifier.rightProjection(), pair.P2, cv::NORM_INF), 1e-9);

  const cv::Mat left = grey(pair.leftRectified), right = grey(pair.rightRectified);
  const cv::Mat texture = localStd(left, 5);
  const cv::Matx33d R(reinterpret_cast<const double*>(pair.calibration.R.data));
  const cv::Vec3d T(reinterpret_cast<const double*>(pair.calibration.T.data));
  const cv::Matx33d R1(reinterpret_cast<const double*>(pair.R1.data));
  int checked = 0, matched = 0;
  double shiftedScore = 0, trueScore = 0;
  for (int y = 20; y < g.imageSize.height - 20; y += 23) {
    for (int x = 20; x < g.imageSize.width - 20; x += 29) {
      const float d = pair.disparityPx.at<float>(y, x);
      if (std::isnan(d)) continue;
      const double z = pair.depthMm.at<float>(y, x);
      // Depth and disparity obey depth = f * B / (d + doffs).
      ASSERT_NEAR(z, g.depthMm(d), 1e-4 * z);
      // The 3D point seen by the left pixel, through the raw cameras and the rectifier, lands on (x, y) in the
      // rectified left view and on (x - d, y) in the rectified right view.
      const cv::Vec3d rectLeft((x - g.cxLeftPx) / g.focalPx * z, (y - g.cyPx) / g.focalPx * z, z);
      const cv::Vec3d rawLeft = R1.t() * rectLeft;
      const cv::Vec3d rawRight = R * rawLeft + T;
      std::vector<cv::Point2d> leftPixel, rightPixel;
      cv::projectPoints(std::vector<cv::Point3d>{cv::Point3d(rawLeft)}, cv::Vec3d(), cv::Vec3d(), pair.calibration.K1,
                        pair.calibration.D1, leftPixel);
      cv::projectPoints(std::vector<cv::Point3d>{cv::Point3d(rawRight)}, cv::Vec3d(), cv::Vec3d(), pair.calibration.K2,
                        pair.calibration.D2, rightPixel);
      const cv::Point2d inLeft = rectifier.rectifyLeftPoints(leftPixel)[0];
      const cv::Point2d inRight = rectifier.rectifyRightPoints(rightPixel)[0];
      EXPECT_NEAR(inLeft.x, x, 1e-3);
      EXPECT_NEAR(inLeft.y, y, 1e-3);
      EXPECT_NEAR(inRight.x, x - d, 1e-3);
      EXPECT_NEAR(inRight.y, y, 1e-3);
      ++checked;
      // Photometric: on textured tissue the windows at the true match correlate, 3 px off they do not.
      if (texture.at<float>(y, x) > 6 && x - d - 12 > 0 && x - d + 12 < g.imageSize.width && left.at<uchar>(y, x) < 240) {
        const double score = zncc(left, right, x, y, x - d, 5);
        trueScore += score;
        shiftedScore += zncc(left, right, x, y, x - d - 3, 5);
        matched += score > 0.8;
      }
    }
  }
  ASSERT_GT(checked, 300);
  int textured = 0;
  for (int y = 20; y < g.imageSize.height - 20; y += 23)
    for (int x = 20; x < g.imageSize.width - 20; x += 29) {
      const float d = pair.disparityPx.at<float>(y, x);
      textured += !std::isnan(d) && texture.at<float>(y, x) > 6 && x - d - 12 > 0 && left.at<uchar>(y, x) < 240;
    }
  ASSERT_GT(textured, 100);
  EXPECT_GT(matched, 0.9 * textured);
  EXPECT_GT(trueScore / textured, 0.9);
  EXPECT_LT(shiftedScore / textured, 0.6);
}

TEST(SyntheticStereoScene, RawPairRectifiedWithStereoRectifierMatchesRectifiedRenders) {
  const SyntheticStereoPair& pair = defaultPair();
  const StereoRectifier rectifier(pair.calibration);
  cv::Mat leftFromRaw, rightFromRaw;
  rectifier.rectify(pair.leftRaw, pair.rightRaw, leftFromRaw, rightFromRaw);
  for (const auto& [fromRaw, render] : {std::pair{leftFromRaw, pair.leftRectified}, {rightFromRaw, pair.rightRectified}}) {
    const cv::Mat a = grey(fromRaw), b = grey(render);
    // Textured, unsaturated pixels away from the border.
    cv::Mat mask = (localStd(b, 5) > 8) & (b < 240);
    mask(cv::Rect(0, 0, mask.cols, 10)) = 0;
    mask(cv::Rect(0, mask.rows - 10, mask.cols, 10)) = 0;
    mask(cv::Rect(0, 0, 10, mask.rows)) = 0;
    mask(cv::Rect(mask.cols - 10, 0, 10, mask.rows)) = 0;
    ASSERT_GT(cv::countNonZero(mask), 0.2 * mask.total());
    cv::Mat difference;
    cv::absdiff(a, b, difference);
    const double meanAbs = cv::mean(difference, mask)[0];
    // The same comparison one pixel off: what a wrong geometry would give.
    cv::Mat shifted;
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 1, 0, 1, 0);
    cv::warpAffine(a, shifted, shift, a.size());
    cv::absdiff(shifted, b, difference);
    const double meanAbsShifted = cv::mean(difference, mask)[0];
    EXPECT_LT(meanAbs, 5.0);
    EXPECT_GT(meanAbsShifted, 1.8 * meanAbs);
    RecordProperty("meanAbsDiff", std::to_string(meanAbs));
  }
}

TEST(SyntheticStereoScene, HasLowTexturePatchesAndHighlightsThatDifferBetweenTheEyes) {
  const SyntheticStereoPair& pair = defaultPair();
  const cv::Mat left = grey(pair.leftRectified), right = grey(pair.rightRectified);
  const cv::Mat spread = localStd(left, 5);
  const double pixels = static_cast<double>(left.total());
  EXPECT_GT(cv::countNonZero(spread < 3.5) / pixels, 0.10);  // low texture: not much above the sensor noise
  EXPECT_GT(cv::countNonZero(spread > 8) / pixels, 0.30);    // well-textured tissue

  const cv::Mat leftHighlight = left >= 250, rightHighlight = right >= 250;
  ASSERT_GT(cv::countNonZero(leftHighlight), 200);
  ASSERT_GT(cv::countNonZero(rightHighlight), 200);
  // A highlight is not painted on the surface: at the matching right pixel it is mostly elsewhere.
  int highlighted = 0, alsoInRight = 0;
  for (int y = 0; y < left.rows; ++y)
    for (int x = 0; x < left.cols; ++x) {
      const float d = pair.disparityPx.at<float>(y, x);
      if (!leftHighlight.at<uchar>(y, x) || std::isnan(d)) continue;
      ++highlighted;
      alsoInRight += rightHighlight.at<uchar>(y, static_cast<int>(std::lround(x - d))) != 0;
    }
  ASSERT_GT(highlighted, 100);
  EXPECT_LT(alsoInRight, 0.7 * highlighted);
}

TEST(SyntheticStereoScene, WritesImagesCalibrationAndGroundTruthThatReadBack) {
  SyntheticStereoOptions options;
  options.width = 240;
  options.height = 136;
  const SyntheticStereoPair pair = renderSyntheticStereoPair(options);
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/synthetic_pair";
  std::filesystem::remove_all(folder);
  const std::vector<std::string> written = writeSyntheticStereoPair(pair, folder);
  EXPECT_EQ(written.size(), 8u);
  for (const char* name : {"left.png", "right.png", "left_raw.png", "right_raw.png", "rig.yml", "disparity.pfm",
                           "depth_mm.pfm", "groundtruth/highlight_mask_left.png"})
    EXPECT_TRUE(std::filesystem::is_regular_file(folder + "/" + name)) << name;
  const cv::Mat mask = cv::imread(folder + "/groundtruth/highlight_mask_left.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mask.type(), CV_8U);
  EXPECT_EQ(cv::norm(mask, pair.highlightMaskLeft, cv::NORM_INF), 0.0);
  const StereoCalibration calibration = readStereoCalibration(folder + "/rig.yml");
  EXPECT_EQ(calibration.imageSize, pair.calibration.imageSize);
  EXPECT_LT(cv::norm(calibration.K1, pair.calibration.K1, cv::NORM_INF), 1e-9);
  EXPECT_LT(cv::norm(calibration.D2, pair.calibration.D2, cv::NORM_INF), 1e-12);
  EXPECT_LT(cv::norm(calibration.R, pair.calibration.R, cv::NORM_INF), 1e-12);
  const cv::Mat disparity = readPfm(folder + "/disparity.pfm");
  ASSERT_EQ(disparity.size(), pair.disparityPx.size());
  const cv::Mat valid = pair.disparityPx == pair.disparityPx;
  EXPECT_EQ(cv::countNonZero(valid != (disparity == disparity)), 0);
  EXPECT_EQ(cv::norm(disparity, pair.disparityPx, cv::NORM_INF, valid), 0.0);
}

TEST(SyntheticStereoScene, RejectsInvalidOptions) {
  SyntheticStereoOptions options;
  options.width = 10;
  EXPECT_THROW(renderSyntheticStereoPair(options), Error);
  options = SyntheticStereoOptions();
  options.baselineMm = -5;
  EXPECT_THROW(renderSyntheticStereoPair(options), Error);
  options = SyntheticStereoOptions();
  options.supersampling = 9;
  EXPECT_THROW(renderSyntheticStereoPair(options), Error);
}

// The realistic look (SyntheticLighting.h): large bright diffuse areas near and at saturation, a sensor that clips at
// 255 exactly, and highlights that the ground-truth mask marks and that sit elsewhere on the surface in each eye.
TEST(SyntheticStereoScene, RealisticLightingHasBrightTissueClippingAndViewDependentHighlights) {
  SyntheticStereoOptions options;
  options.width = 480;
  options.height = 270;
  options.lighting = SyntheticLighting::Realistic;
  const SyntheticStereoPair pair = renderSyntheticStereoPair(options);
  const cv::Mat left = grey(pair.leftRectified), right = grey(pair.rightRectified);
  const double pixels = static_cast<double>(left.total());
  const cv::Mat mask = pair.highlightMaskLeft;
  ASSERT_EQ(mask.type(), CV_8U);
  ASSERT_EQ(mask.size(), left.size());
  EXPECT_GT(cv::countNonZero(mask) / pixels, 0.0015);  // 0.0025 at seed 1: glints, a few larger lobes
  EXPECT_LT(cv::countNonZero(mask) / pixels, 0.10);
  // Bright diffuse tissue: many pixels above 230 outside the highlights.
  EXPECT_GT(cv::countNonZero((left > 230) & (mask == 0)) / pixels, 0.05);
  // Clipping: a saturated channel reads 255 exactly, without noise (the standard look adds noise after clipping, so
  // that its saturated pixels spread over 250..255).
  std::vector<cv::Mat> channels;
  cv::split(pair.leftRectified, channels);
  const int clipped = cv::countNonZero((channels[1] == 255) & (mask != 0));
  EXPECT_GT(clipped, 200);
  EXPECT_GT(clipped, 10 * cv::countNonZero((channels[1] == 254) & (mask != 0)));
  // The mask marks the highlights: on it the image is brighter than around it.
  EXPECT_GT(cv::mean(left, mask)[0], cv::mean(left, mask == 0)[0] + 40);
  // View-dependent: at the true match the right eye sees the same diffuse tissue alike, but not the highlights.
  double highlightDifference = 0, tissueDifference = 0;
  long highlightPixels = 0, tissuePixels = 0;
  for (int y = 0; y < left.rows; ++y)
    for (int x = 0; x < left.cols; ++x) {
      const float d = pair.disparityPx.at<float>(y, x);
      if (std::isnan(d)) continue;
      const int xr = static_cast<int>(std::lround(x - d));
      const double difference = left.at<uchar>(y, x) - right.at<uchar>(y, xr);
      if (mask.at<uchar>(y, x)) {
        highlightDifference += difference;
        ++highlightPixels;
      } else {
        tissueDifference += std::abs(difference);
        ++tissuePixels;
      }
    }
  ASSERT_GT(highlightPixels, 100);
  std::printf("left - right at the true match: highlights %+.1f, tissue |%.1f| grey levels\n",
              highlightDifference / highlightPixels, tissueDifference / tissuePixels);
  // Seed 1: +9.2 on highlights (their rims overlap the twin's), |3.4| on tissue (noise). Without view dependence the
  // highlights' mean would be as near 0 as the tissue's.
  EXPECT_GT(highlightDifference / highlightPixels, 2.0 * tissueDifference / tissuePixels);
  EXPECT_LT(tissueDifference / tissuePixels, 6.0);
  // The looks by name, as `synth --lighting` takes them.
  EXPECT_THROW(parseSyntheticLighting("neon"), Error);
  EXPECT_EQ(parseSyntheticLighting("realistic"), SyntheticLighting::Realistic);
}
