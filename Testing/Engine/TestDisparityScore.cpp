// scoreDisparity grades every stereo accuracy test and `tissuemosaic stereo --ground-truth`: here it is graded itself,
// on maps small enough to score by hand.
#include "Core/Error.h"
#include "Stereo/DisparityScore.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace tissuemosaic;

namespace {
const float none = std::numeric_limits<float>::quiet_NaN();  // no estimate, or unknown truth
const float inf = std::numeric_limits<float>::infinity();
}  // namespace

// Truth 10 20 NaN / 30 40 50 and estimate 10.5 22 7 / NaN 41 48.5: the pixel of unknown truth is not evaluated (its
// estimate 7 counts nowhere), the missing estimate lowers the density, and the errors 0.5, 2, 1, 1.5 are bad-1
// only above 1 px and bad-2 only above 2 px (the errors of exactly 1 and 2 px are not bad).
TEST(DisparityScore, HandComputedSmallMap) {
  const cv::Mat truth = (cv::Mat_<float>(2, 3) << 10, 20, none, 30, 40, 50);
  const cv::Mat estimate = (cv::Mat_<float>(2, 3) << 10.5f, 22, 7, none, 41, 48.5f);
  const DisparityScore score = scoreDisparity(estimate, truth);
  EXPECT_EQ(score.evaluated, 5);
  EXPECT_EQ(score.estimated, 4);
  EXPECT_DOUBLE_EQ(score.density, 4.0 / 5.0);
  EXPECT_DOUBLE_EQ(score.badOver1, 2.0 / 4.0);  // 2 and 1.5
  EXPECT_DOUBLE_EQ(score.badOver2, 0.0);        // none above 2
  EXPECT_DOUBLE_EQ(score.meanAbsError, (0.5 + 2 + 1 + 1.5) / 4);
}

// The mask leaves out the pixel with the 2 px error: 4 evaluated, 3 estimated, errors 0.5, 1, 1.5.
TEST(DisparityScore, HandComputedWithMask) {
  const cv::Mat truth = (cv::Mat_<float>(2, 3) << 10, 20, none, 30, 40, 50);
  const cv::Mat estimate = (cv::Mat_<float>(2, 3) << 10.5f, 22, 7, none, 41, 48.5f);
  const cv::Mat mask = (cv::Mat_<uchar>(2, 3) << 255, 0, 255, 1, 255, 255);
  const DisparityScore score = scoreDisparity(estimate, truth, mask);
  EXPECT_EQ(score.evaluated, 4);
  EXPECT_EQ(score.estimated, 3);
  EXPECT_DOUBLE_EQ(score.density, 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(score.badOver1, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(score.badOver2, 0.0);
  EXPECT_DOUBLE_EQ(score.meanAbsError, (0.5 + 1 + 1.5) / 3);
}

// An error of 2.5 px is bad-2 as well; an infinite estimate is no estimate.
TEST(DisparityScore, BadTwoAndInfiniteEstimates) {
  const cv::Mat truth = (cv::Mat_<float>(1, 4) << 5, 5, 5, 5);
  const cv::Mat estimate = (cv::Mat_<float>(1, 4) << 7.5f, 5, inf, -inf);
  const DisparityScore score = scoreDisparity(estimate, truth);
  EXPECT_EQ(score.evaluated, 4);
  EXPECT_EQ(score.estimated, 2);
  EXPECT_DOUBLE_EQ(score.badOver1, 0.5);
  EXPECT_DOUBLE_EQ(score.badOver2, 0.5);
  EXPECT_DOUBLE_EQ(score.meanAbsError, 2.5 / 2);
}

// Nothing estimated: density 0 and the bad shares stay at their worst (1), so that an empty map never passes a
// "bad-1 <= x" bar; nothing evaluated: density 0 as well.
TEST(DisparityScore, EmptyEstimatesScoreWorst) {
  const cv::Mat truth = (cv::Mat_<float>(1, 2) << 5, 6);
  const DisparityScore nothingEstimated = scoreDisparity(cv::Mat(1, 2, CV_32F, cv::Scalar(none)), truth);
  EXPECT_EQ(nothingEstimated.evaluated, 2);
  EXPECT_EQ(nothingEstimated.estimated, 0);
  EXPECT_EQ(nothingEstimated.density, 0.0);
  EXPECT_EQ(nothingEstimated.badOver1, 1.0);
  EXPECT_EQ(nothingEstimated.badOver2, 1.0);
  const DisparityScore unknown = scoreDisparity(truth, cv::Mat(1, 2, CV_32F, cv::Scalar(none)));
  EXPECT_EQ(unknown.evaluated, 0);
  EXPECT_EQ(unknown.density, 0.0);
}

TEST(DisparityScore, RefusesMismatchedInput) {
  const cv::Mat truth(2, 3, CV_32F, cv::Scalar(1));
  EXPECT_THROW(scoreDisparity(cv::Mat(2, 2, CV_32F, cv::Scalar(1)), truth), Error);
  EXPECT_THROW(scoreDisparity(cv::Mat(2, 3, CV_64F, cv::Scalar(1)), truth), Error);
  EXPECT_THROW(scoreDisparity(truth, truth, cv::Mat(2, 3, CV_32F, cv::Scalar(1))), Error);
  EXPECT_THROW(scoreDisparity(truth, truth, cv::Mat(3, 2, CV_8U, cv::Scalar(1))), Error);
}
