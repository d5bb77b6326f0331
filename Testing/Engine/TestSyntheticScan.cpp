// The synthetic scanning video: deterministic from the seed, a path inside the brief's envelope (60-120 mm from the
// tissue, 3-30 mm/s), and ground truth that agrees with itself: a ground-truth depth pixel back-projected with the
// ground-truth pose lies on the written surface mesh, and the written trajectory is the scan's pose.
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "IO/DisparityPfm.h"
#include "IO/MeshPly.h"
#include "IO/TrajectoryTum.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>
#include <filesystem>

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
  EXPECT_EQ(written, 3 + 3 * scan.frameCount());
  for (int k = 0; k < scan.frameCount(); ++k) {
    const std::string name = cv::format("%06d", k);
    EXPECT_TRUE(std::filesystem::exists(folder / "left" / (name + ".png")));
    EXPECT_TRUE(std::filesystem::exists(folder / "right" / (name + ".png")));
  }
  const StereoCalibration rig = StereoCalibration::read((folder / "rig.yml").string());
  EXPECT_NEAR(StereoRectifier(rig).geometry().focalPx, scan.geometry().focalPx, 1e-9);

  const Trajectory trajectory = readTumTrajectory((folder / "groundtruth" / "trajectory.txt").string());
  ASSERT_EQ(static_cast<int>(trajectory.size()), scan.frameCount());
  const TriangleMesh mesh = readMeshPly((folder / "groundtruth" / "surface.ply").string());
  ASSERT_GT(mesh.triangles.size(), 1000u);

  const RectifiedGeometry& g = scan.geometry();
  for (int k : {0, scan.frameCount() - 1}) {
    EXPECT_NEAR(trajectory[k].timeS, k / 30.0, 1e-6);
    EXPECT_LT((trajectory[k].T_world_camera - scan.T_world_camera(k)).norm(), 1e-9);
    const cv::Mat depth = readPfm((folder / "groundtruth" / cv::format("depth_%06d.pfm", k)).string());
    ASSERT_EQ(depth.size(), cv::Size(240, 136));
    int checked = 0;
    double worstMm = 0;
    for (int v = 3; v < depth.rows; v += 19) {
      for (int u = 5; u < depth.cols; u += 23) {
        const float z = depth.at<float>(v, u);
        if (!std::isfinite(z)) continue;
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

TEST(SyntheticScan, RejectsInvalidOptions) {
  SyntheticScanOptions options = smallScan();
  options.maxWorkingDistanceMm = options.minWorkingDistanceMm - 1;
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = smallScan();
  options.frames = 0;
  EXPECT_THROW(SyntheticScan{options}, Error);
}
