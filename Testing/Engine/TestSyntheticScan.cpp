// The synthetic scanning video: deterministic from the seed, a path inside the brief's envelope (60-120 mm from the
// tissue, 3-30 mm/s), and ground truth that agrees with itself: a ground-truth depth pixel back-projected with the
// ground-truth pose lies on the written surface mesh, and the written trajectory is the scan's pose. The written
// surface is what both eyes saw: every kept triangle was inside both views in some frame, and none is missing.
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "IO/DisparityPfm.h"
#include "IO/Calibration/CalibrationFile.h"
#include "IO/MeshPly.h"
#include "IO/TrajectoryTum.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <utility>

using namespace tissuemosaic;
using namespace tissuemosaic::synthetic;

namespace {

SyntheticScanOptions smallScan(uint32_t seed = 7) {
  SyntheticScanOptions options;
  options.width = 240;
  options.height = 136;
  options.frames = 4;
  options.seed = seed;
  return options;
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  return std::memcmp(a.data, b.data, a.total() * a.elemSize()) == 0 || cv::norm(a, b, cv::NORM_INF) == 0;
}

/// Height of the mesh at (x, y): the triangle whose XY projection contains the point, interpolated linearly.
double meshHeightMm(const TriangleMesh& mesh, double x, double y) {
  for (const cv::Vec3i& t : mesh.triangles) {
    const cv::Point3f &a = mesh.verticesMm[t[0]], &b = mesh.verticesMm[t[1]], &c = mesh.verticesMm[t[2]];
    const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    if (std::abs(det) < 1e-12) continue;
    const double l1 = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
    const double l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
    const double l0 = 1 - l1 - l2;
    if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
    return l0 * a.z + l1 * b.z + l2 * c.z;
  }
  return std::nan("");
}

/// Whether both rectified eyes of frame k see the world point at least kSeenBorderPx inside their images, from the
/// ground-truth pose and the rectified geometry alone (the right eye sits baselineMm along the left camera's x).
bool seenByBothEyes(const SyntheticScan& scan, int k, const cv::Point3f& point) {
  const RectifiedGeometry& g = scan.geometry();
  const Eigen::Matrix4d T = scan.T_world_camera(k);
  const Eigen::Vector3d p =
      T.topLeftCorner<3, 3>().transpose() * (Eigen::Vector3d(point.x, point.y, point.z) - T.topRightCorner<3, 1>());
  if (p.z() <= 0) return false;
  const double border = SyntheticScan::kSeenBorderPx;
  const double v = g.focalPx * p.y() / p.z() + g.cyPx;
  const double uLeft = g.focalPx * p.x() / p.z() + g.cxLeftPx;
  const double uRight = g.focalPx * (p.x() - g.baselineMm) / p.z() + g.cxLeftPx + g.doffsPx;
  const auto inside = [&](double x, int size) { return x >= border && x <= size - 1 - border; };
  return inside(v, g.imageSize.height) && inside(uLeft, g.imageSize.width) && inside(uRight, g.imageSize.width);
}

bool seenWhole(const SyntheticScan& scan, int k, const TriangleMesh& mesh, const cv::Vec3i& t) {
  return seenByBothEyes(scan, k, mesh.verticesMm[t[0]]) && seenByBothEyes(scan, k, mesh.verticesMm[t[1]]) &&
         seenByBothEyes(scan, k, mesh.verticesMm[t[2]]);
}

/// A grid triangle's identity across meshes: its centroid (the vertices are the same floats in both).
std::pair<long long, long long> centroidKey(const TriangleMesh& mesh, const cv::Vec3i& t) {
  const cv::Point3f &a = mesh.verticesMm[t[0]], &b = mesh.verticesMm[t[1]], &c = mesh.verticesMm[t[2]];
  return {std::llround((a.x + b.x + c.x) * 1000.0), std::llround((a.y + b.y + c.y) * 1000.0)};
}

}  // namespace

TEST(SyntheticScan, IsDeterministicFromTheSeed) {
  const SyntheticScan a(smallScan()), b(smallScan()), other(smallScan(8));
  const SyntheticScanFrame fa = a.renderFrame(2), fb = b.renderFrame(2), fo = other.renderFrame(2);
  EXPECT_TRUE(identical(fa.leftRectified, fb.leftRectified));
  EXPECT_TRUE(identical(fa.rightRectified, fb.rightRectified));
  EXPECT_TRUE(cv::norm(fa.depthMm, fb.depthMm, cv::NORM_INF, fa.depthMm == fa.depthMm) == 0);
  EXPECT_EQ((fa.T_world_camera - fb.T_world_camera).norm(), 0.0);
  EXPECT_FALSE(identical(fa.leftRectified, fo.leftRectified));
  EXPECT_GT((fa.T_world_camera - fo.T_world_camera).norm(), 1.0);
  // Each frame has its own sensor noise: consecutive frames differ even where the view barely moves.
  EXPECT_FALSE(identical(a.renderFrame(0).leftRectified, fa.leftRectified));
}

