// Point-based TSDF fusion (paper III.E) and the surface measurement it reads, on the CPU, against analytic truth:
// measureSurface reproduces disparityToPointCloud and the analytic normals of a tilted plane; repeated noisy
// observations average out (RMSE ~ 1/sqrt(N)); revisits from the same, a shifted, a nearer, a farther and a tilted
// pose add no second layer while a newly seen area is appended; the image centre's colour outweighs the edge's; the
// point budget holds; sampleVisible keeps the nearest, camera-facing points; and a synthetic scan fuses to well
// below half a millimetre.
#include "FusionTestScene.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "Fusion/PointFusion.h"

#include <gtest/gtest.h>

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>

using namespace tissuemosaic;
using test::cameraPose;
using test::fusionGeometry;
using test::PlanePatch;

namespace {

Eigen::Vector3d toEigen(const cv::Point3f& p) { return {p.x, p.y, p.z}; }

/// Root mean square of the model points' distances to the plane, and the largest distance.
double planeRmseMm(const ModelPoints& model, const PlanePatch& plane, double* maxAbsMm = nullptr) {
  double sum = 0, largest = 0;
  for (const cv::Point3f& p : model.cloud.pointsMm) {
    const double d = plane.distanceMm(toEigen(p));
    sum += d * d;
    largest = std::max(largest, std::abs(d));
  }
  if (maxAbsMm) *maxAbsMm = largest;
  return model.size() ? std::sqrt(sum / model.size()) : 0;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

// ---- measureSurface -----------------------------------------------------------------------------------------------

TEST(SurfaceMeasurement, PointsEqualDisparityToPointCloud) {
  // doffs -8: disparities at or below 8 px put the point at or behind the camera and must be skipped.
  const RectifiedGeometry g = fusionGeometry(97, 61, 250, -8);
  cv::Mat disparity(g.imageSize, CV_32F);
  cv::RNG rng(7);
  rng.fill(disparity, cv::RNG::UNIFORM, -5.0, 60.0);
  for (int i = 0; i < static_cast<int>(disparity.total() / 10); ++i)
    disparity.at<float>(rng.uniform(0, g.imageSize.height), rng.uniform(0, g.imageSize.width)) = NAN;
  cv::Mat left(g.imageSize, CV_8UC3);
  rng.fill(left, cv::RNG::UNIFORM, 0, 256);

  const SurfaceMeasurement m = measureSurface(disparity, left, g, Device::Cpu);
  const ColoredPointCloud cloud = disparityToPointCloud(disparity, left, g);
  const cv::Mat depth = disparityToDepthMm(disparity, g);
  std::size_t next = 0, mismatches = 0;
  for (int y = 0; y < g.imageSize.height; ++y)
    for (int x = 0; x < g.imageSize.width; ++x) {
      const cv::Vec3f p = m.pointsCameraMm.at<cv::Vec3f>(y, x);
      const float z = depth.at<float>(y, x);
      if (std::isnan(p[0])) {
        mismatches += !std::isnan(z);
        continue;
      }
      ASSERT_LT(next, cloud.size());
      const cv::Point3f& q = cloud.pointsMm[next++];
      mismatches += !sameBits(p[0], q.x) || !sameBits(p[1], q.y) || !sameBits(p[2], q.z) || !sameBits(p[2], z);
    }
  EXPECT_EQ(next, cloud.size());
  EXPECT_EQ(mismatches, 0u);
  EXPECT_GT(cloud.size(), disparity.total() / 2);  // both kinds of pixel occur
  EXPECT_LT(cloud.size(), disparity.total() * 9 / 10);
  EXPECT_EQ(cv::norm(m.colourBgr, left, cv::NORM_INF), 0);

  // Grey input gives a grey BGR colour image.
  cv::Mat grey;
  cv::cvtColor(left, grey, cv::COLOR_BGR2GRAY);
  const SurfaceMeasurement fromGrey = measureSurface(disparity, grey, g, Device::Cpu);
  ASSERT_EQ(fromGrey.colourBgr.type(), CV_8UC3);
  EXPECT_EQ(fromGrey.colourBgr.at<cv::Vec3b>(5, 9), cv::Vec3b(grey.at<uchar>(5, 9), grey.at<uchar>(5, 9), grey.at<uchar>(5, 9)));

  EXPECT_THROW(measureSurface(disparity(cv::Rect(0, 0, 50, 50)).clone(), left, g, Device::Cpu), Error);
  EXPECT_THROW(measureSurface(disparity, left(cv::Rect(0, 0, 50, 50)).clone(), g, Device::Cpu), Error);
}

// The mask that lets refinement pick ICP pixels without the maps themselves (they may stay on the device).
TEST(SurfaceMeasurement, ValidMaskMarksThePixelsWithAPointAndANormal) {
  const RectifiedGeometry g = fusionGeometry(97, 61, 250, -8);
  cv::Mat disparity(g.imageSize, CV_32F);
  cv::RNG rng(11);
  rng.fill(disparity, cv::RNG::UNIFORM, 20.0, 24.0);
  for (int i = 0; i < static_cast<int>(disparity.total() / 10); ++i)
    disparity.at<float>(rng.uniform(0, g.imageSize.height), rng.uniform(0, g.imageSize.width)) = NAN;
  SurfaceMeasurement m = measureSurface(disparity, test::uniformImage(g), g, Device::Cpu, 1, 50.0);
  ASSERT_EQ(m.validMask.type(), CV_8U);
  EXPECT_FALSE(m.onDevice) << "measured on the CPU";
  long mismatches = 0, valid = 0;
  for (int y = 0; y < g.imageSize.height; ++y)
    for (int x = 0; x < g.imageSize.width; ++x) {
      const cv::Vec3f p = m.pointsCameraMm.at<cv::Vec3f>(y, x), n = m.normalsCamera.at<cv::Vec3f>(y, x);
      const bool both = std::isfinite(p[0]) && std::isfinite(p[2]) && std::isfinite(n[0]) && std::isfinite(n[2]);
      mismatches += both != (m.validMask.at<uchar>(y, x) == 255);
      valid += both;
    }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(m.validPixels, valid);
  EXPECT_GT(valid, static_cast<long>(disparity.total() / 4));  // both kinds of pixel occur
  EXPECT_LT(valid, static_cast<long>(disparity.total()));
  // A measurement assembled without a mask gets the same one from its maps.
  const cv::Mat fromMask = m.validPixelMask();
  m.validMask.release();
  EXPECT_EQ(cv::norm(m.validPixelMask(), fromMask, cv::NORM_INF), 0);
}

// A kept disparity range (the pipeline's working depth range) measures exactly what the disparity with the others
// set to NaN measures: the same points, normals and mask, bit for bit; the bounds themselves are kept.
TEST(SurfaceMeasurement, AMapWhereItWasComputedGivesTheSameSurfaceAndTheColourIsShared) {
  // The pipeline measures a key frame's surface from the stereo matcher's own map (no copy); a continuous BGR image
  // is shared, not copied; a grey or non-continuous one is converted or copied.
  const RectifiedGeometry g = fusionGeometry(97, 61, 250, -8);
  cv::Mat disparity(g.imageSize, CV_32F);  // a slanted plane with noise and holes
  cv::RNG rng(8);
  rng.fill(disparity, cv::RNG::UNIFORM, -0.2, 0.2);
  for (int y = 0; y < disparity.rows; ++y)
    for (int x = 0; x < disparity.cols; ++x) disparity.at<float>(y, x) += 30.0f + 0.05f * x + 0.03f * y;
  for (int i = 0; i < 200; ++i) disparity.at<float>(rng.uniform(0, disparity.rows), rng.uniform(0, disparity.cols)) = NAN;
  cv::Mat left(g.imageSize, CV_8UC3);
  rng.fill(left, cv::RNG::UNIFORM, 0, 256);
  const SurfaceMeasurement fromMat = measureSurface(disparity, left, g, Device::Cpu, 1, 50.0);
  const ImageView<const float> view{disparity.ptr<float>(), disparity.cols, disparity.rows};
  const SurfaceMeasurement fromView = measureSurface(view, left, g, Device::Cpu, 1, 50.0);
  EXPECT_GT(fromMat.validPixels, static_cast<int>(disparity.total() / 2));
  EXPECT_EQ(fromView.validPixels, fromMat.validPixels);
  const auto sameMap = [](const cv::Mat& a, const cv::Mat& b) {  // bit for bit, NaN (no estimate) included
    return a.size() == b.size() && a.type() == b.type() && std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0;
  };
  EXPECT_TRUE(sameMap(fromView.pointsCameraMm, fromMat.pointsCameraMm));
  EXPECT_TRUE(sameMap(fromView.normalsCamera, fromMat.normalsCamera));
  EXPECT_EQ(fromView.colourBgr.data, left.data) << "a continuous BGR image is shared";
  const cv::Mat wider(g.imageSize.height, g.imageSize.width + 3, CV_8UC3, cv::Scalar(1, 2, 3));
  const cv::Mat part = wider(cv::Rect(0, 0, g.imageSize.width, g.imageSize.height));
  const SurfaceMeasurement fromPart = measureSurface(view, part, g, Device::Cpu, 1, 50.0);
  EXPECT_TRUE(fromPart.colourBgr.isContinuous());
  EXPECT_NE(fromPart.colourBgr.data, part.data);
  EXPECT_EQ(cv::norm(fromPart.colourBgr, part, cv::NORM_INF), 0);
  EXPECT_THROW(measureSurface(ImageView<const float>{}, left, g, Device::Cpu), Error);
  EXPECT_THROW(measureSurface(ImageView<const float>{disparity.ptr<float>(), 20, 20}, left, g, Device::Cpu), Error);
}

TEST(SurfaceMeasurement, KeptRangeEqualsMissingDisparitiesOutsideIt) {
  const RectifiedGeometry g = fusionGeometry(97, 61, 250, -8);
  cv::Mat disparity(g.imageSize, CV_32F);
  cv::RNG rng(12);
  rng.fill(disparity, cv::RNG::UNIFORM, 18.0, 26.0);
  DisparityRangePx kept;
  kept.lowestPx = 20.0f;
  kept.highestPx = 24.0f;
  disparity.at<float>(3, 3) = kept.lowestPx;
  disparity.at<float>(4, 4) = kept.highestPx;
  cv::Mat masked = disparity.clone();
  int outside = 0;
  for (float& d : cv::Mat_<float>(masked)) {
    if (!(d >= kept.lowestPx && d <= kept.highestPx)) {
      d = NAN;
      ++outside;
    }
  }
  ASSERT_GT(outside, static_cast<int>(disparity.total() / 4));
  const SurfaceMeasurement ranged =
      measureSurface(disparity, test::uniformImage(g), g, Device::Cpu, 1, 50.0, SurfaceMapResidence::HostAndDevice, kept);
  const SurfaceMeasurement reference = measureSurface(masked, test::uniformImage(g), g, Device::Cpu, 1, 50.0);
  EXPECT_EQ(ranged.validPixels, reference.validPixels);
  EXPECT_EQ(cv::norm(ranged.validMask, reference.validMask, cv::NORM_INF), 0);
  EXPECT_TRUE(std::isfinite(ranged.pointsCameraMm.at<cv::Vec3f>(3, 3)[2])) << "the lowest bound is kept";
  EXPECT_TRUE(std::isfinite(ranged.pointsCameraMm.at<cv::Vec3f>(4, 4)[2])) << "the highest bound is kept";
  for (int y = 0; y < g.imageSize.height; ++y)
    for (int x = 0; x < g.imageSize.width; ++x) {
      const cv::Vec3f a = ranged.pointsCameraMm.at<cv::Vec3f>(y, x), b = reference.pointsCameraMm.at<cv::Vec3f>(y, x);
      const cv::Vec3f na = ranged.normalsCamera.at<cv::Vec3f>(y, x), nb = reference.normalsCamera.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(a[c] == b[c] || (std::isnan(a[c]) && std::isnan(b[c]))) << "point at " << x << "," << y;
        ASSERT_TRUE(na[c] == nb[c] || (std::isnan(na[c]) && std::isnan(nb[c]))) << "normal at " << x << "," << y;
      }
    }
}

TEST(SurfaceMeasurement, NormalsOfATiltedPlaneMatchTheAnalyticNormal) {
  const RectifiedGeometry g = fusionGeometry();
  PlanePatch plane;
  plane.normal = Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 0.6, 0).normalized()) * Eigen::Vector3d::UnitZ();
  plane.offsetMm = 90;
  const Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  const SurfaceMeasurement m = test::patchMeasurement(g, plane, T);
  const Eigen::Vector3d truth = -plane.normal.normalized();  // toward the camera at the origin
  double worstDeg = 0;
  int valid = 0;
  for (int y = 0; y < g.imageSize.height; ++y)
    for (int x = 0; x < g.imageSize.width; ++x) {
      const cv::Vec3f n = m.normalsCamera.at<cv::Vec3f>(y, x);
      const bool interior = x >= 2 && y >= 2 && x < g.imageSize.width - 2 && y < g.imageSize.height - 2;
      if (!interior) {
        EXPECT_TRUE(std::isnan(n[0])) << x << "," << y;  // a neighbour 2 px away is outside the image
        continue;
      }
      ASSERT_FALSE(std::isnan(n[0])) << x << "," << y;
      ++valid;
      const double c = std::min(1.0, Eigen::Vector3d(n[0], n[1], n[2]).dot(truth));
      worstDeg = std::max(worstDeg, std::acos(c) * 180 / M_PI);
    }
  std::printf("tilted plane (%.1f deg): worst normal error %.4f deg over %d pixels\n",
              std::acos(truth.z() * -1) * 180 / M_PI, worstDeg, valid);
  EXPECT_LT(worstDeg, 0.05);
  EXPECT_EQ(m.validPixels, valid);

  // A 10 mm depth step: no normal within the radius of the step, normals elsewhere.
  cv::Mat disparity = test::patchDisparity(g, PlanePatch{}, T);
  const float farDisparity = static_cast<float>(g.focalPx * g.baselineMm / 110.0);
  disparity(cv::Rect(160, 0, 160, g.imageSize.height)).setTo(farDisparity);
  const SurfaceMeasurement step = measureSurface(disparity, test::uniformImage(g), g, Device::Cpu, 2, 2.0);
  for (int x = 150; x < 170; ++x) {
    const bool nearStep = x >= 158 && x <= 161;
    EXPECT_EQ(std::isnan(step.normalsCamera.at<cv::Vec3f>(100, x)[0]), nearStep) << "column " << x;
  }
}

