// The whole section II pipeline against the exact ground truth of a synthetic tissue pair (textured liver-like
// surface with low-texture patches, specular highlights that differ between the eyes, vignetting and noise).
#include "Core/StereoRig.h"
#include "StereoTestUtilities.h"
#include "Stereo/StereoMatcher.h"
#include "SyntheticScan.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace tissuemosaic;

namespace {

test::DisparityScore scoreAgainstTruth(const cv::Mat& disparity, const cv::Mat& truth) {
  return test::scoreDisparity(disparity, truth, cv::Mat(truth.size(), CV_8U, cv::Scalar(255)));
}

// The requirement: bad-1 <= 0.02 over >= 95% of the visible surface, mean error <= 0.35 px. Regression bars near
// twice the values measured when they were set (2026-11-25): rectified renders density 0.9796, bad-1 0.0030, mean
// error 0.130 px; raw pair rectified by StereoRectifier 0.9797, 0.0007, 0.126 px. The remaining errors sit in the
// saturated specular highlight and the weakest-texture patches. Returns the bars missed ("" when none).
std::string missedBars(const test::DisparityScore& score, double measuredBad1, double measuredMeanPx) {
  std::string missed;
  if (score.density < 0.95) missed += " density requirement;";
  if (score.density < 1 - 2 * (1 - 0.9796)) missed += " density regression (twice the missing share);";
  if (score.badOver1 > 0.02) missed += " bad-1 requirement;";
  if (score.badOver1 > 2 * measuredBad1) missed += " bad-1 regression;";
  if (score.meanAbsError > 0.35) missed += " mean error requirement;";
  if (score.meanAbsError > 2 * measuredMeanPx) missed += " mean error regression;";
  return missed;
}

}  // namespace

TEST(StereoSyntheticTissue, RectifiedPairAgainstGroundTruth) {
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions{});
  StereoMatcher matcher(Device::Cpu, StereoParameters{});
  const cv::Mat disparity = matcher.computeDisparity(pair.leftRectified, pair.rightRectified);
  const auto score = scoreAgainstTruth(disparity, pair.disparityPx);
  std::printf("rectified renders: density %.4f bad-1 %.4f bad-2 %.4f mean abs error %.3f px\n", score.density,
              score.badOver1, score.badOver2, score.meanAbsError);
  EXPECT_EQ(missedBars(score, 0.0030, 0.130), "");
  // Negative control: the truth 0.3 px off everywhere meets every requirement bar (bad-1 0, mean 0.3 <= 0.35 px) but
  // not the regression bar on the mean error.
  const cv::Mat offByAThird = pair.disparityPx + 0.3f;
  EXPECT_EQ(missedBars(scoreAgainstTruth(offByAThird, pair.disparityPx), 0.0030, 0.130), " mean error regression;");
}

TEST(StereoSyntheticTissue, RawPairRectifiedFromCalibrationAgainstGroundTruth) {
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions{});
  const StereoRectifier rectifier(pair.calibration);
  cv::Mat left, right;
  rectifier.rectify(pair.leftRaw, pair.rightRaw, left, right);
  StereoMatcher matcher(Device::Cpu, StereoParameters{});
  const cv::Mat disparity = matcher.computeDisparity(left, right);
  const auto score = scoreAgainstTruth(disparity, pair.disparityPx);
  std::printf("raw pair rectified: density %.4f bad-1 %.4f bad-2 %.4f mean abs error %.3f px\n", score.density,
              score.badOver1, score.badOver2, score.meanAbsError);
  EXPECT_EQ(missedBars(score, 0.0007, 0.126), "");
}