TEST(SyntheticScan, PathStaysInsideTheScanningEnvelope) {
  SyntheticScanOptions options = smallScan(3);
  options.frames = 600;  // 20 s: several speed and tilt periods
  const SyntheticScan scan(options);
  double slowest = 1e9, fastest = 0, maxTiltDeg = 0;
  for (int k = 0; k + 1 < scan.frameCount(); ++k) {
    const Eigen::Matrix4d a = scan.T_world_camera(k), b = scan.T_world_camera(k + 1);
    const double speed = (b.block<3, 1>(0, 3) - a.block<3, 1>(0, 3)).norm() * options.fps;
    slowest = std::min(slowest, speed);
    fastest = std::max(fastest, speed);
    const Eigen::Vector3d axis = a.block<3, 3>(0, 0) * Eigen::Vector3d::UnitZ();
    maxTiltDeg = std::max(maxTiltDeg, std::acos(axis.z()) * 180 / M_PI);
    // Working distance: along the optical axis to the surface.
    const Eigen::Vector3d centre = a.block<3, 1>(0, 3);
    const double t = scan.surface().intersect(cv::Vec3d(centre.x(), centre.y(), centre.z()),
                                              cv::Vec3d(axis.x(), axis.y(), axis.z()));
    ASSERT_GE(t, 60.0) << "frame " << k;
    ASSERT_LE(t, 120.0) << "frame " << k;
  }
  EXPECT_GE(slowest, 3.0);
  EXPECT_LE(fastest, 30.0);
  EXPECT_GT(fastest - slowest, 5.0) << "the speed should vary along the path";
  EXPECT_GT(maxTiltDeg, 2.0);
  EXPECT_LE(maxTiltDeg, options.maxTiltDeg + 0.1);
}

TEST(SyntheticScan, WrittenGroundTruthIsConsistent) {
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "synthetic_scan";
  std::filesystem::remove_all(folder);
  const SyntheticScan scan(smallScan());
  const int written = writeSyntheticScan(scan, folder.string());
  EXPECT_EQ(written, 3 + 4 * scan.frameCount());
  for (int k = 0; k < scan.frameCount(); ++k) {
    const std::string name = cv::format("%06d", k);
    EXPECT_TRUE(std::filesystem::exists(folder / "left" / (name + ".png")));
    EXPECT_TRUE(std::filesystem::exists(folder / "right" / (name + ".png")));
  }
  const StereoCalibration rig = readStereoCalibration((folder / "rig.yml").string());
  EXPECT_NEAR(StereoRectifier(rig).geometry().focalPx, scan.geometry().focalPx, 1e-9);

  const Trajectory trajectory = readTumTrajectory((folder / "groundtruth" / "trajectory.txt").string());
  ASSERT_EQ(static_cast<int>(trajectory.size()), scan.frameCount());
  const TriangleMesh mesh = readMeshPly((folder / "groundtruth" / "surface.ply").string());
  ASSERT_GT(mesh.triangles.size(), 1000u);
  EXPECT_EQ(mesh.triangles.size(), scan.seenSurfaceMesh(0.5).triangles.size()) << "surface.ply: the seen surface";

  const RectifiedGeometry& g = scan.geometry();
  for (int k : {0, scan.frameCount() - 1}) {
    EXPECT_NEAR(trajectory[k].timeS, k / 30.0, 1e-6);
    EXPECT_LT((trajectory[k].T_world_camera - scan.T_world_camera(k)).norm(), 1e-9);
    const cv::Mat depth = readPfm((folder / "groundtruth" / cv::format("depth_%06d.pfm", k)).string());
    ASSERT_EQ(depth.size(), cv::Size(240, 136));
    int checked = 0;
    double worstMm = 0;
    // The mesh holds what both eyes saw kSeenBorderPx inside their images: test pixels a triangle (~2 px) further in.
    const double margin = SyntheticScan::kSeenBorderPx + 3;
    for (int v = 3; v < depth.rows; v += 19) {
      for (int u = 5; u < depth.cols; u += 23) {
        const float z = depth.at<float>(v, u);
        if (!std::isfinite(z)) continue;
        const double uRight = u - g.focalPx * g.baselineMm / z + g.doffsPx;  // its pixel in the right view
        if (v < margin || v > depth.rows - 1 - margin || u < margin || u > depth.cols - 1 - margin ||
            uRight < margin || uRight > depth.cols - 1 - margin) {
          continue;
        }
        const Eigen::Vector3d camera((u - g.cxLeftPx) * z / g.focalPx, (v - g.cyPx) * z / g.focalPx, z);
        const Eigen::Vector3d world = trajectory[k].T_world_camera.block<3, 3>(0, 0) * camera +
                                      trajectory[k].T_world_camera.block<3, 1>(0, 3);
        const double h = meshHeightMm(mesh, world.x(), world.y());
        ASSERT_TRUE(std::isfinite(h)) << "point outside the surface mesh";
        worstMm = std::max(worstMm, std::abs(world.z() - h));
        ++checked;
      }
    }
    EXPECT_GT(checked, 40);
    EXPECT_LT(worstMm, 0.02) << "frame " << k;  // mesh spacing 0.5 mm: linear interpolation error ~0.005 mm
  }
}