// ---- fusion -------------------------------------------------------------------------------------------------------

TEST(PointFusion, RepeatedObservationsReduceNoise) {
  const RectifiedGeometry g = fusionGeometry();
  PlanePatch plane;
  plane.normal = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ();
  plane.halfXMm = 30;
  plane.halfYMm = 22;
  const double noiseMm = 0.3;
  cv::RNG rng(11);
  PointFusion fusion(g, FusionParameters{}, Device::Cpu);
  std::vector<double> rmse;
  for (int k = 0; k < 8; ++k) {
    // Small pose jitter (up to 1.5 mm, 1.5 degrees): model points no longer fall on pixel centres.
    const Eigen::Matrix4d T = cameraPose(Eigen::Vector3d(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5)),
                                         Eigen::Vector3d(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.3),
                                         rng.uniform(-1.5, 1.5));
    const FusionStats stats = fusion.integrate(test::patchMeasurement(g, plane, T, noiseMm, &rng), T);
    rmse.push_back(planeRmseMm(fusion.download(), plane));
    std::printf("observation %d: %d merged, %d added, %zu points, RMSE %.4f mm, %.1f ms\n", k + 1, stats.merged,
                stats.added, fusion.pointCount(), rmse.back(), stats.milliseconds);
  }
  // One observation: the depth noise seen along the plane's normal (tilted 0.35 rad from the optical axis).
  EXPECT_NEAR(rmse[0], noiseMm * std::cos(0.35), 0.05 * noiseMm);
  EXPECT_LT(rmse[3], 0.65 * rmse[0]);             // 1/sqrt(4) = 0.5 in theory
  EXPECT_LT(rmse[7], 0.5 * rmse[0]);              // 1/sqrt(8) = 0.35 in theory
  EXPECT_LT(rmse[7], 0.15);
  // Weights count the observations.
  const ModelPoints model = fusion.download();
  int seenEveryTime = 0;
  for (float w : model.weights) seenEveryTime += w == 8.0f;
  EXPECT_GT(seenEveryTime, static_cast<int>(0.8 * model.size()));
}

