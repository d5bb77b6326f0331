// The disparity range's parts: the kernels' grid, a working distance through the rig, the parameters' modes and
// their files, the left-right feature matching the automatic range is measured from, the estimator's choice and
// hysteresis on known samples, and the matcher taking a new range between frames.
#include "Core/Error.h"
#include "Stereo/DisparityRange.h"
#include "Stereo/DisparityRangeEstimator.h"
#include "Stereo/DisparityRangeFollower.h"
#include "Stereo/StereoMatcher.h"
#include "Tracking/LeftRightMatching.h"
#include "Tracking/OrbFeatures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <string>

using namespace tissuemosaic;

namespace {

RectifiedGeometry rig(double focalPx, double baselineMm, double doffsPx) {
  RectifiedGeometry g;
  g.imageSize = cv::Size(640, 360);
  g.focalPx = focalPx;
  g.baselineMm = baselineMm;
  g.doffsPx = doffsPx;
  return g;
}

/// Disparities spread evenly over [lowPx, highPx].
std::vector<float> even(double lowPx, double highPx, int count) {
  std::vector<float> values;
  for (int i = 0; i < count; ++i) values.push_back(static_cast<float>(lowPx + (highPx - lowPx) * i / std::max(1, count - 1)));
  return values;
}

/// The q-quantile of the values (nearest rank below).
double quantileOf(std::vector<float> values, double q) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * (values.size() - 1))];
}

/// Texture with structure at several scales (blurred noise), 8-bit.
cv::Mat texture(int width, int height, uint64_t seed) {
  cv::Mat noise(height, width, CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::Mat smooth;
  cv::GaussianBlur(noise, smooth, cv::Size(0, 0), 1.2);
  cv::Mat image;
  cv::normalize(smooth, image, 0, 255, cv::NORM_MINMAX, CV_8U);
  return image;
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int y = 0; y < a.rows; ++y) {
    if (std::memcmp(a.ptr(y), b.ptr(y), a.cols * a.elemSize()) != 0) return false;
  }
  return true;
}

}  // namespace

TEST(DisparityRange, EndsOnTheKernelsGrid) {
  EXPECT_EQ(disparityRangeOnGrid(10.2, 20.7), (DisparityRange{8, 23}));
  EXPECT_EQ(disparityRangeOnGrid(-10.5, 3.0), (DisparityRange{-12, 3}));
  EXPECT_EQ(disparityRangeOnGrid(8.0, 11.0), (DisparityRange{8, 15})) << "at least two grid steps";
  EXPECT_EQ(disparityRangeOnGrid(8.0, 11.0).count() % kDisparityRangeGridPx, 0);
  EXPECT_EQ(disparityRangeOnGrid(8.0, 12.0), (DisparityRange{8, 15}));
  EXPECT_EQ(disparityRangeOnGrid(8.0, 12.0 + 1e-9), (DisparityRange{8, 15}));
  EXPECT_EQ(disparityRangeOnGrid(8.0, 16.0), (DisparityRange{8, 19}));
  EXPECT_THROW(disparityRangeOnGrid(0, 2000), Error);
  EXPECT_THROW(disparityRangeOnGrid(5, 2), Error);
  EXPECT_THROW(disparityRangeOnGrid(NAN, 2), Error);
  EXPECT_EQ(DisparityRange({-12, 3}).text(), "-12..3 px");
}

TEST(DisparityRange, WorkingDistanceThroughTheRig) {
  // f B = 5000 px mm: 50 mm -> 100 px, 100 mm -> 50 px.
  EXPECT_EQ(disparityRangeForDepthMm(rig(1000, 5, 0), 50, 100), (DisparityRange{48, 103}));
  // doffs moves every disparity down: 100 - 40 = 60, 50 - 40 = 10.
  EXPECT_EQ(disparityRangeForDepthMm(rig(1000, 5, 40), 50, 100), (DisparityRange{8, 63}));
  // The range holds the disparity of every depth in between.
  const RectifiedGeometry g = rig(1035.3, 4.143, 0);
  const DisparityRange range = disparityRangeForDepthMm(g, 30, 150);
  for (double z = 30; z <= 150; z += 0.5) EXPECT_TRUE(range.contains(g.focalPx * g.baselineMm / z)) << z;
  EXPECT_EQ(range, (DisparityRange{28, 143}));
  EXPECT_THROW(disparityRangeForDepthMm(rig(1000, 5, 0), 100, 50), Error);
  EXPECT_THROW(disparityRangeForDepthMm(rig(1000, 5, 0), 0, 50), Error);
  EXPECT_THROW(disparityRangeForDepthMm(rig(0, 5, 0), 30, 50), Error);
  try {
    disparityRangeForDepthMm(rig(1000, 5, 0), 2, 50);  // 2500 px at 2 mm
    FAIL() << "a range beyond the matcher's was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("2..50 mm gives disparities 100.0..2500.0 px"), std::string::npos)
        << error.what();
  }
}

