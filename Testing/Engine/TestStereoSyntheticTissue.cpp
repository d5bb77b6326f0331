// The whole section II pipeline against the exact ground truth of a synthetic tissue pair (textured liver-like
// surface with low-texture patches, specular highlights that differ between the eyes, vignetting and noise).
#include "Core/StereoRig.h"
#include "StereoTestUtilities.h"
#include "Stereo/StereoMatcher.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>

#include <string>

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
