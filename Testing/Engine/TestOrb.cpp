// The ORB extractor and Hamming matcher on the CPU (the CUDA path is the same code, compared in TestOrbCuda.cpp):
// FAST-9 on hand-made corners, the orientation of a rotated patch, the descriptor's invariance to rotation, the
// matcher against brute force, and the quality of frame-to-frame matches against OpenCV's cv::ORB with the
// ground-truth motion of a synthetic scan.
#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Tracking/OrbFeatures.h"
#include "Tracking/OrbKernels.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace tissuemosaic;

namespace {

ImageView<const uint8_t> viewOf(const cv::Mat& grey) { return {grey.ptr<uint8_t>(), grey.cols, grey.rows}; }

/// Orientation (degrees, [0, 360)) and descriptor of the patch centred on integer pixel (x, y), through the
/// extractor's own per-feature step.
struct Described {
  double angleDeg;
  cv::Mat descriptor;
};

std::vector<Described> describeAt(const cv::Mat& grey, const std::vector<cv::Point>& points) {
  cv::Mat smoothed;
  // The extractor's smoothing, run through its functors on the CPU.
  cv::Mat rows(grey.size(), CV_16U);
  smoothed.create(grey.size(), CV_8U);
  const ImageView<uint16_t> rowView{rows.ptr<uint16_t>(), grey.cols, grey.rows};
  const ImageView<uint8_t> smoothView{smoothed.ptr<uint8_t>(), grey.cols, grey.rows};
  const int64_t pixels = static_cast<int64_t>(grey.cols) * grey.rows;
  for (int64_t i = 0; i < pixels; ++i) orb::SmoothRows{viewOf(grey), rowView}(i);
  for (int64_t i = 0; i < pixels; ++i) orb::SmoothColumns{rowView, smoothView}(i);
  std::vector<orb::LevelKeypoint> features;
  for (const cv::Point& p : points) features.push_back({p.x, p.y, 1, 0, 0});
  std::vector<uint8_t> descriptors(points.size() * orb::kDescriptorBytes);
  int control[orb::kControlCount] = {0, 0, static_cast<int>(points.size()), 0};
  const orb::Describe describe{viewOf(grey), ImageView<const uint8_t>(smoothView), OrbExtractor::pattern().data(),
                               control, features.data(), descriptors.data()};
  std::vector<Described> result;
  for (std::size_t i = 0; i < points.size(); ++i) {
    describe(static_cast<int64_t>(i));
    double angle = std::atan2(double(features[i].m01), double(features[i].m10)) * 180 / M_PI;
    result.push_back({angle < 0 ? angle + 360 : angle,
                      cv::Mat(1, orb::kDescriptorBytes, CV_8U, descriptors.data() + i * orb::kDescriptorBytes).clone()});
  }
  return result;
}

double angleDifference(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180) d -= 360;
  if (d < -180) d += 360;
  return d;
}