TEST(DisparityRange, ModesOfTheParametersAndTheirFiles) {
  StereoParameters p;
  EXPECT_EQ(p.disparityRangeMode, DisparityRangeMode::Automatic) << "the default: a surgeon knows no disparities";
  EXPECT_FALSE(requestedDisparityRange(p, nullptr).has_value());
  p.setFixedDisparityRange(3, 44);
  EXPECT_EQ(*requestedDisparityRange(p, nullptr), (DisparityRange{3, 44}));
  p.disparityRangeMode = DisparityRangeMode::WorkingDistance;
  p.workingDistanceNearMm = 50;
  p.workingDistanceFarMm = 100;
  EXPECT_THROW(requestedDisparityRange(p, nullptr), Error) << "millimetres need the rig";
  const RectifiedGeometry g = rig(1000, 5, 0);
  EXPECT_EQ(*requestedDisparityRange(p, &g), (DisparityRange{48, 103}));
  p.workingDistanceFarMm = 40;
  EXPECT_THROW(p.validate(), Error);

  const auto parse = [](const std::string& body) {
    cv::FileStorage storage("%YAML:1.0\n---\nstereo:\n" + body, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    return StereoParameters::read(storage["stereo"]);
  };
  EXPECT_EQ(parse("   znccWindowPx: 9\n").disparityRangeMode, DisparityRangeMode::Automatic);
  EXPECT_EQ(parse("   maxDisparityPx: 60\n").disparityRangeMode, DisparityRangeMode::Fixed)
      << "a file that gives a range means it";
  EXPECT_EQ(parse("   disparityRange: auto\n   maxDisparityPx: 60\n").disparityRangeMode, DisparityRangeMode::Automatic);
  const StereoParameters distance =
      parse("   disparityRange: working-distance\n   workingDistanceNearMm: 35\n   workingDistanceFarMm: 90\n");
  EXPECT_EQ(distance.disparityRangeMode, DisparityRangeMode::WorkingDistance);
  EXPECT_FLOAT_EQ(distance.workingDistanceNearMm, 35);
  EXPECT_FLOAT_EQ(distance.workingDistanceFarMm, 90);
  EXPECT_THROW(parse("   disparityRange: sometimes\n"), Error);
  EXPECT_THROW(parse("   disparityRange: 3\n"), Error);

  // Written and read back, every mode.
  for (DisparityRangeMode mode : {DisparityRangeMode::Automatic, DisparityRangeMode::Fixed,
                                  DisparityRangeMode::WorkingDistance}) {
    StereoParameters written;
    written.disparityRangeMode = mode;
    written.workingDistanceNearMm = 42;
    cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    written.write(out);
    const std::string text = out.releaseAndGetString();
    cv::FileStorage in(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
    const StereoParameters read = StereoParameters::read(in["stereo"]);
    EXPECT_EQ(read.disparityRangeMode, mode) << disparityRangeModeName(mode);
    EXPECT_FLOAT_EQ(read.workingDistanceNearMm, 42);
    EXPECT_EQ(parseDisparityRangeMode(disparityRangeModeName(mode)), mode);
  }
}

TEST(LeftRightMatching, FindsTheShiftOfATexturedPair) {
  // Left x shows what right x - 23 shows: every match says 23.
  const cv::Mat wide = texture(400, 240, 11);
  const cv::Mat left = wide(cv::Rect(0, 0, 360, 240)).clone(), right = wide(cv::Rect(23, 0, 360, 240)).clone();
  OrbParameters orb;
  orb.levels = 1;
  OrbExtractor extractor(Device::Cpu, orb);
  const OrbFeatures l = extractor.extract(left), r = extractor.extract(right);
  const std::vector<LeftRightMatch> matches = matchLeftRight(l, r);
  ASSERT_GT(matches.size(), 0.5 * l.keypoints.size()) << l.keypoints.size() << " features";
  // Left features closer than 23 px + ORB's border to the left edge have no partner in the right view; a few of
  // them find a wrong one (the estimator drops that band). Every other match is right.
  int right23 = 0, partnered = 0, partneredRight23 = 0;
  for (const LeftRightMatch& m : matches) {
    right23 += m.disparityPx == 23.0f;
    if (l.keypoints[m.left].xPx - 23 >= orb.edgeThresholdPx) {
      ++partnered;
      partneredRight23 += m.disparityPx == 23.0f;
    }
  }
  EXPECT_EQ(partneredRight23, partnered);
  EXPECT_GE(right23, 0.98 * matches.size());
  // Features never match across rows: the same pair moved down by 5 rows gives no match at 23 px.
  const cv::Mat down = wide(cv::Rect(23, 5, 360, 235)).clone();
  cv::Mat rightDown(240, 360, CV_8U, cv::Scalar(128));
  down.copyTo(rightDown(cv::Rect(0, 0, 360, 235)));
  int acrossRows = 0;
  for (const LeftRightMatch& m : matchLeftRight(l, extractor.extract(rightDown))) acrossRows += m.disparityPx == 23.0f;
  EXPECT_EQ(acrossRows, 0);
  // ... unless the band is moved to where the right view's rows are: 5 rows above the left's.
  LeftRightMatchOptions offsetRows;
  offsetRows.rowOffsetPx = -5;
  const std::vector<LeftRightMatch> alongOffset = matchLeftRight(l, extractor.extract(rightDown), offsetRows);
  int offsetRight23 = 0;
  for (const LeftRightMatch& m : alongOffset) {
    offsetRight23 += m.disparityPx == 23.0f && m.rowOffsetPx == -5.0f;
  }
  EXPECT_GE(offsetRight23, 0.9 * alongOffset.size());
  EXPECT_GT(alongOffset.size(), 0.5 * matches.size());
  // The candidates stay within the disparities asked for.
  LeftRightMatchOptions narrow;
  narrow.minDisparityPx = 0;
  narrow.maxDisparityPx = 20;
  EXPECT_TRUE(matchLeftRight(l, r, narrow).size() < 0.05 * matches.size());
  EXPECT_TRUE(matchLeftRight(l, OrbFeatures{}).empty());
}

TEST(DisparityRangeFollower, AlignRightRowsMovesTheRightViewOntoTheLeftsRows) {
  cv::Mat right(6, 3, CV_8UC3);
  for (int y = 0; y < right.rows; ++y) right.row(y).setTo(cv::Scalar::all(10 * (y + 1)));
  // Rows 2 below the left's: moved 2 up, black rows enter at the bottom.
  const cv::Mat up = alignRightRows(right, 2);
  for (int y = 0; y < 6; ++y) {
    EXPECT_EQ(up.at<cv::Vec3b>(y, 1)[0], y < 4 ? 10 * (y + 3) : 0) << "row " << y;
  }
  const cv::Mat down = alignRightRows(right, -1);
  for (int y = 0; y < 6; ++y) EXPECT_EQ(down.at<cv::Vec3b>(y, 2)[2], y == 0 ? 0 : 10 * y) << "row " << y;
  EXPECT_EQ(alignRightRows(right, 0.4).data, right.data) << "under half a row: the same image, no copy";
  EXPECT_EQ(cv::countNonZero(alignRightRows(right, 9).reshape(1)), 0);
}

TEST(DisparityRangeEstimator, WantedRangeIsTheRobustEndsWithAMargin) {
  DisparityRangeEstimator estimator(Device::Cpu);
  const auto sample = [&](double low, double high, int count) { return estimator.sample(even(low, high, count), count, count); };
  // 101 matches over 60..100 px: quantiles 60.8 and 99.2, margin 0.15 x 38.4 = 5.76 px.
  const DisparitySample s = sample(60, 100, 101);
  EXPECT_NEAR(s.lowPx, 60.8, 1e-4);
  EXPECT_NEAR(s.highPx, 99.2, 1e-4);
  EXPECT_NEAR(s.medianPx, 80, 1e-4);
  const DisparityRange range = estimator.wantedRange(s);
  EXPECT_EQ(range, disparityRangeOnGrid(60.8 - 5.76, 99.2 + 5.76));
  EXPECT_EQ(range, (DisparityRange{52, 107}));
  // A few wild matches (left-right mismatches) barely move the ends.
  std::vector<float> wild = even(60, 100, 401);
  wild.push_back(-150);
  wild.push_back(300);
  EXPECT_EQ(estimator.wantedRange(estimator.sample(wild, 500, 500)), estimator.wantedRange(sample(60, 100, 401)));
  // A flat scene still gets the minimum margin on both sides.
  EXPECT_EQ(estimator.wantedRange(sample(40, 40, 50)), disparityRangeOnGrid(37, 43));
  // A deep view (31..157 px, ends 33.5..154.5): above, 0.15 x the span; below, at most a quarter of the far end's
  // disparity (depth at most 1.33 x the farthest tissue's), not 18 px down to 15 px (twice as deep).
  const DisparitySample deep = sample(31, 157, 101);
  const double span = deep.highPx - deep.lowPx;
  EXPECT_EQ(estimator.wantedRange(deep), disparityRangeOnGrid(deep.lowPx - 0.25 * deep.lowPx, deep.highPx + 0.15 * span));
  // The cap counts from the disparity at infinity, -doffs: with doffs 50 the same view lies at -19..107 px.
  DisparityRangeEstimatorOptions offset;
  offset.infinityDisparityPx = -50;
  DisparityRangeEstimator offsetEstimator(Device::Cpu, offset);
  const DisparitySample shifted = offsetEstimator.sample(even(-19, 107, 101), 101, 101);
  EXPECT_EQ(offsetEstimator.wantedRange(shifted),
            disparityRangeOnGrid(shifted.lowPx - 0.25 * (shifted.lowPx + 50), shifted.highPx + 0.15 * span));
}

TEST(DisparityRangeEstimator, TooFewMatchesIsAClearErrorNotADefault) {
  DisparityRangeEstimator estimator(Device::Cpu);
  const DisparitySample few = estimator.sample(even(10, 20, 12), 40, 35);
  try {
    estimator.wantedRange(few);
    FAIL() << "a range was chosen from 12 matches";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("12 left-right feature matches (40 features left, 35 right)"), std::string::npos) << message;
    EXPECT_NE(message.find("working distance"), std::string::npos) << message;
  }
  // A black pair, and a pair too small for ORB's border, measure no match at all.
  const cv::Mat black(360, 640, CV_8UC3, cv::Scalar::all(0));
  EXPECT_EQ(estimator.measure(black, black).matches(), 0);
  const cv::Mat tiny = texture(40, 30, 3);
  EXPECT_EQ(estimator.measure(tiny, tiny).matches(), 0);
  EXPECT_THROW(estimator.measure(cv::Mat(), black), Error);
  EXPECT_THROW(estimator.measure(black, cv::Mat(100, 100, CV_8UC3)), Error);
}

TEST(DisparityRangeEstimator, FollowsWithHysteresis) {
  DisparityRangeEstimator estimator(Device::Cpu);
  const auto evenSample = [&](double low, double high, int count) {
    return estimator.sample(even(low, high, count), count, count);
  };
  const DisparityRange start = estimator.wantedRange(evenSample(60, 100, 200));
  // Small moves of the tissue keep the range: no new workspace, no flapping.
  for (double shift : {-1.0, 1.0, -2.0, 2.0, 0.5}) {
    EXPECT_EQ(estimator.followingRange(start, evenSample(60 + shift, 100 + shift, 200)), start) << shift;
  }
  // The scope comes closer: the range moves with it, keeping its count, and holds the new ends with the margin.
  const DisparityRange closer = estimator.followingRange(start, evenSample(66, 106, 200));
  EXPECT_NE(closer, start);
  EXPECT_EQ(closer.count(), start.count());
  EXPECT_LE(closer.minPx, 66 - 0.5 * 5.8);
  EXPECT_GE(closer.maxPx, 106 + 0.5 * 5.8);
  // ... and stays there while the tissue stays.
  EXPECT_EQ(estimator.followingRange(closer, evenSample(66, 106, 200)), closer);
  // The tissue spreads over more disparities: the range widens to what is wanted.
  const DisparitySample spread = evenSample(50, 120, 200);
  EXPECT_EQ(estimator.followingRange(start, spread), estimator.wantedRange(spread));
  // Much less is needed: the range narrows, once it is clearly too wide.
  const DisparitySample flat = evenSample(78, 84, 200);
  EXPECT_EQ(estimator.followingRange(start, flat), estimator.wantedRange(flat));
  // A frame without matches (smoke, blur) keeps the range.
  EXPECT_EQ(estimator.followingRange(start, DisparitySample{}), start);
  // Nor does a view without tissue, whose random matches spread over any disparity (the scope withdrawn; at 960x540
  // such a frame once asked for -456..569 px and stopped the scan), nor a span far wider than the range.
  EXPECT_EQ(estimator.followingRange(start, evenSample(-456, 569, 200)), start);
  EXPECT_EQ(estimator.followingRange(start, evenSample(-100, 150, 200)), start);

  // The tissue coming closer by 4 px since the sample before: the high end is predicted that much further for the
  // next frame, and 5/3 as far when the sample serves the frames 3 to 5 after its own (every third frame measured).
  const DisparitySample before = evenSample(60, 100, 200), now = evenSample(64, 104, 200);
  const DisparityRange nextFrame = estimator.followingRange(start, now, &before);
  const DisparityRange threeAhead = estimator.followingRange(start, now, &before, 5.0 / 3.0);
  EXPECT_EQ(nextFrame, estimator.wantedRange(evenSample(64, 108, 200)));
  EXPECT_GT(threeAhead.maxPx, nextFrame.maxPx);
  EXPECT_GE(threeAhead.maxPx, 104 + 4 * 5.0 / 3.0 + 0.5 * 6.6);
}

TEST(DisparityRangeEstimator, WrongMatchesOfABlurredFrameDoNotWidenTheRange) {
  // A real in-vivo frame with motion blur: 180 matches on tissue at 22..114 px, and 8 % wrong ones (repeated texture,
  // glints) at -260..-100 px, beyond infinity (behind the camera), and at 250..300 px, beyond the near fence. The
  // quantiles alone pass 2 %: the range followed such frames to -268..171 px.
  DisparityRangeEstimator estimator(Device::Cpu);
  const std::vector<float> tissue = even(22, 114, 180);
  std::vector<float> blurred = tissue;
  for (float wrong : {-260.f, -240.f, -200.f, -180.f, -150.f, -120.f, -100.f, -110.f, -130.f, -255.f, 300.f, 270.f,
                      280.f, 250.f, 260.f}) {
    blurred.push_back(wrong);
  }
  const DisparitySample clean = estimator.sample(tissue, 500, 500);
  const DisparitySample withWrong = estimator.sample(blurred, 500, 500);
  EXPECT_EQ(withWrong.matches(), clean.matches()) << "every wrong match dropped, no tissue match";
  EXPECT_NEAR(withWrong.implausibleShare, 15.0 / 195.0, 1e-9);
  EXPECT_EQ(estimator.wantedRange(withWrong), estimator.wantedRange(clean));
  const DisparityRange current = estimator.wantedRange(clean);
  EXPECT_EQ(estimator.followingRange(current, withWrong), current);
  EXPECT_LE(current.count(), 200);
  // Without the rule the low end would follow them (quantile 0.02 of the 195 matches).
  EXPECT_LT(quantileOf(blurred, 0.02), -100);
  // With doffs the disparity at infinity moves: -30 px are tissue where infinity lies at -50 px.
  DisparityRangeEstimatorOptions offset;
  offset.infinityDisparityPx = -50;
  DisparityRangeEstimator offsetEstimator(Device::Cpu, offset);
  EXPECT_EQ(offsetEstimator.sample(even(-30, 60, 100), 100, 100).matches(), 100);
}

TEST(DisparityRangeFollower, RangeChangesOnlyBetweenFrames) {
  const cv::Mat wide = texture(700, 360, 5);
  const cv::Mat left = wide(cv::Rect(0, 0, 640, 360)).clone(), right = wide(cv::Rect(30, 0, 640, 360)).clone();
  const RectifiedGeometry g = rig(1000, 5, 0);
  DisparityRangeFollower follower(StereoParameters{}, g, Device::Cpu);
  ASSERT_TRUE(follower.automatic());
  const DisparityRange first = follower.beforeFrame(left, right);
  EXPECT_TRUE(first.contains(30));
  EXPECT_EQ(follower.beforeFrame(left, right), first) << "the same frame asked twice";
  // The tissue moved to 70 px: the next frame, not this one, gets a new range.
  const cv::Mat closerLeft = wide(cv::Rect(0, 0, 630, 360)).clone(), closerRight = wide(cv::Rect(70, 0, 630, 360)).clone();
  cv::Mat l2, r2;
  cv::copyMakeBorder(closerLeft, l2, 0, 0, 0, 10, cv::BORDER_REFLECT);
  cv::copyMakeBorder(closerRight, r2, 0, 0, 0, 10, cv::BORDER_REFLECT);
  follower.afterFrame(l2, r2);
  EXPECT_EQ(follower.history().current, first);
  const DisparityRange next = follower.beforeFrame(l2, r2);
  EXPECT_TRUE(next.contains(70)) << next.text();
  EXPECT_EQ(follower.history().changes, 1);
  EXPECT_NE(follower.description().find("auto: " + next.text()), std::string::npos) << follower.description();

  // Fixed and working-distance ranges need no image and never change.
  StereoParameters fixed;
  fixed.setFixedDisparityRange(-20, 80);
  DisparityRangeFollower fixedFollower(fixed, g, Device::Cpu);
  EXPECT_FALSE(fixedFollower.automatic());
  const cv::Mat black(360, 640, CV_8U, cv::Scalar(0));
  EXPECT_EQ(fixedFollower.beforeFrame(black, black), (DisparityRange{-20, 80}));
  fixedFollower.afterFrame(left, right);
  EXPECT_EQ(fixedFollower.beforeFrame(left, right), (DisparityRange{-20, 80}));
  EXPECT_EQ(fixedFollower.description(), "fixed: -20..80 px");
  StereoParameters distance;
  distance.disparityRangeMode = DisparityRangeMode::WorkingDistance;
  distance.workingDistanceNearMm = 50;
  distance.workingDistanceFarMm = 100;
  DisparityRangeFollower distanceFollower(distance, g, Device::Cpu);
  EXPECT_EQ(distanceFollower.beforeFrame(black, black), (DisparityRange{48, 103}));
  EXPECT_EQ(distanceFollower.description(), "working distance 50..100 mm: 48..103 px");

  // A black first frame is an error that says so.
  DisparityRangeFollower blind(StereoParameters{}, g, Device::Cpu);
  try {
    blind.beforeFrame(black, black);
    FAIL() << "a black frame got a range";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("0 left-right feature matches"), std::string::npos) << error.what();
  }
}

TEST(StereoMatcher, NewRangeBetweenFramesMatchesAFreshMatcher) {
  const cv::Mat wide = texture(400, 200, 8);
  const cv::Mat left = wide(cv::Rect(0, 0, 360, 200)).clone(), right = wide(cv::Rect(20, 0, 360, 200)).clone();
  StereoParameters p;
  p.setFixedDisparityRange(0, 31);
  StereoMatcher matcher(Device::Cpu, p);
  matcher.computeDisparity(left, right);
  for (const DisparityRange range : {DisparityRange{8, 39}, DisparityRange{4, 51}, DisparityRange{-4, 27}}) {
    matcher.setDisparityRange(range);
    EXPECT_EQ(matcher.disparityRange(), range);
    StereoParameters fresh = p;
    fresh.setFixedDisparityRange(range.minPx, range.maxPx);
    StereoMatcher reference(Device::Cpu, fresh);
    EXPECT_TRUE(identical(matcher.computeDisparity(left, right), reference.computeDisparity(left, right)))
        << range.text();
  }
  EXPECT_THROW(matcher.setDisparityRange({10, 5}), Error);
  EXPECT_EQ(matcher.disparityRange(), (DisparityRange{-4, 27})) << "a refused range leaves the last one";
}