// An instrument's shaft nearer the scope than a range that follows the tissue (the hard-mode scan of
// docs/SCENE_MOTION.md, frame 90, where the shaft spans 59-92 px and the tissue 48-56): without the range-end rule
// its pixels take the range's top, the same in every frame, and the fusion took them for a floating surface.
TEST(StereoSyntheticTissue, AnInstrumentNearerThanTheRangeIsNotPutAtTheRangesEnd) {
  synthetic::SyntheticScanOptions options;
  options.frames = 300;
  options.seed = 3;
  options.supersampling = 1;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.instruments = 2;
  const synthetic::SyntheticScan scan(options);
  const synthetic::SyntheticScanFrame frame = scan.renderFrame(90);
  ASSERT_GT(cv::countNonZero(frame.instrumentMask), 20000);
  // The range follows the tissue: its 2 % .. 98 % disparities, widened by 4 px each way.
  std::vector<float> tissue;
  for (int y = 0; y < frame.disparityPx.rows; ++y)
    for (int x = 0; x < frame.disparityPx.cols; ++x)
      if (frame.instrumentMask.at<uint8_t>(y, x) == 0 && std::isfinite(frame.disparityPx.at<float>(y, x)))
        tissue.push_back(frame.disparityPx.at<float>(y, x));
  std::sort(tissue.begin(), tissue.end());
  StereoParameters parameters;
  parameters.minDisparityPx = static_cast<int>(std::floor(tissue[tissue.size() / 50])) - 4;
  parameters.maxDisparityPx = static_cast<int>(std::ceil(tissue[tissue.size() * 49 / 50])) + 4;
  // Instrument pixels given a value within 2 px of the range's top, and tissue pixels more than 3 px off.
  const auto count = [&](int marginPx, int& instrumentAtTop, int& tissueOff) {
    parameters.rangeEndMarginPx = marginPx;
    StereoMatcher matcher(Device::Cpu, parameters);
    const cv::Mat disparity = matcher.computeDisparity(frame.leftRectified, frame.rightRectified);
    instrumentAtTop = tissueOff = 0;
    for (int y = 0; y < disparity.rows; ++y) {
      for (int x = 0; x < disparity.cols; ++x) {
        const float d = disparity.at<float>(y, x), truth = frame.disparityPx.at<float>(y, x);
        if (!std::isfinite(d)) continue;
        if (frame.instrumentMask.at<uint8_t>(y, x) != 0) instrumentAtTop += d >= parameters.maxDisparityPx - 2;
        else if (std::isfinite(truth)) tissueOff += std::abs(d - truth) > 3.0f;
      }
    }
  };
  int offAtTop = 0, offTissue = 0, onAtTop = 0, onTissue = 0;
  count(-1, offAtTop, offTissue);
  count(StereoParameters{}.rangeEndMarginPx, onAtTop, onTissue);
  std::printf("range %d..%d px: instrument pixels at the range's top %d (%d without the rule), tissue pixels more "
              "than 3 px off %d (%d)\n", parameters.minDisparityPx, parameters.maxDisparityPx, onAtTop, offAtTop,
              onTissue, offTissue);
  EXPECT_GT(offAtTop, 10000);
  EXPECT_LT(onAtTop, offAtTop / 2);
  EXPECT_LT(onTissue, offTissue);
}

// The scope light's highlights at 1920x1080 (the second key frame, frame 10, of `bench reconstruct --width 1920
// --height 1080`'s scan): twice as many pixels across as at 960x540. With the highlight sizes of 960x540 most were classed as bright
// tissue, ZNCC matched their mirror images 40-60 px below the tissue's disparity, and, the mirror image of a curved
// surface lying at about the same place from every viewpoint, the fusion merged them into blobs 10-63 mm behind the
// tissue (the 1080p model RMSE 0.31 mm, against 0.07 without them). The sizes now scale with the width.
TEST(StereoSyntheticTissue, HighlightsAtHdAreNotMatchedBehindTheTissue) {
  synthetic::SyntheticScanOptions options;
  options.width = 1920;
  options.height = 1080;
  options.frames = 120;
  options.supersampling = 1;
  const synthetic::SyntheticScan scan(options);
  const synthetic::SyntheticScanFrame frame = scan.renderFrame(10);
  const auto behindTheTissue = [&](const StereoParameters& parameters) {
    StereoMatcher matcher(Device::Cpu, parameters);
    matcher.computeDisparity(frame.leftRectified, frame.rightRectified);
    const cv::Mat fused = matcher.lastDisparityAwayFromHighlights();  // what tracking and fusion take
    int count = 0;
    for (int y = 0; y < fused.rows; ++y) {
      for (int x = 0; x < fused.cols; ++x) {
        const float d = fused.at<float>(y, x), truth = frame.disparityPx.at<float>(y, x);
        count += std::isfinite(d) && std::isfinite(truth) && d < truth - 10;
      }
    }
    return count;
  };
  StereoParameters parameters;
  parameters.setFixedDisparityRange(-40, 215);  // bench reconstruct's at 1920 px
  const StereoParameters sized = parameters.forImageWidth(1920);
  EXPECT_EQ(sized.specularMaxRadiusPx, 96);
  EXPECT_EQ(sized.specularMarginPx, 6);
  EXPECT_EQ(sized.trackingHighlightMarginPx, 28);
  const StereoParameters paper = parameters.forImageWidth(960);
  EXPECT_EQ(paper.specularMaxRadiusPx, 48);
  EXPECT_EQ(parameters.forImageWidth(640).specularMarginPx, 3) << "narrower images keep the sizes";
  EXPECT_EQ(parameters.forImageWidth(1280).specularMaxRadiusPx, 64);
  // Half the sizes, scaled by 2 at this width: about the sizes of 960x540 as they were used at 1920x1080 before.
  StereoParameters halfSized = parameters;
  halfSized.specularMaxRadiusPx = 24;
  halfSized.specularMarginPx = 2;
  halfSized.trackingHighlightMarginPx = 7;
  const int scaled = behindTheTissue(parameters), unscaled = behindTheTissue(halfSized);
  std::printf("fused pixels more than 10 px behind the tissue: %d with the sizes scaled, %d with those of 960x540\n",
              scaled, unscaled);
  // Measured 2026-11-26: 0 scaled, 1 262 with the sizes of 960x540 (frames 20 and 40: 0 / 1 145, 0 / 59).
  EXPECT_LE(scaled, 50);
  EXPECT_GT(unscaled, 5 * std::max(scaled, 20));
}