cv::Mat syntheticGrey(const synthetic::SyntheticScanFrame& frame) {
  cv::Mat grey;
  cv::cvtColor(frame.leftRectified, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

synthetic::SyntheticScanOptions scanOptions() {
  synthetic::SyntheticScanOptions options;
  options.width = 960;
  options.height = 540;
  options.frames = 8;
  options.seed = 5;
  return options;
}

}  // namespace

TEST(OrbFast, ScoresNineContiguousPixelsAndRejectsEight) {
  // A 7x7 patch: centre 100, circle pixels 0..n-1 (clockwise from the top) at 160, the rest at 100.
  for (int arc : {8, 9, 12}) {
    cv::Mat image(7, 7, CV_8U, cv::Scalar(100));
    for (int k = 0; k < arc; ++k) {
      int dx, dy;
      orb::fastCircle((k + 5) % 16, dx, dy);  // start the arc anywhere: the test is rotation-free
      image.at<uint8_t>(3 + dy, 3 + dx) = 160;
    }
    const int score = orb::fastScore(viewOf(image), 3, 3, 20);
    if (arc < 9) EXPECT_EQ(score, 0) << arc << " contiguous brighter pixels are not a FAST-9 corner";
    else EXPECT_EQ(score, 60) << "score: the largest threshold the arc passes";
    EXPECT_EQ(orb::fastScore(viewOf(image), 3, 3, 60), 0) << "the test is strict (> threshold)";
  }
  // A dark arc of 9 counts too.
  cv::Mat image(7, 7, CV_8U, cv::Scalar(100));
  for (int k = 0; k < 9; ++k) {
    int dx, dy;
    orb::fastCircle(k, dx, dy);
    image.at<uint8_t>(3 + dy, 3 + dx) = static_cast<uint8_t>(40 + k);
  }
  EXPECT_EQ(orb::fastScore(viewOf(image), 3, 3, 20), 100 - 48);
}

TEST(OrbFast, FindsTheCornersOfHandMadeShapes) {
  // Two rectangles (one bright, one dark) on mid grey: features at their 8 corners and nowhere else.
  cv::Mat image(200, 260, CV_8U, cv::Scalar(120));
  cv::rectangle(image, cv::Rect(40, 50, 70, 90), cv::Scalar(220), cv::FILLED);
  cv::rectangle(image, cv::Rect(150, 40, 60, 110), cv::Scalar(30), cv::FILLED);
  const std::vector<cv::Point2f> corners = {{40, 50}, {109, 50}, {40, 139}, {109, 139},
                                            {150, 40}, {209, 40}, {150, 149}, {209, 149}};
  OrbParameters parameters;
  parameters.levels = 1;
  parameters.fastThreshold = 20;
  OrbExtractor extractor(Device::Cpu, parameters);
  const OrbFeatures features = extractor.extract(image);
  ASSERT_EQ(features.descriptors.rows, static_cast<int>(features.keypoints.size()));
  for (const OrbKeypoint& k : features.keypoints) {
    double nearest = 1e9;
    for (const cv::Point2f& c : corners) nearest = std::min(nearest, double(std::hypot(k.xPx - c.x, k.yPx - c.y)));
    EXPECT_LE(nearest, 2.5) << "feature away from every corner at " << k.xPx << ", " << k.yPx;
  }
  for (const cv::Point2f& c : corners) {
    double nearest = 1e9;
    for (const OrbKeypoint& k : features.keypoints) nearest = std::min(nearest, double(std::hypot(k.xPx - c.x, k.yPx - c.y)));
    EXPECT_LE(nearest, 2.5) << "corner " << c << " not found";
  }
  EXPECT_LE(features.keypoints.size(), 16u) << "3x3 non-maximum suppression leaves about one feature per corner";
  // The output order is (response desc, level, y, x).
  for (std::size_t i = 1; i < features.keypoints.size(); ++i) {
    EXPECT_GE(features.keypoints[i - 1].response, features.keypoints[i].response);
  }
}

TEST(OrbFast, SpreadsFeaturesOverTheGridAndKeepsTheBudget) {
  const synthetic::SyntheticScan scan(scanOptions());
  const cv::Mat grey = syntheticGrey(scan.renderFrame(0));
  OrbParameters parameters;
  parameters.maxFeatures = 1500;
  OrbExtractor extractor(Device::Cpu, parameters);
  const OrbFeatures features = extractor.extract(grey);
  EXPECT_EQ(features.keypoints.size(), 1500u);
  int perCell[64][64] = {};
  for (const OrbKeypoint& k : features.keypoints) {
    EXPECT_GE(k.levelX, parameters.edgeThresholdPx);
    EXPECT_GE(k.levelY, parameters.edgeThresholdPx);
    if (k.level == 0) EXPECT_LE(++perCell[k.levelY / parameters.cellSizePx][k.levelX / parameters.cellSizePx], parameters.maxPerCell);
  }
  // Deterministic: a second run gives the same bytes.
  const OrbFeatures again = extractor.extract(grey);
  ASSERT_EQ(again.keypoints.size(), features.keypoints.size());
  EXPECT_EQ(cv::norm(again.descriptors, features.descriptors, cv::NORM_HAMMING), 0.0);
}

TEST(OrbOrientation, FollowsARotatedPatch) {
  const synthetic::SyntheticScan scan(scanOptions());
  const cv::Mat grey = syntheticGrey(scan.renderFrame(0));
  // The strongest level-0 features away from the image border; the image is rotated by 30 degrees about each
  // point itself, so the point stays at the same pixel.
  OrbParameters parameters;
  parameters.levels = 1;
  OrbExtractor extractor(Device::Cpu, parameters);
  const OrbFeatures features = extractor.extract(grey);
  int checked = 0, good = 0;
  std::vector<double> errors;
  for (const OrbKeypoint& k : features.keypoints) {
    if (checked == 60) break;
    if (k.levelX < 60 || k.levelY < 60 || k.levelX >= grey.cols - 60 || k.levelY >= grey.rows - 60) continue;
    const cv::Point p(k.levelX, k.levelY);
    cv::Mat rotated;
    const cv::Mat R = cv::getRotationMatrix2D(cv::Point2f(float(p.x), float(p.y)), 30.0, 1.0);  // anticlockwise on screen
    cv::warpAffine(grey, rotated, R, grey.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    const Described before = describeAt(grey, {p})[0], after = describeAt(rotated, {p})[0];
    EXPECT_NEAR(before.angleDeg, k.angleDeg, 1e-3) << "the extractor reports the same orientation";
    // Our angles are atan2(y, x) with y down, i.e. clockwise on screen: anticlockwise by 30 is -30.
    ++checked;
    errors.push_back(std::abs(angleDifference(after.angleDeg, before.angleDeg) + 30.0));
    good += errors.back() <= 6.0;
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  const double medianError = errors[errors.size() / 2];
  // The rotation's bilinear resampling and the sensor noise move the centroid a little: a median error of 1-2
  // degrees (a sign or axis mistake would give 60).
  std::printf("orientation error under 30 degrees rotation: median %.2f degrees, within 6 degrees at %d of %d "
              "features\n", medianError, good, checked);
  EXPECT_EQ(checked, 60);
  EXPECT_LE(medianError, 2.5);
  EXPECT_GE(good, checked * 9 / 10);
}

TEST(OrbDescriptor, IsInvariantToRotation) {
  const synthetic::SyntheticScan scan(scanOptions());
  const cv::Mat grey = syntheticGrey(scan.renderFrame(0));
  const cv::Point2f centre(480, 270);
  cv::Mat rotated;
  const cv::Mat R = cv::getRotationMatrix2D(centre, 30.0, 1.0);
  cv::warpAffine(grey, rotated, R, grey.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  std::vector<cv::Point> points, moved;
  for (int y = 170; y <= 370; y += 20) {
    for (int x = 330; x <= 630; x += 20) {
      points.emplace_back(x, y);
      const double u = R.at<double>(0, 0) * x + R.at<double>(0, 1) * y + R.at<double>(0, 2);
      const double v = R.at<double>(1, 0) * x + R.at<double>(1, 1) * y + R.at<double>(1, 2);
      moved.emplace_back(cvRound(u), cvRound(v));
    }
  }
  const std::vector<Described> a = describeAt(grey, points), b = describeAt(rotated, moved);
  std::vector<double> same, different;
  for (std::size_t i = 0; i < a.size(); ++i) {
    same.push_back(cv::norm(a[i].descriptor, b[i].descriptor, cv::NORM_HAMMING));
    different.push_back(cv::norm(a[i].descriptor, b[(i * 37 + 11) % b.size()].descriptor, cv::NORM_HAMMING));
  }
  std::nth_element(same.begin(), same.begin() + same.size() / 2, same.end());
  std::nth_element(different.begin(), different.begin() + different.size() / 2, different.end());
  const double medianSame = same[same.size() / 2], medianDifferent = different[different.size() / 2];
  std::printf("Hamming distance under 30 degrees rotation: same point median %.0f, random pairs median %.0f (of 256)\n",
              medianSame, medianDifferent);
  EXPECT_LE(medianSame, 0.4 * medianDifferent);
  EXPECT_GE(medianDifferent, 90.0) << "random pairs of a good binary descriptor differ in about half the bits";
}

TEST(HammingMatcher, EqualsBruteForce) {
  std::mt19937 generator(99);
  cv::Mat a(300, 32, CV_8U), b(450, 32, CV_8U);
  cv::randu(a, 0, 256);
  cv::randu(b, 0, 256);
  // Near copies and exact duplicates, so ties and small distances occur.
  for (int i = 0; i < 100; ++i) {
    a.row(i).copyTo(b.row(3 * i));
    b.at<uint8_t>(3 * i, i % 32) ^= static_cast<uint8_t>(1 << (i % 8));
    if (i % 10 == 0) a.row(i).copyTo(b.row(3 * i + 1));
    if (i % 10 == 0) a.row(i).copyTo(b.row(3 * i + 2));
  }
  HammingMatcher matcher(Device::Cpu);
  for (int k : {1, 3, 8}) {
    const auto matches = matcher.match(a, b, k);
    ASSERT_EQ(matches.size(), 300u);
    for (int i = 0; i < a.rows; ++i) {
      std::vector<std::pair<int, int>> all;
      for (int j = 0; j < b.rows; ++j) all.emplace_back(static_cast<int>(cv::norm(a.row(i), b.row(j), cv::NORM_HAMMING)), j);
      std::sort(all.begin(), all.end());
      ASSERT_EQ(matches[i].size(), static_cast<std::size_t>(k));
      for (int j = 0; j < k; ++j) {
        EXPECT_EQ(matches[i][j].queryIdx, i);
        EXPECT_EQ(matches[i][j].trainIdx, all[j].second) << "row " << i << " rank " << j;
        EXPECT_EQ(matches[i][j].distance, all[j].first);
      }
    }
  }
  // Fewer B rows than k: every B row, no padding.
  EXPECT_EQ(matcher.match(a, b.rowRange(0, 2), 3)[0].size(), 2u);
  EXPECT_THROW(matcher.match(a, b, 9), Error);
}

TEST(HammingMatcher, MatchesSeveralPairsAtOnceAsOneByOne) {
  cv::Mat a(200, 32, CV_8U), b(350, 32, CV_8U), c(40, 32, CV_8U);
  cv::randu(a, 0, 256);
  cv::randu(b, 0, 256);
  cv::randu(c, 0, 256);
  for (int i = 0; i < 30; ++i) a.row(i).copyTo(b.row(2 * i));  // exact matches and ties
  const std::vector<std::pair<cv::Mat, cv::Mat>> pairs{
      {a, b}, {c, b.rowRange(100, 102)}, {a.rowRange(0, 0), b}, {c, cv::Mat()}, {b.rowRange(10, 60), a}};
  HammingMatcher matcher(Device::Cpu);
  const auto together = matcher.matchPairs(pairs, 3);
  ASSERT_EQ(together.size(), pairs.size());
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const auto alone = matcher.match(pairs[p].first, pairs[p].second, 3);
    ASSERT_EQ(together[p].size(), alone.size()) << "pair " << p;
    for (std::size_t i = 0; i < alone.size(); ++i) {
      ASSERT_EQ(together[p][i].size(), alone[i].size()) << "pair " << p << " row " << i;
      for (std::size_t j = 0; j < alone[i].size(); ++j) {
        EXPECT_EQ(together[p][i][j].queryIdx, alone[i][j].queryIdx);
        EXPECT_EQ(together[p][i][j].trainIdx, alone[i][j].trainIdx);
        EXPECT_EQ(together[p][i][j].distance, alone[i][j].distance);
      }
    }
  }
  EXPECT_EQ(together[1][0].size(), 2u) << "two B rows give two matches";
  EXPECT_TRUE(together[2].empty());
  EXPECT_EQ(together[3].size(), 40u);
  EXPECT_TRUE(together[3][0].empty()) << "an empty B gives no matches";
}

TEST(OrbQuality, MatchesAdjacentScanFramesAtLeastNearlyAsWellAsOpenCv) {
  const synthetic::SyntheticScan scan(scanOptions());
  const RectifiedGeometry& g = scan.geometry();
  // Pairs of frames 2 apart along the path; the true motion of each feature from its true depth.
  struct Score {
    long matches = 0, inliers = 0;
    double ratio() const { return matches ? double(inliers) / matches : 0; }
  };
  Score ours, opencv;
  OrbParameters parameters;  // the tracker's settings: 2000 features, 2 levels, threshold 10
  OrbExtractor extractor(Device::Cpu, parameters);
  HammingMatcher matcher(Device::Cpu);
  cv::Ptr<cv::ORB> reference = cv::ORB::create(2000, 1.2f, 2, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, 10);
  cv::BFMatcher bf(cv::NORM_HAMMING);
  for (int first : {0, 4}) {
    const auto a = scan.renderFrame(first), b = scan.renderFrame(first + 2);
    const cv::Mat greyA = syntheticGrey(a), greyB = syntheticGrey(b);
    const Eigen::Matrix4d T_b_a = b.T_world_camera.inverse() * a.T_world_camera;
    auto expected = [&](const cv::Point2f& p, cv::Point2f& q) {
      const float z = a.depthMm.at<float>(cvRound(p.y), cvRound(p.x));
      if (!std::isfinite(z)) return false;
      const Eigen::Vector4d X((p.x - g.cxLeftPx) * z / g.focalPx, (p.y - g.cyPx) * z / g.focalPx, z, 1.0);
      const Eigen::Vector4d Y = T_b_a * X;
      q = cv::Point2f(float(g.focalPx * Y.x() / Y.z() + g.cxLeftPx), float(g.focalPx * Y.y() / Y.z() + g.cyPx));
      return true;
    };
    auto score = [&](const std::vector<cv::KeyPoint>& ka, const std::vector<cv::KeyPoint>& kb,
                     const std::vector<std::vector<cv::DMatch>>& matches, Score& s) {
      for (const auto& list : matches) {
        if (list.empty() || list[0].distance > 64) continue;  // the tracker's maxHammingDistance
        cv::Point2f q;
        if (!expected(ka[list[0].queryIdx].pt, q)) continue;
        ++s.matches;
        s.inliers += cv::norm(kb[list[0].trainIdx].pt - q) <= 3.0;
      }
    };
    const OrbFeatures fa = extractor.extract(greyA), fb = extractor.extract(greyB);
    score(toCvKeyPoints(fa, parameters.scaleFactor), toCvKeyPoints(fb, parameters.scaleFactor),
          matcher.match(fa.descriptors, fb.descriptors, 1), ours);
    std::vector<cv::KeyPoint> ka, kb;
    cv::Mat da, db;
    reference->detectAndCompute(greyA, cv::noArray(), ka, da);
    reference->detectAndCompute(greyB, cv::noArray(), kb, db);
    std::vector<std::vector<cv::DMatch>> knn;
    bf.knnMatch(da, db, knn, 1);
    score(ka, kb, knn, opencv);
  }
  std::printf("frame pairs 2 apart: ours %ld/%ld inliers (%.3f), OpenCV ORB %ld/%ld (%.3f)\n", ours.inliers,
              ours.matches, ours.ratio(), opencv.inliers, opencv.matches, opencv.ratio());
  EXPECT_GE(ours.ratio(), 0.8 * opencv.ratio());
  EXPECT_GE(ours.inliers, opencv.inliers / 2) << "and not by matching only a few features";
}

TEST(OrbDescriptor, RowsAreSelectedInTheGivenOrder) {
  cv::Mat descriptors(5, 32, CV_8U);
  cv::randu(descriptors, 0, 256);
  const cv::Mat selected = descriptorRows(descriptors, {4, 0, 4});
  ASSERT_EQ(selected.rows, 3);
  ASSERT_EQ(selected.cols, 32);
  ASSERT_EQ(selected.type(), CV_8U);
  EXPECT_EQ(cv::norm(selected.row(0), descriptors.row(4), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(selected.row(1), descriptors.row(0), cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(selected.row(2), descriptors.row(4), cv::NORM_INF), 0.0);
  EXPECT_EQ(descriptorRows(descriptors, {}).rows, 0);
  EXPECT_THROW(descriptorRows(descriptors, {5}), Error);
  EXPECT_THROW(descriptorRows(descriptors, {-1}), Error);
}

TEST(OrbExtractorApi, RejectsBadInput) {
  OrbExtractor extractor(Device::Cpu);
  EXPECT_THROW(extractor.extract(cv::Mat()), Error);
  EXPECT_THROW(extractor.extract(cv::Mat(100, 100, CV_8UC3)), Error);
  EXPECT_THROW(extractor.extract(cv::Mat(30, 30, CV_8U, cv::Scalar(0))), Error);
  OrbParameters bad;
  bad.maxPerCell = 9;
  EXPECT_THROW(OrbExtractor(Device::Cpu, bad), Error);
  bad = OrbParameters{};
  bad.edgeThresholdPx = 10;
  EXPECT_THROW(OrbExtractor(Device::Cpu, bad), Error);
}