TEST(PointFusion, RevisitsAddNoDuplicateLayers) {
  const RectifiedGeometry g = fusionGeometry();
  PlanePatch patch;  // seen whole from every pose below
  patch.normal = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ();
  patch.halfXMm = 28;
  patch.halfYMm = 18;
  cv::RNG rng(3);
  const FusionParameters parameters;
  PointFusion fusion(g, parameters, Device::Cpu);
  const double noiseMm = 0.2;
  const Eigen::Matrix4d first = Eigen::Matrix4d::Identity();
  fusion.integrate(test::patchMeasurement(g, patch, first, noiseMm, &rng), first);
  const std::size_t initial = fusion.pointCount();
  ASSERT_GT(initial, 15000u);

  struct Visit {
    const char* name;
    Eigen::Matrix4d T;
  };
  const Visit visits[] = {
      {"same pose", first},
      {"shifted 6 mm", cameraPose(Eigen::Vector3d(6, -4, 0))},
      {"30 mm nearer", cameraPose(Eigen::Vector3d(0, 0, 30))},
      {"30 mm farther", cameraPose(Eigen::Vector3d(0, 0, -30))},
      {"tilted 15 deg", cameraPose(Eigen::Vector3d(-25, 0, 5), Eigen::Vector3d::UnitY(), 15)},
      {"nearer and rolled", cameraPose(Eigen::Vector3d(3, 2, 20), Eigen::Vector3d(0.2, 0.1, 1), 25)},
  };
  for (const Visit& visit : visits) {
    const std::size_t before = fusion.pointCount();
    const SurfaceMeasurement m = test::patchMeasurement(g, patch, visit.T, noiseMm, &rng);
    const FusionStats stats = fusion.integrate(m, visit.T);
    double maxAbs = 0;
    const double rmse = planeRmseMm(fusion.download(), patch, &maxAbs);
    std::printf("%-18s: %6d measured, %6d merged, %4d added (%.2f%% of the model), RMSE %.4f mm, max %.3f mm\n",
                visit.name, m.validPixels, stats.merged, stats.added, 100.0 * stats.added / before, rmse, maxAbs);
    EXPECT_LE(stats.added, 0.02 * before) << visit.name;
    EXPECT_EQ(fusion.pointCount(), before + stats.added);
    EXPECT_LE(maxAbs, parameters.truncationMm) << visit.name;
    EXPECT_LT(rmse, noiseMm) << visit.name;
  }
  EXPECT_LE(fusion.pointCount(), initial * 1.05);
}

