// A disparity range that cannot hold the scene is said (StereoMatcher::lastRangeEndCounts, rangeTooNarrowWarning):
// the winners pile up on the range's end candidate, where the cost was still improving.
#include "StereoTestUtilities.h"
#include "Stereo/StereoMatcher.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;

TEST(StereoRangeEnds, ARangeBelowTheSceneIsSaid) {
  // A small random texture seen 20..23 px apart: 0..12 px cannot hold it, 8..40 px can.
  const cv::Mat left = test::randomTexture(160, 90, 5, 4.0);
  const cv::Mat right = test::shiftedView(left, 20.0, 0.02);
  StereoParameters parameters;
  parameters.setFixedDisparityRange(0, 12);
  StereoMatcher narrow(Device::Cpu, parameters);
  narrow.computeDisparity(left, right);
  const RangeEndCounts counts = narrow.lastRangeEndCounts();
  std::printf("0..12: %ld winners, %ld on 0, %ld on 12\n", counts.withWinner, counts.atMin, counts.atMax);
  // Far from the match the correlation of fine texture is noise: the winners pile up on both ends.
  EXPECT_GT(counts.atMax + counts.atMin, 4 * kRangeEndWarningShare * counts.withWinner);
  const std::string warning = rangeTooNarrowWarning(counts);
  EXPECT_NE(warning.find("the disparity range 0..12 px cannot hold the scene"), std::string::npos) << warning;
  EXPECT_NE(warning.find("upper end (12 px)"), std::string::npos) << warning;

  parameters.setFixedDisparityRange(8, 40);
  StereoMatcher holds(Device::Cpu, parameters);
  holds.computeDisparity(left, right);
  const RangeEndCounts held = holds.lastRangeEndCounts();
  EXPECT_LT(held.atMin + held.atMax, kRangeEndWarningShare * held.withWinner);
  std::printf("8..40: %ld winners, %ld on 8, %ld on 40\n", held.withWinner, held.atMin, held.atMax);
  EXPECT_GT(held.withWinner, 0);
  EXPECT_EQ(rangeTooNarrowWarning(held), "");
}

TEST(StereoRangeEnds, ARangeAboveTheSceneIsSaidAtItsLowerEnd) {
  const cv::Mat left = test::randomTexture(160, 90, 6, 4.0);
  const cv::Mat right = test::shiftedView(left, 4.0);
  StereoParameters parameters;
  parameters.setFixedDisparityRange(12, 40);
  StereoMatcher matcher(Device::Cpu, parameters);
  matcher.computeDisparity(left, right);
  const std::string warning = rangeTooNarrowWarning(matcher.lastRangeEndCounts());
  EXPECT_NE(warning.find("cannot hold the scene"), std::string::npos) << warning;
  EXPECT_NE(warning.find("lower end (12 px)"), std::string::npos) << warning;
}
