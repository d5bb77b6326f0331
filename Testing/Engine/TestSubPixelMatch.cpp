// Sub-pixel match refinement (Tracking/SubPixelMatch.h) on the CPU: known sub-pixel shifts of a textured image are
// recovered, and matches that cannot be located (no texture, near the border, shifted too far) are not locked.

#include "Core/Error.h"
#include "Tracking/SubPixelMatch.h"

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include <random>

using namespace tissuemosaic;

namespace {

/// A smooth random texture (blurred noise) and the same texture translated by (dx, dy) px.
struct ShiftedPair {
  cv::Mat reference, shifted;
};

ShiftedPair texturePair(float dx, float dy, unsigned seed = 3) {
  cv::Mat noise(240, 320, CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
  cv::normalize(noise, noise, 20, 235, cv::NORM_MINMAX);
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, dy);
  cv::Mat moved;
  cv::warpAffine(noise, moved, shift, noise.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  ShiftedPair pair;
  noise.convertTo(pair.reference, CV_8U);
  moved.convertTo(pair.shifted, CV_8U);
  return pair;
}

}  // namespace

TEST(SubPixelMatch, RecoversKnownSubPixelShifts) {
  const float dx = 0.37f, dy = -0.62f;
  const ShiftedPair pair = texturePair(dx, dy);
  std::vector<SubPixelMatchQuery> queries;
  for (int y = 30; y < 210; y += 15) {
    for (int x = 30; x < 290; x += 15) {
      SubPixelMatchQuery q;
      q.fromPx = cv::Point2f(static_cast<float>(x), static_cast<float>(y));
      q.toPx = cv::Point2f(std::round(x + dx), std::round(y + dy));  // ORB's pixel grid
      queries.push_back(q);
    }
  }
  SubPixelMatcher matcher(Device::Cpu, 2.0);
  const std::vector<SubPixelMatchAnswer> answers = matcher.refine({pair.reference, pair.shifted}, queries);
  ASSERT_EQ(answers.size(), queries.size());
  int locked = 0;
  double worstErrorPx = 0, sumErrorPx = 0, sumStartErrorPx = 0;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    sumStartErrorPx += std::hypot(queries[i].toPx.x - (queries[i].fromPx.x + dx), queries[i].toPx.y - (queries[i].fromPx.y + dy));
    if (!answers[i].locked) continue;
    ++locked;
    const double error = std::hypot(answers[i].toPx.x - (queries[i].fromPx.x + dx), answers[i].toPx.y - (queries[i].fromPx.y + dy));
    worstErrorPx = std::max(worstErrorPx, error);
    sumErrorPx += error;
  }
  const double startErrorPx = sumStartErrorPx / answers.size();
  std::printf("%d of %zu locked, mean error %.4f px (%.4f px on the pixel grid), worst %.4f px\n", locked,
              answers.size(), sumErrorPx / locked, startErrorPx, worstErrorPx);
  EXPECT_GE(locked, static_cast<int>(0.95 * answers.size()));
  // Bilinear LK against a bicubic shift of an 8-bit image: a few hundredths of a pixel, 10x better than the grid.
  EXPECT_LT(sumErrorPx / locked, 0.06);
  EXPECT_LT(sumErrorPx / locked, 0.1 * startErrorPx);
  EXPECT_LT(worstErrorPx, 0.1);
}

TEST(SubPixelMatch, DoesNotLockWhatItCannotLocate) {
  const ShiftedPair pair = texturePair(0.5f, 0.5f);
  cv::Mat flat(pair.reference.size(), CV_8U, cv::Scalar(128));
  SubPixelMatcher matcher(Device::Cpu, 1.0);
  SubPixelMatchQuery blank;  // no texture in the reference window
  blank.fromPx = blank.toPx = cv::Point2f(100, 100);
  blank.referenceImage = 2;
  SubPixelMatchQuery border;  // the window would leave the image
  border.fromPx = border.toPx = cv::Point2f(3, 100);
  SubPixelMatchQuery tooFar;  // the true match is 4 px away, beyond the 1 px limit
  tooFar.fromPx = cv::Point2f(120, 120);
  tooFar.toPx = cv::Point2f(124.5f, 120.5f);
  SubPixelMatchQuery good;
  good.fromPx = cv::Point2f(120, 120);
  good.toPx = cv::Point2f(121, 121);
  const std::vector<SubPixelMatchAnswer> answers =
      matcher.refine({pair.reference, pair.shifted, flat}, {blank, border, tooFar, good});
  EXPECT_FALSE(answers[0].locked);
  EXPECT_FALSE(answers[1].locked);
  EXPECT_FALSE(answers[2].locked);
  EXPECT_EQ(answers[2].toPx, tooFar.toPx) << "an unlocked match keeps its start";
  ASSERT_TRUE(answers[3].locked);
  EXPECT_NEAR(answers[3].toPx.x, 120.5f, 0.05f);
  EXPECT_NEAR(answers[3].toPx.y, 120.5f, 0.05f);
}

TEST(SubPixelMatch, RejectsBadInput) {
  const ShiftedPair pair = texturePair(0, 0);
  SubPixelMatcher matcher(Device::Cpu, 2.0);
  SubPixelMatchQuery q;
  q.fromPx = q.toPx = cv::Point2f(50, 50);
  q.image = 5;
  EXPECT_THROW(matcher.refine({pair.reference, pair.shifted}, {q}), Error);
  q.image = 1;
  cv::Mat small(10, 10, CV_8U, cv::Scalar(0)), colour(pair.reference.size(), CV_8UC3);
  EXPECT_THROW(matcher.refine({pair.reference, small}, {q}), Error);
  EXPECT_THROW(matcher.refine({pair.reference, colour}, {q}), Error);
  EXPECT_TRUE(matcher.refine({pair.reference, pair.shifted}, {}).empty());
  EXPECT_THROW(SubPixelMatcher(Device::Cpu, 0.0), Error);
  EXPECT_THROW(SubPixelMatcher(Device::Cpu, 2.0, 9), Error);
}