namespace {

/// Fuses `visits` views of a plane from nearby poses, each with 30 fresh 8 x 8 px blobs (about 2.5 % of the pixels)
/// moved 6 mm off the plane (the gross errors stereo makes on specular or weakly textured patches); returns the model.
ModelPoints fuseRevisitsWithOutliers(int conflictMinWeight, int visits, std::size_t* firstVisitPoints) {
  const RectifiedGeometry g = fusionGeometry();
  PlanePatch patch;
  patch.halfXMm = 28;
  patch.halfYMm = 18;
  FusionParameters parameters;
  parameters.conflictMinWeight = conflictMinWeight;
  // The outliers lie in front of the plane, which the scene-motion handling's occluder rule refuses as well: off, so
  // that the test shows the conflict guard alone.
  parameters.motionPenalty = 0;
  PointFusion fusion(g, parameters, Device::Cpu);
  cv::RNG rng(11);
  for (int visit = 0; visit < visits; ++visit) {
    const Eigen::Matrix4d T = cameraPose(Eigen::Vector3d(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0), 0));
    cv::Mat disparity = test::patchDisparity(g, patch, T, 0.1, &rng);
    // Outliers come in blobs (a highlight, a weakly textured patch), smooth enough to have normals.
    for (int blob = 0; blob < 30; ++blob) {
      const int x0 = rng.uniform(0, disparity.cols - 8), y0 = rng.uniform(0, disparity.rows - 8);
      for (int y = y0; y < y0 + 8; ++y) {
        for (int x = x0; x < x0 + 8; ++x) {
          float& d = disparity.at<float>(y, x);
          if (std::isfinite(d)) d = static_cast<float>(g.focalPx * g.baselineMm / (g.depthMm(d) - 6.0) - g.doffsPx);
        }
      }
    }
    fusion.integrate(measureSurface(disparity, test::uniformImage(g, cv::Scalar(90, 120, 200)), g, Device::Cpu), T);
    if (visit == 0 && firstVisitPoints) *firstVisitPoints = fusion.pointCount();
  }
  return fusion.download();
}