TEST(SyntheticScan, SurfaceMeshHoldsWhatBothEyesSaw) {
  SyntheticScanOptions options = smallScan(9);
  options.frames = 40;
  const SyntheticScan scan(options);
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh seen = scan.seenSurfaceMesh(0.5);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const TriangleMesh grid = scan.surfaceMesh(0.5);
  std::printf("seen surface: %zu of %zu triangles, %zu vertices, %.1f ms for %d frames\n", seen.triangles.size(),
              grid.triangles.size(), seen.verticesMm.size(), ms, scan.frameCount());
  ASSERT_GT(seen.triangles.size(), 5000u);
  EXPECT_LT(seen.triangles.size(), grid.triangles.size());

  // Sound: every kept triangle lies inside both views in one frame; every vertex is used.
  std::vector<bool> used(seen.verticesMm.size(), false);
  std::size_t unseen = 0;
  for (const cv::Vec3i& t : seen.triangles) {
    bool found = false;
    for (int k = 0; k < scan.frameCount() && !found; ++k) found = seenWhole(scan, k, seen, t);
    unseen += !found;
    for (int i = 0; i < 3; ++i) used[static_cast<std::size_t>(t[i])] = true;
  }
  EXPECT_EQ(unseen, 0u) << "kept triangles that no frame saw whole with both eyes";
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);

  // Complete: every grid triangle that a frame saw is kept. Triangles far outside the path are not: the outer 3 mm
  // of the scanned domain lie outside every view by construction.
  std::set<std::pair<long long, long long>> kept;
  for (const cv::Vec3i& t : seen.triangles) kept.insert(centroidKey(seen, t));
  const cv::Rect2d domain = scan.scannedDomainMm();
  std::size_t missing = 0, seenInChecked = 0, keptAtEdge = 0;
  for (const cv::Vec3i& t : grid.triangles) {
    const bool isKept = kept.count(centroidKey(grid, t)) > 0;
    for (int k : {0, 13, 27, scan.frameCount() - 1}) {
      if (seenWhole(scan, k, grid, t)) {
        ++seenInChecked;
        missing += !isKept;
        break;
      }
    }
    const cv::Point3f& a = grid.verticesMm[t[0]];
    const bool atEdge = a.x < domain.x + 2 || a.x > domain.x + domain.width - 2 || a.y < domain.y + 2 ||
                        a.y > domain.y + domain.height - 2;
    keptAtEdge += atEdge && isKept;
  }
  EXPECT_GT(seenInChecked, 3000u);
  EXPECT_EQ(missing, 0u) << "triangles seen whole by both eyes but not kept";
  EXPECT_EQ(keptAtEdge, 0u) << "triangles kept at the edge of the scanned domain, which no frame sees";
  const cv::Vec3i corner = grid.triangles.front();  // at the domain's corner, far from every view
  EXPECT_EQ(kept.count(centroidKey(grid, corner)), 0u);

  // Testing every 4th frame (and the last) keeps a subset.
  EXPECT_LE(scan.seenSurfaceMesh(0.5, 4).triangles.size(), seen.triangles.size());
  EXPECT_THROW(scan.seenSurfaceMesh(0.5, 0), Error);
}

TEST(SyntheticScan, RejectsInvalidOptions) {
  SyntheticScanOptions options = smallScan();
  options.maxWorkingDistanceMm = options.minWorkingDistanceMm - 1;
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = smallScan();
  options.frames = 0;
  EXPECT_THROW(SyntheticScan{options}, Error);
}
