// Specular highlights (HighlightKernels.h): the seed rule on hand-made spots, and the whole matcher against the
// synthetic generator's ground truth (disparity and highlight mask), in the standard and the realistic look.
#include "StereoTestUtilities.h"
#include "Core/ParallelFor.h"
#include "Stereo/StereoMatcher.h"
#include "Stereo/StereoPipeline.h"
#include "SyntheticStereoScene.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>

using namespace tissuemosaic;
using namespace tissuemosaic::stereo;

namespace {

/// Scores of one matcher output over the pixel sets the bars name.
struct HighlightScores {
  DisparityScore all;          ///< every pixel with ground truth
  DisparityScore highlights;   ///< inside the generator's highlight mask
  DisparityScore brightTissue; ///< outside it, grey level above 230 in the left image
};

HighlightScores scoreHighlights(const synthetic::SyntheticStereoPair& pair, const cv::Mat& disparity) {
  cv::Mat grey;
  cv::cvtColor(pair.leftRectified, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat bright = (grey > 230) & (pair.highlightMaskLeft == 0);
  return {scoreDisparity(disparity, pair.disparityPx), scoreDisparity(disparity, pair.disparityPx, pair.highlightMaskLeft),
          scoreDisparity(disparity, pair.disparityPx, bright)};
}

void print(const char* what, const HighlightScores& s) {
  std::printf("%s: all density %.4f bad-1 %.4f | highlights (%ld px) density %.4f bad-2 %.4f | bright tissue (%ld px) "
              "density %.4f bad-2 %.4f\n",
              what, s.all.density, s.all.badOver1, s.highlights.evaluated, s.highlights.density,
              s.highlights.badOver2, s.brightTissue.evaluated, s.brightTissue.density, s.brightTissue.badOver2);
}

StereoParameters withoutHighlightRemoval() {
  StereoParameters parameters;
  parameters.specularMinGrey = 256.0f;
  return parameters;
}

synthetic::SyntheticStereoPair realisticPair(uint32_t seed) {
  synthetic::SyntheticStereoOptions options;
  options.lighting = synthetic::SyntheticLighting::Realistic;
  options.seed = seed;
  return synthetic::renderSyntheticStereoPair(options);
}

}  // namespace

// The bars on the realistic look (960x540): density >= 0.97 and bad-1 <= 0.02 over all pixels with ground
// truth; bad-2 <= 0.01 among the estimates inside the highlight mask; density >= 0.98 over diffuse pixels brighter
// than 230. Measured when written (seed 1): 0.994 / 0.0010; 0.0041; 1.000 (without highlight removal: highlights
// 0.0079, and the previous rule, grey >= 240 with a 14 px square margin, left bright tissue at density 0.64).
TEST(StereoHighlights, RealisticPairMeetsTheBars) {
  for (uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto pair = realisticPair(seed);
    ASSERT_GT(cv::countNonZero(pair.highlightMaskLeft), 1000) << "the realistic look should have highlights";
    StereoMatcher matcher(Device::Cpu, StereoParameters{});
    StereoExplanation explanation;
    const HighlightScores s = scoreHighlights(pair, matcher.computeDisparity(pair.leftRectified, pair.rightRectified,
                                                                             nullptr, &explanation));
    print(("realistic seed " + std::to_string(seed)).c_str(), s);
    ASSERT_GT(s.brightTissue.evaluated, 20000) << "the realistic look should have large bright diffuse areas";
    EXPECT_GT(explanation.highlight, 0);
    EXPECT_GE(s.all.density, 0.97);
    EXPECT_LE(s.all.badOver1, 0.02);
    EXPECT_LE(s.highlights.badOver2, 0.01);
    EXPECT_GE(s.brightTissue.density, 0.98);
  }
}

// The standard look's highlight is a large white disc with a soft tail: without removal ZNCC matches it with its
// twin over the whole disc (bad-2 0.41 inside the mask when written); removed and refilled it is 0.0018, at the
// density of the matcher without removal (0.994; the previous rule's output had no estimate there: 0.980).
TEST(StereoHighlights, StandardHighlightIsRemovedAndFilledFromTheTissueAround) {
  const auto pair = synthetic::renderSyntheticStereoPair(synthetic::SyntheticStereoOptions{});
  StereoMatcher matcher(Device::Cpu, StereoParameters{});
  const HighlightScores with = scoreHighlights(pair, matcher.computeDisparity(pair.leftRectified, pair.rightRectified));
  StereoMatcher without(Device::Cpu, withoutHighlightRemoval());
  const HighlightScores off = scoreHighlights(pair, without.computeDisparity(pair.leftRectified, pair.rightRectified));
  print("standard look", with);
  print("standard look, no highlight removal", off);
  ASSERT_GT(with.highlights.evaluated, 5000);
  EXPECT_GE(with.highlights.density, 0.99);
  EXPECT_LE(with.highlights.badOver2, 0.01);
  EXPECT_GT(off.highlights.badOver2, 0.1) << "the scene should show the phenomenon";
  EXPECT_GE(with.all.density, off.all.density - 0.001);
}

namespace {

/// A textured plane at disparity 10 in both eyes, with spots painted in: tests of the seed rule by hand.
struct SpotScene {
  static constexpr int kWidth = 240, kHeight = 120, kDisparity = 10;
  cv::Mat left, right;               ///< 8-bit grey
  Image<float> leftImage{Device::Cpu, kWidth, kHeight}, rightImage{Device::Cpu, kWidth, kHeight};
  Image<int16_t> leftWinners{Device::Cpu, kWidth, kHeight}, rightWinners{Device::Cpu, kWidth, kHeight};
  Image<int16_t> leftSeeds{Device::Cpu, kWidth, kHeight}, rightSeeds{Device::Cpu, kWidth, kHeight};