double shareFartherThan(const ModelPoints& model, double mm) {
  PlanePatch patch;
  std::size_t far = 0;
  for (const cv::Point3f& p : model.cloud.pointsMm) far += std::abs(patch.distanceMm(toEigen(p))) > mm;
  return model.size() ? static_cast<double>(far) / model.size() : 0;
}

}  // namespace

TEST(PointFusion, RevisitsDoNotPileUpStereoOutliers) {
  std::size_t first = 0;
  const ModelPoints guarded = fuseRevisitsWithOutliers(FusionParameters{}.conflictMinWeight, 40, &first);
  const ModelPoints unguarded = fuseRevisitsWithOutliers(0, 40, nullptr);
  const double guardedShare = shareFartherThan(guarded, 1.0), unguardedShare = shareFartherThan(unguarded, 1.0);
  std::printf("40 visits with 2.5%% outliers each: %zu points after the first, %zu guarded (%.2f%% off the plane), "
              "%zu unguarded (%.2f%% off)\n", first, guarded.size(), 100 * guardedShare, unguarded.size(),
              100 * unguardedShare);
  EXPECT_LT(guarded.size(), 1.1 * first);
  EXPECT_LT(guardedShare, 0.03);
  EXPECT_GT(unguardedShare, 2 * guardedShare) << "the test must show what the guard prevents";
}

TEST(PointFusion, AppendsANewlySeenArea) {
  const RectifiedGeometry g = fusionGeometry();
  const PlanePatch plane;  // unlimited, Z = 100
  PointFusion fusion(g, FusionParameters{}, Device::Cpu);
  const Eigen::Matrix4d a = Eigen::Matrix4d::Identity(), b = cameraPose(Eigen::Vector3d(30, 0, 0));
  fusion.integrate(test::patchMeasurement(g, plane, a), a);
  const ModelPoints before = fusion.download();
  double seenUpToXMm = -1e9;
  for (const cv::Point3f& p : before.cloud.pointsMm) seenUpToXMm = std::max<double>(seenUpToXMm, p.x);

  // Pixels of the second view with a complete measurement beyond what the first view saw.
  const SurfaceMeasurement m = test::patchMeasurement(g, plane, b);
  int expectedNew = 0, expectedOld = 0;
  for (int y = 0; y < g.imageSize.height; ++y)
    for (int x = 0; x < g.imageSize.width; ++x) {
      const cv::Vec3f n = m.normalsCamera.at<cv::Vec3f>(y, x);
      if (std::isnan(n[0])) continue;
      const double worldX = m.pointsCameraMm.at<cv::Vec3f>(y, x)[0] + 30.0;
      (worldX > seenUpToXMm ? expectedNew : expectedOld) += 1;
    }
  const FusionStats stats = fusion.integrate(m, b);
  std::printf("new area: %d added (%d pixels beyond the first view), %d merged (%d pixels over it)\n", stats.added,
              expectedNew, stats.merged, expectedOld);
  // Up to one column of pixels next to the old area counts as covered (coverage radius 1 px).
  EXPECT_LE(stats.added, expectedNew);
  EXPECT_GE(stats.added, expectedNew - 2 * g.imageSize.height);
  EXPECT_NEAR(stats.merged, expectedOld, 0.01 * expectedOld);
  const ModelPoints after = fusion.download();
  double maxAbs = 0;
  planeRmseMm(after, plane, &maxAbs);
  EXPECT_LT(maxAbs, 1e-3);  // noise-free: every point on the plane
}

