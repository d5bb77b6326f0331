// The whole section II pipeline on real rectified pairs with ground truth (Middlebury v2, Scharstein and Szeliski
// 2003): density over non-occluded pixels and bad-2 over the pixels that carry an estimate.
#include "StereoTestUtilities.h"
#include "Stereo/StereoMatcher.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;

namespace {

// The bar is density >= 0.95 with bad-2 <= 0.04; the paper's local ZNCC matcher with its filling does not
// reach the bad-2 part (docs/STEREO.md, "What is left"), the AD-Census method does (tests at the end). The paper's
// bounds guard its measured level (cones: density
// 0.999, bad-2 0.098; teddy: 0.992, 0.123 when written) against regressions.
void checkScene(const std::string& name, double maxBadOver2, StereoMethod method = StereoMethod::Paper) {
  test::MiddleburyScene scene;
  if (!test::loadMiddlebury(name, scene)) {
    const std::string missing = "Middlebury data not found under " + test::middleburyDirectory();
    if (test::testDataRequired()) FAIL() << missing << " (TM_REQUIRE_TEST_DATA=1: this machine must have it)";
    GTEST_SKIP() << missing;
  }
  StereoParameters parameters;
  parameters.minDisparityPx = 0;
  parameters.maxDisparityPx = scene.maxDisparity;
  parameters.method = method;
  // Middlebury's scenes have bright diffuse surfaces, not the specular highlights of tissue that this mask is for.
  if (method == StereoMethod::AdCensus) parameters.specularMinGrey = 256.0f;
  StereoMatcher matcher(Device::Cpu, parameters);
  const cv::Mat disparity = matcher.computeDisparity(scene.left, scene.right);
  const auto zncc = test::scoreDisparity(matcher.lastZnccDisparity(), scene.groundTruth, scene.nonOccluded);
  const auto filled = test::scoreDisparity(matcher.lastFilledDisparity(), scene.groundTruth, scene.nonOccluded);
  const auto final = test::scoreDisparity(disparity, scene.groundTruth, scene.nonOccluded);
  std::printf("%s %s: zncc density %.4f bad2 %.4f | filled density %.4f bad2 %.4f | final density %.4f bad1 %.4f bad2 %.4f mae %.3f\n",
              name.c_str(), stereoMethodName(method), zncc.density, zncc.badOver2, filled.density, filled.badOver2, final.density,
              final.badOver1, final.badOver2, final.meanAbsError);
  EXPECT_GE(final.density, 0.95);
  EXPECT_LE(final.badOver2, maxBadOver2);
}

}  // namespace

TEST(StereoMiddlebury, ConesDensityAndBadPixels) { checkScene("cones", 0.11); }
TEST(StereoMiddlebury, TeddyDensityAndBadPixels) { checkScene("teddy", 0.14); }

// AD-Census (the engine's alternative matcher) against the bar itself: density >= 0.95 and bad-2 <= 0.04
// over non-occluded pixels (measured when written: cones 0.971 / 0.021, teddy 0.972 / 0.020 in the prototype).
TEST(StereoMiddlebury, AdCensusConesMeetsTheBar) { checkScene("cones", 0.04, StereoMethod::AdCensus); }
TEST(StereoMiddlebury, AdCensusTeddyMeetsTheBar) { checkScene("teddy", 0.04, StereoMethod::AdCensus); }