  SpotScene() {
    left = test::randomTexture(kWidth, kHeight, 5);
    left.convertTo(left, CV_8U, 0.5, 60);  // tissue grey levels 65..182
    right = test::shiftedView(left, kDisparity);
    for (int i = 0; i < kWidth * kHeight; ++i) {
      leftWinners.view()[i] = kDisparity;
      rightWinners.view()[i] = kDisparity;
    }
  }
  /// A disc of grey `grey` at left (x, y); in the right eye at x - d + shift (shift 0: the same surface point).
  void paintSpot(int x, int y, int radius, int grey, int shift) {
    cv::circle(left, {x, y}, radius, cv::Scalar(grey), cv::FILLED);
    cv::circle(right, {x - kDisparity + shift, y}, radius, cv::Scalar(grey), cv::FILLED);
  }
  void paintRectangle(const cv::Rect& inLeft, int grey, int shift) {
    left(inLeft).setTo(cv::Scalar(grey));
    right(inLeft - cv::Point(kDisparity - shift, 0)).setTo(cv::Scalar(grey));
  }
  /// Diffuse tissue (the same surface points in both eyes): an annulus around left (x, y).
  void paintAnnulus(int x, int y, int inner, int outer, int grey) {
    for (cv::Mat* image : {&left, &right}) {
      const int centre = image == &left ? x : x - kDisparity;
      cv::circle(*image, {centre, y}, (inner + outer) / 2, cv::Scalar(grey), outer - inner + 1);
    }
  }
  /// ZNCC matched the spot with its twin: the winners over it are off by `shift`.
  void matchTwins(int x, int y, int radius, int shift) {
    for (int yy = y - radius; yy <= y + radius; ++yy)
      for (int xx = x - radius; xx <= x + radius; ++xx) leftWinners.view().at(xx, yy) = kDisparity - shift;
  }
  /// Seeds of both eyes (CPU launcher); returns the left seeds within radius + 1 of (x, y) and the right seeds
  /// anywhere.
  std::pair<int, int> seeds(int x, int y, int radius, const StereoParameters& p = StereoParameters{}) {
    for (int i = 0; i < kWidth * kHeight; ++i) {
      leftImage.view()[i] = left.at<uint8_t>(i);
      rightImage.view()[i] = right.at<uint8_t>(i);
    }
    const HighlightRule rule{p.specularMinGrey, p.specularMaxRadiusPx, p.znccRadiusPx() + 1, p.specularMinContrastGrey,
                             p.specularViewToleranceGrey};
    detectHighlightSeedsCpu(DetectHighlightSeeds{leftImage.view(), rightImage.view(), leftWinners.view(),
                                                 rightWinners.view(), leftSeeds.view(), rightSeeds.view(), rule});
    int near = 0, right = 0;
    for (int yy = 0; yy < kHeight; ++yy) {
      for (int xx = 0; xx < kWidth; ++xx) {
        const bool leftSeed = leftSeeds.view().at(xx, yy) != kNoDisparity;
        near += leftSeed && std::abs(xx - x) <= radius + 1 && std::abs(yy - y) <= radius + 1;
        right += rightSeeds.view().at(xx, yy) != kNoDisparity;
      }
    }
    return {near, right};
  }
};

}  // namespace

TEST(StereoHighlights, SeedsAreSmallBrightContrastedAndViewDependent) {
  {  // A saturated spot that sits 6 px apart on the surface in the two eyes: seeds in both eyes (where the other
     // eye, at the tissue's disparity, does not see it).
    SpotScene scene;
    scene.paintSpot(100, 60, 4, 255, 6);
    const auto [left, right] = scene.seeds(100, 60, 4);
    EXPECT_GT(left, 10);
    EXPECT_GT(right, 10);
  }
  {  // The same spot matched with its twin (the winners over it are off by the shift): every spot pixel is a seed.
    SpotScene scene;
    scene.paintSpot(100, 60, 4, 255, 6);
    scene.matchTwins(100, 60, 4, 6);
    EXPECT_EQ(scene.seeds(100, 60, 4).first, cv::countNonZero(scene.left == 255));
  }
  {  // A bright diffuse spot: the same surface point in both eyes, matched where its surroundings match. No seeds.
    SpotScene scene;
    scene.paintSpot(100, 60, 4, 255, 0);
    const auto [left, right] = scene.seeds(100, 60, 4);
    EXPECT_EQ(left, 0);
    EXPECT_EQ(right, 0);
  }
  {  // Below the highlight level (240): not near saturation, not a seed however view-dependent.
    SpotScene scene;
    scene.paintSpot(100, 60, 4, 235, 6);
    EXPECT_EQ(scene.seeds(100, 60, 4).first, 0);
  }
  {  // Hardly brighter than its surroundings (244 on tissue of 235 out to 40 px: 9 grey levels, less than half the
     // headroom 255 - 235): bright tissue, not a seed, however view-dependent. Without the contrast test it is one.
    // (A view tolerance below the spot's 9 grey levels, so that the view test would pass it.)
    SpotScene scene;
    scene.paintAnnulus(100, 60, 5, 40, 235);
    scene.paintSpot(100, 60, 5, 244, 6);
    StereoParameters tolerant;
    tolerant.specularViewToleranceGrey = 5.0f;
    EXPECT_EQ(scene.seeds(100, 60, 5, tolerant).first, 0);
    StereoParameters noContrast = tolerant;
    noContrast.specularMinContrastGrey = 0.0f;
    EXPECT_GT(scene.seeds(100, 60, 5, noContrast).first, 0) << "the contrast test is what spared it";
  }
  {  // A saturated area wider than any highlight (110 px: the core reaches 48 px on both sides of its middle third):
     // bright tissue there, even where matched with its twin. With a larger maximum radius the middle is seeded too.
    SpotScene scene;
    scene.paintRectangle({60, 10, 110, 100}, 255, 6);
    scene.matchTwins(115, 60, 40, 6);
    const auto middleSeeds = [&](const StereoParameters& p) {
      scene.seeds(115, 60, 0, p);
      int count = 0;
      for (int y = 15; y < 105; ++y)
        for (int x = 60 + 48; x < 170 - 48; ++x) count += scene.leftSeeds.view().at(x, y) != kNoDisparity;
      return count;
    };
    EXPECT_EQ(middleSeeds(StereoParameters{}), 0);
    StereoParameters larger;
    larger.specularMaxRadiusPx = 60;
    EXPECT_GT(middleSeeds(larger), 0) << "the size test is what spared it";
  }
}

TEST(StereoHighlights, ExplanationCountsAddUpAndChangeNothing) {
  // A random texture with a flat patch (textureless windows), its right view at disparity 8, and candidates from 4:
  // the first 4 columns have none inside the right image.
  cv::Mat left = test::randomTexture(200, 120, 7);
  left(cv::Rect(60, 30, 40, 40)).setTo(cv::Scalar(128));
  const cv::Mat right = test::shiftedView(left, 8);
  StereoParameters parameters;
  parameters.minDisparityPx = 4;
  parameters.maxDisparityPx = 30;
  for (const Device device : {Device::Cpu}) {
    StereoMatcher matcher(device, parameters);
    const cv::Mat plain = matcher.computeDisparity(left, right);
    StereoExplanation e;
    const cv::Mat explained = matcher.computeDisparity(left, right, nullptr, &e);
    EXPECT_EQ(cv::norm(plain != explained & plain == plain), 0.0) << "counting must not change the result";
    std::printf("%s\n", e.json().c_str());
    EXPECT_EQ(e.pixels, 200 * 120);
    EXPECT_EQ(e.estimated, cv::countNonZero(explained == explained));
    EXPECT_EQ(e.estimated, e.pixels - e.removed() + e.filledBack);
    EXPECT_EQ(e.notFilled, e.pixels - cv::countNonZero(matcher.lastFilledDisparity() == matcher.lastFilledDisparity()));
    EXPECT_GE(e.outsideRightImage, 4 * 120);
    EXPECT_GE(e.texturelessWindow, 30 * 30);  // the patch's interior, at least
    EXPECT_GT(e.leftRightCheck, 0);
    EXPECT_GT(e.filledBack, 0);
  }
  // The same counts from the realistic look, highlights among them.
  const auto pair = realisticPair(1);
  StereoMatcher matcher(Device::Cpu, StereoParameters{});
  StereoExplanation e;
  const cv::Mat disparity = matcher.computeDisparity(pair.leftRectified, pair.rightRectified, nullptr, &e);
  EXPECT_EQ(e.estimated, cv::countNonZero(disparity == disparity));
  EXPECT_EQ(e.estimated, e.pixels - e.removed() + e.filledBack);
  EXPECT_GT(e.highlight, 500);
}

// Tracking and fusion leave out the pixels within trackingHighlightMarginPx of a left highlight seed (a highlight
// slides over the tissue as the camera moves): on the realistic look, the neighbourhood covers the generator's
// highlights and stays near them (bright diffuse tissue keeps its pixels for tracking), the matcher's disparity for
// tracking is its output without exactly those pixels, and with highlight removal off nothing is left out.
TEST(StereoHighlights, TrackingLeavesOutTheHighlightNeighbourhood) {
  const auto pair = realisticPair(1);
  const StereoParameters parameters;
  StereoMatcher matcher(Device::Cpu, parameters);
  const cv::Mat disparity = matcher.computeDisparity(pair.leftRectified, pair.rightRectified);
  const cv::Mat near = matcher.lastHighlightNeighbourhood();
  ASSERT_EQ(near.type(), CV_8U);
  ASSERT_EQ(near.size(), disparity.size());
  const int highlightPixels = cv::countNonZero(pair.highlightMaskLeft);
  const int covered = cv::countNonZero(pair.highlightMaskLeft & (near != 0));
  // Bright pixels farther from every generator highlight than the margin (square) and a seed's tail reach: tissue.
  const int reach = 2 * (parameters.trackingHighlightMarginPx + parameters.specularMarginPx) + 1;
  cv::Mat highlightsGrown;
  cv::dilate(pair.highlightMaskLeft, highlightsGrown, cv::getStructuringElement(cv::MORPH_RECT, {reach, reach}));
  cv::Mat grey;
  cv::cvtColor(pair.leftRectified, grey, cv::COLOR_BGR2GRAY);
  const cv::Mat brightTissue = (grey > 230) & (highlightsGrown == 0);
  std::printf("highlight neighbourhood: %d px; generator highlights %d px, %d covered; bright tissue far from them "
              "%d px, %d left out\n",
              cv::countNonZero(near), highlightPixels, covered, cv::countNonZero(brightTissue),
              cv::countNonZero(brightTissue & (near != 0)));
  // Measured when written: 25390 px (4.9% of the image); 1074 of 1168 highlight pixels covered (0.92); 11052 of
  // 62365 bright tissue pixels far from the highlights left out (0.18; the old rule, grey >= 240 with 14 px, left
  // bright tissue at density 0.64 in the stereo output itself). No neighbourhood fails the first bound, one around
  // every bright pixel the last.
  ASSERT_GT(highlightPixels, 100) << "the scene should show highlights";
  EXPECT_GE(covered, 0.9 * highlightPixels);
  EXPECT_LE(cv::countNonZero(near), 0.1 * near.rows * near.cols);
  EXPECT_LE(cv::countNonZero(brightTissue & (near != 0)), 0.3 * cv::countNonZero(brightTissue));

  const cv::Mat kept = matcher.lastDisparityAwayFromHighlights();
  ASSERT_EQ(kept.type(), CV_32F);
  ASSERT_EQ(kept.size(), disparity.size());
  long wrong = 0;
  for (int i = 0; i < disparity.rows * disparity.cols; ++i) {
    const float d = disparity.at<float>(i), k = kept.at<float>(i);
    const bool expected = near.at<uint8_t>(i) != 0 ? std::isnan(k) : (std::isnan(d) ? std::isnan(k) : k == d);
    wrong += !expected;
  }
  EXPECT_EQ(wrong, 0);

  StereoMatcher without(Device::Cpu, withoutHighlightRemoval());
  const cv::Mat all = without.computeDisparity(pair.leftRectified, pair.rightRectified);
  EXPECT_EQ(cv::countNonZero(without.lastHighlightNeighbourhood()), 0);
  const cv::Mat allKept = without.lastDisparityAwayFromHighlights();
  EXPECT_EQ(std::memcmp(all.data, allKept.data, all.total() * sizeof(float)), 0) << "a copy with removal off";
}