TEST(PointFusion, ColourFromTheImageCentreOutweighsTheEdge) {
  const RectifiedGeometry g = fusionGeometry();
  const PlanePatch plane;  // Z = 100
  // From `edge` the world point (0, 0, 100) projects near the top-left corner, pixel (10, 10).
  const Eigen::Matrix4d centre = Eigen::Matrix4d::Identity();
  const Eigen::Matrix4d edge =
      cameraPose(Eigen::Vector3d(-(g.cxLeftPx - 10) / g.focalPx * 100, -(g.cyPx - 10) / g.focalPx * 100, 0));
  const cv::Scalar red(40, 40, 220), blue(220, 40, 40);  // BGR

  // Mean red level of the model points within 1 mm of (0, 0, 100).
  const auto redAtTarget = [](const ModelPoints& model) {
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < model.size(); ++i) {
      const cv::Point3f& p = model.cloud.pointsMm[i];
      if (std::hypot(p.x, p.y) < 1.0) {
        sum += model.cloud.colorsRgb[i][0];
        ++n;
      }
    }
    EXPECT_GT(n, 20);
    return sum / std::max(1, n);
  };
  const auto fuse = [&](const FusionParameters& parameters, bool centreFirst) {
    PointFusion fusion(g, parameters, Device::Cpu);
    if (centreFirst) {
      fusion.integrate(test::patchMeasurement(g, plane, centre, 0, nullptr, red), centre);
      fusion.integrate(test::patchMeasurement(g, plane, edge, 0, nullptr, blue), edge);
    } else {
      fusion.integrate(test::patchMeasurement(g, plane, edge, 0, nullptr, blue), edge);
      fusion.integrate(test::patchMeasurement(g, plane, centre, 0, nullptr, red), centre);
    }
    return redAtTarget(fusion.download());
  };
  const FusionParameters weighted;
  FusionParameters uniform;
  uniform.colourMinWeight = 1.0;
  const double centreThenEdge = fuse(weighted, true), edgeThenCentre = fuse(weighted, false);
  const double uniformWeights = fuse(uniform, true);
  std::printf("red level at the target (centre 220, edge 40): centre then edge %.1f, edge then centre %.1f, "
              "uniform weights %.1f\n", centreThenEdge, edgeThenCentre, uniformWeights);
  EXPECT_GT(centreThenEdge, 220 - 0.25 * 180);
  EXPECT_GT(edgeThenCentre, 220 - 0.25 * 180);
  EXPECT_NEAR(uniformWeights, 130, 2);  // equal weights: the plain average
}

TEST(PointFusion, StopsAtThePointBudget) {
  const RectifiedGeometry g = fusionGeometry();
  FusionParameters parameters;
  parameters.maxPoints = 12345;
  PointFusion fusion(g, parameters, Device::Cpu);
  const PlanePatch plane;
  const Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
  const SurfaceMeasurement m = test::patchMeasurement(g, plane, a);
  FusionStats stats = fusion.integrate(m, a);
  EXPECT_EQ(stats.added, 12345);
  EXPECT_EQ(stats.refusedForBudget, m.validPixels - 12345);
  EXPECT_TRUE(fusion.budgetReached());
  EXPECT_EQ(fusion.pointCount(), 12345u);
  // New area: everything refused; the old points still merge.
  const Eigen::Matrix4d b = cameraPose(Eigen::Vector3d(20, 10, 0));
  stats = fusion.integrate(test::patchMeasurement(g, plane, b), b);
  EXPECT_EQ(stats.added, 0);
  EXPECT_GT(stats.refusedForBudget, 10000);
  EXPECT_GT(stats.merged, 2000);
  EXPECT_EQ(fusion.pointCount(), 12345u);
  EXPECT_EQ(fusion.download().size(), 12345u);

  // Below the budget nothing is refused; reset() empties the model and clears the flag.
  fusion.reset();
  EXPECT_EQ(fusion.pointCount(), 0u);
  EXPECT_FALSE(fusion.budgetReached());
  PlanePatch small;
  small.halfXMm = 10;
  small.halfYMm = 10;
  stats = fusion.integrate(test::patchMeasurement(g, small, a), a);
  EXPECT_EQ(stats.refusedForBudget, 0);
  EXPECT_FALSE(fusion.budgetReached());
  EXPECT_EQ(fusion.deviceBytes(), 0u);  // CPU
}

TEST(PointFusion, SampleVisibleKeepsTheNearestCameraFacingPoints) {
  const RectifiedGeometry g = fusionGeometry();
  // A surface appearing 20 mm in front of fused tissue is what the scene-motion handling refuses to fuse (an
  // instrument; FusionParameters::occlusionMarginMm): with it on, the front patch adds nothing.
  PlanePatch front, back;
  front.offsetMm = 100;
  front.halfXMm = 15;
  front.halfYMm = 15;
  back.offsetMm = 120;
  const Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  {
    PointFusion refusing(g, FusionParameters{}, Device::Cpu);
    refusing.integrate(test::patchMeasurement(g, back, T), T);
    const std::size_t background = refusing.pointCount();
    EXPECT_EQ(refusing.integrate(test::patchMeasurement(g, front, T), T).added, 0);
    EXPECT_EQ(refusing.pointCount(), background);
  }
  FusionParameters withoutMotionHandling;
  withoutMotionHandling.motionPenalty = 0;
  PointFusion fusion(g, withoutMotionHandling, Device::Cpu);
  fusion.integrate(test::patchMeasurement(g, back, T), T);  // the whole background first
  // Then the front patch alone, 20 mm nearer: far beyond the truncation, so its points are new and the background
  // behind it stays in the model.
  fusion.integrate(test::patchMeasurement(g, front, T), T);
  ASSERT_GT(fusion.pointCount(), 76000u);

  std::vector<Eigen::Vector3f> points, normals;
  fusion.sampleVisible(T, 2000, points, normals);
  ASSERT_EQ(points.size(), normals.size());
  std::printf("sampleVisible: %zu of at most 2000 samples\n", points.size());
  EXPECT_LE(points.size(), 2000u);
  EXPECT_GT(points.size(), 1000u);
  int occluded = 0, onFront = 0;
  double minX = 1e9, maxX = -1e9, minY = 1e9, maxY = -1e9;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    // The front patch's shadow on the background is |X|, |Y| < 18 mm (15 * 120 / 100).
    const bool behindFront = std::abs(p.x()) < 17 && std::abs(p.y()) < 17 && p.z() > 110;
    occluded += behindFront;
    onFront += p.z() < 110;
    EXPECT_NEAR(normals[i].z(), -1.0f, 1e-3);
    const double u = g.focalPx * p.x() / p.z() + g.cxLeftPx, v = g.focalPx * p.y() / p.z() + g.cyPx;
    minX = std::min(minX, u), maxX = std::max(maxX, u), minY = std::min(minY, v), maxY = std::max(maxY, v);
  }
  EXPECT_EQ(occluded, 0);  // background points behind the front patch lose the z-buffer
  // The front patch covers (30 * 300 / 100)^2 = 8100 of 76800 pixels: about a tenth of the samples.
  EXPECT_NEAR(onFront, 0.105 * points.size(), 0.03 * points.size());
  EXPECT_LT(minX, 10);  // spread over the whole image
  EXPECT_GT(maxX, g.imageSize.width - 10);
  EXPECT_LT(minY, 10);
  EXPECT_GT(maxY, g.imageSize.height - 10);

  // From behind, every point faces away: nothing is visible.
  fusion.sampleVisible(cameraPose(Eigen::Vector3d(0, 0, 250), Eigen::Vector3d::UnitY(), 180), 2000, points, normals);
  EXPECT_TRUE(points.empty());
  // Few requested: few returned.
  fusion.sampleVisible(T, 50, points, normals);
  EXPECT_LE(points.size(), 50u);
  EXPECT_GT(points.size(), 25u);
}

TEST(PointFusion, FusesASyntheticScanWellBelowHalfAMillimetre) {
  synthetic::SyntheticScanOptions options;
  options.width = 480;
  options.height = 270;
  options.frames = 90;
  options.seed = 21;
  const synthetic::SyntheticScan scan(options);
  const RectifiedGeometry& g = scan.geometry();
  const FusionParameters parameters;
  PointFusion fusion(g, parameters, Device::Cpu);
  cv::RNG rng(5);
  // Disparity noise of 0.1 px per pixel: 0.26 mm of depth at 80 mm with this 500 px focal length, 0.4 mm at 100 mm.
  const double noisePx = 0.1;
  const auto surfaceRmse = [&](const ModelPoints& model, double* maxAbs) {
    double sum = 0, largest = 0;
    for (std::size_t i = 0; i < model.size(); ++i) {
      const cv::Point3f& p = model.cloud.pointsMm[i];
      const cv::Vec3d n = scan.surface().normal(p.x, p.y);
      const double d = (p.z - scan.surface().heightMm(p.x, p.y)) * std::abs(n[2]);  // ~ orthogonal distance
      sum += d * d;
      largest = std::max(largest, std::abs(d));
    }
    *maxAbs = largest;
    return std::sqrt(sum / model.size());
  };
  double singleFrameRmse = 0, rmse = 0, maxAbs = 0;
  for (int index = 0; index < options.frames; index += 6) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(index);
    cv::Mat disparity = frame.disparityPx.clone(), noise(disparity.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, noisePx);
    disparity += noise;
    const SurfaceMeasurement m =
        measureSurface(disparity, frame.leftRectified, g, Device::Cpu, parameters.normalRadiusPx, parameters.maxDepthJumpMm);
    const FusionStats stats = fusion.integrate(m, frame.T_world_camera);
    rmse = surfaceRmse(fusion.download(), &maxAbs);
    if (index == 0) singleFrameRmse = rmse;
    std::printf("frame %3d: %6d merged %6d added, %7zu points, RMSE %.3f mm (max %.2f), %.1f ms\n", index, stats.merged,
                stats.added, fusion.pointCount(), rmse, maxAbs, stats.milliseconds);
  }
  // Requirement: < 0.25 mm, and fusion must beat a single frame; regression: within twice the 0.148 mm measured
  // when the bound was set (2026-11-25).
  EXPECT_LT(rmse, 0.25);
  EXPECT_LT(rmse, 2 * 0.148);
  EXPECT_LT(rmse, 0.8 * singleFrameRmse);
}

// ---- parameters and errors ----------------------------------------------------------------------------------------

TEST(FusionParameters, RoundTripAndValidation) {
  FusionParameters p;
  p.truncationMm = 2.5;
  p.maxWeight = 30;
  p.coverageRadiusPx = 2;
  p.colourMinWeight = 0.2;
  p.maxPoints = 1234567;
  p.newPointStepPx = 2;
  p.normalRadiusPx = 3;
  p.conflictMinWeight = 5;
  cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  p.write(out);
  const std::string text = out.releaseAndGetString();
  cv::FileStorage in(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  const FusionParameters q = FusionParameters::read(in["fusion"]);
  EXPECT_EQ(q.truncationMm, 2.5);
  EXPECT_EQ(q.maxWeight, 30);
  EXPECT_EQ(q.coverageRadiusPx, 2);
  EXPECT_EQ(q.colourMinWeight, 0.2);
  EXPECT_EQ(q.maxPoints, 1234567);
  EXPECT_EQ(q.newPointStepPx, 2);
  EXPECT_EQ(q.normalRadiusPx, 3);
  EXPECT_EQ(q.conflictMinWeight, 5);
  EXPECT_EQ(q.maxDepthJumpMm, p.maxDepthJumpMm);
  EXPECT_NO_THROW(FusionParameters{}.validate());
  EXPECT_EQ(FusionParameters::read(cv::FileNode()).truncationMm, FusionParameters{}.truncationMm);

  FusionParameters bad;
  bad.truncationMm = 0;
  EXPECT_THROW(bad.validate(), Error);
  bad = FusionParameters{};
  bad.maxPoints = 0;
  EXPECT_THROW(bad.validate(), Error);
  bad = FusionParameters{};
  bad.colourMinWeight = 1.5;
  EXPECT_THROW(bad.validate(), Error);
  bad = FusionParameters{};
  bad.conflictMinWeight = -1;
  EXPECT_THROW(bad.validate(), Error);
  cv::FileStorage wrongType("%YAML:1.0\nfusion:\n  maxPoints: 1.5\n", cv::FileStorage::READ | cv::FileStorage::MEMORY);
  EXPECT_THROW(FusionParameters::read(wrongType["fusion"]), Error);
}

TEST(PointFusion, RejectsBadInput) {
  const RectifiedGeometry g = fusionGeometry();
  PointFusion fusion(g, FusionParameters{}, Device::Cpu);
  const SurfaceMeasurement wrongSize = test::patchMeasurement(fusionGeometry(160, 120), PlanePatch{}, Eigen::Matrix4d::Identity());
  EXPECT_THROW(fusion.integrate(wrongSize, Eigen::Matrix4d::Identity()), Error);
  Eigen::Matrix4d scaled = Eigen::Matrix4d::Identity();
  scaled(0, 0) = 2;
  EXPECT_THROW(fusion.integrate(test::patchMeasurement(g, PlanePatch{}, Eigen::Matrix4d::Identity()), scaled), Error);
  FusionParameters bad;
  bad.maxWeight = 0;
  EXPECT_THROW(PointFusion(g, bad, Device::Cpu), Error);
  if (!cudaAvailable()) {
    EXPECT_THROW(PointFusion(g, FusionParameters{}, Device::Cuda), Error);
  }
}
