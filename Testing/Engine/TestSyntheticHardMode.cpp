// The hard-mode synthetic scans (SyntheticHardMode.h) and their ground truth: the breathing surface per frame and
// the part that never moves, instruments that occlude the tissue (mask, clearance, the union mesh), the camera
// taken out and put back 10 mm and 10 degrees away, smoke; deterministic from the seed.
#include "SyntheticBreathing.h"
#include "SyntheticInstruments.h"
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
#include <filesystem>

using namespace tissuemosaic;
using namespace tissuemosaic::synthetic;

namespace {

SyntheticScanOptions hardScan() {
  SyntheticScanOptions options;
  options.width = 240;
  options.height = 136;
  options.frames = 40;
  options.seed = 3;
  options.supersampling = 1;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.breathingPeriodS = 1;
  options.hardMode.instruments = 2;
  options.hardMode.cameraOutStart = 20;
  options.hardMode.cameraOutEnd = 26;
  return options;
}

/// The world point seen at left pixel (u, v) with ground-truth depth z at frame k.
Eigen::Vector3d backProject(const SyntheticScan& scan, int k, int u, int v, double z) {
  const RectifiedGeometry& g = scan.geometry();
  const Eigen::Vector3d camera((u - g.cxLeftPx) * z / g.focalPx, (v - g.cyPx) * z / g.focalPx, z);
  const Eigen::Matrix4d T = scan.T_world_camera(k);
  return T.block<3, 3>(0, 0) * camera + T.block<3, 1>(0, 3);
}

/// Frame k's ground-truth depth, every 5th pixel, against a surface: how far it lies from it at worst, how far it
/// rises above the scan's surface at rest, and at how many samples that rise passes 0.5 mm.
struct DepthAgainstSurface {
  double worstMm = 0, largestRiseMm = 0;
  int risenSamples = 0;
};

DepthAgainstSurface compareDepth(const SyntheticScan& scan, int k, const SyntheticScanFrame& frame,
                                 const TissueSurface& surface) {
  DepthAgainstSurface result;
  for (int v = 2; v < frame.depthMm.rows; v += 5) {
    for (int u = 2; u < frame.depthMm.cols; u += 5) {
      const float z = frame.depthMm.at<float>(v, u);
      if (!std::isfinite(z)) continue;
      const Eigen::Vector3d p = backProject(scan, k, u, v, z);
      result.worstMm = std::max(result.worstMm, std::abs(p.z() - surface.heightMm(p.x(), p.y())));
      const double rise = scan.surface().heightMm(p.x(), p.y()) - p.z();
      result.largestRiseMm = std::max(result.largestRiseMm, rise);
      result.risenSamples += rise > 0.5;
    }
  }
  return result;
}

}  // namespace

TEST(SyntheticHardMode, BreathingMovesOnlyItsPartAndTheDepthFollowsIt) {
  SyntheticScanOptions options = hardScan();
  options.hardMode.instruments = 0;
  options.hardMode.cameraOutStart = options.hardMode.cameraOutEnd = -1;
  const SyntheticScan scan(options);
  const SyntheticBreathing& breathing = scan.breathing();
  ASSERT_TRUE(breathing.active());
  const SurfaceSwell& shape = breathing.shape();
  // At rest at t = 0, A at the centre at half a period, nothing beyond the outer radius.
  EXPECT_EQ(breathing.swellAt(0).amplitudeMm, 0.0);
  EXPECT_NEAR(breathing.swellAt(0.5).amplitudeMm, -2.0, 1e-12);
  EXPECT_DOUBLE_EQ(breathing.peakDisplacementMm(shape.centreXMm, shape.centreYMm), 2.0);
  EXPECT_EQ(breathing.peakDisplacementMm(shape.centreXMm + shape.outerRadiusMm + 0.01, shape.centreYMm), 0.0);
  EXPECT_TRUE(breathing.isStatic(shape.centreXMm, shape.centreYMm + shape.outerRadiusMm));
  EXPECT_FALSE(breathing.isStatic(shape.centreXMm, shape.centreYMm + shape.innerRadiusMm));
  EXPECT_DOUBLE_EQ(shape.outerRadiusMm, 18.0);  // the default radius
  EXPECT_DOUBLE_EQ(shape.innerRadiusMm, 10.0);

  // --breathing-radius-mm: the same shape, wider. At 30 mm from the centre the default disc stands still, a 40 mm
  // one still moves.
  SyntheticScanOptions wide = options;
  wide.hardMode.breathingRadiusMm = 40;
  const SyntheticScan wideScan(wide);
  const SurfaceSwell& wideShape = wideScan.breathing().shape();
  EXPECT_DOUBLE_EQ(wideShape.outerRadiusMm, 40.0);
  EXPECT_NEAR(wideShape.innerRadiusMm, 40.0 * 10.0 / 18.0, 1e-12);
  EXPECT_TRUE(breathing.isStatic(shape.centreXMm + 30, shape.centreYMm));
  EXPECT_FALSE(wideScan.breathing().isStatic(wideShape.centreXMm + 30, wideShape.centreYMm));

  // Frame 15 (t = 0.5 s: the peak): every ground-truth depth pixel lies on the swollen surface, and where the swell
  // is, that is up to 2 mm nearer the scope than the surface at rest.
  const int k = 15;
  const SyntheticScanFrame frame = scan.renderFrame(k);
  const DepthAgainstSurface peak =
      compareDepth(scan, k, frame, scan.surface().swollen(breathing.swellAt(frame.timeS)));
  EXPECT_LT(peak.worstMm, 1e-4);
  EXPECT_GT(peak.risenSamples, 20) << "the breathing part should be in view";
  EXPECT_NEAR(peak.largestRiseMm, 2.0, 0.05);

  // static_surface: the seen surface less every triangle the breathing moves.
  const TriangleMesh seen = scan.seenSurfaceMesh(0.5), still = scan.staticSurfaceMesh(0.5);
  EXPECT_LT(still.triangles.size(), seen.triangles.size());
  EXPECT_GT(still.triangles.size(), seen.triangles.size() / 2);
  for (const cv::Point3f& p : still.verticesMm) ASSERT_TRUE(breathing.isStatic(p.x, p.y));
}

// A breath hold (the ventilator paused from 0.4 to 1.0 s): the tissue rests where it was at 0.4 s for the whole span,
// the rendered depth follows it, and the breath goes on from that phase afterwards.
TEST(SyntheticHardMode, ABreathHoldStopsTheBreathWhereItIsAndItGoesOnAfter) {
  SyntheticScanOptions options = hardScan();
  options.hardMode.instruments = 0;
  options.hardMode.cameraOutStart = options.hardMode.cameraOutEnd = -1;
  options.hardMode.breathHoldStartS = 0.4;
  options.hardMode.breathHoldEndS = 1.0;
  const SyntheticScan scan(options);
  const SyntheticBreathing& breathing = scan.breathing();
  SyntheticScanOptions free = options;
  free.hardMode.breathHoldStartS = free.hardMode.breathHoldEndS = -1;
  const SyntheticScan freeScan(free);
  const SyntheticBreathing& unheld = freeScan.breathing();
  const double held = unheld.swellAt(0.4).amplitudeMm;
  EXPECT_LT(held, -1.0);  // near the peak (-2 mm at 0.5 s)
  for (double t : {0.0, 0.2, 0.39}) EXPECT_EQ(breathing.swellAt(t).amplitudeMm, unheld.swellAt(t).amplitudeMm) << t;
  for (double t : {0.4, 0.6, 0.99}) EXPECT_EQ(breathing.swellAt(t).amplitudeMm, held) << t;
  for (double t : {1.0, 1.3}) {
    EXPECT_NEAR(breathing.swellAt(t).amplitudeMm, unheld.swellAt(t - 0.6).amplitudeMm, 1e-12) << t;
  }
  // Frame 24 (t = 0.8 s, inside the hold) is rendered at the held phase; without the hold it would be near rest.
  const int k = 24;
  const SyntheticScanFrame frame = scan.renderFrame(k);
  ASSERT_NEAR(frame.timeS, 0.8, 1e-9);
  const DepthAgainstSurface inHold = compareDepth(scan, k, frame, scan.surface().swollen(unheld.swellAt(0.4)));
  EXPECT_LT(inHold.worstMm, 1e-4);
  EXPECT_NEAR(inHold.largestRiseMm, -held, 0.05);
}

TEST(SyntheticHardMode, InstrumentsOccludeTheTissueAndKeepClearOfIt) {
  SyntheticScanOptions options = hardScan();
  options.hardMode.breathingAmplitudeMm = 0;
  options.hardMode.cameraOutStart = options.hardMode.cameraOutEnd = -1;
  const SyntheticScan scan(options);
  const SyntheticInstruments& instruments = scan.instruments();
  ASSERT_EQ(instruments.count(), 2);
  int framesWithInstrument = 0;
  for (int k = 0; k < scan.frameCount(); k += 3) {
    const SyntheticScanFrame frame = scan.renderFrame(k);
    ASSERT_EQ(frame.instrumentMask.type(), CV_8U);
    const std::vector<InstrumentPose> poses = instruments.posesAt(k);
    const int covered = cv::countNonZero(frame.instrumentMask);
    if (poses.empty()) EXPECT_EQ(covered, 0) << "frame " << k;
    framesWithInstrument += covered > 0;
    // Where the mask says instrument, the pixel is steel: the view differs from the same frame without instruments.
    for (const InstrumentPose& pose : poses) {
      // Clearance: the tip, the jaws' ends and the shaft near the tip stay 3 mm off the tissue.
      for (const cv::Vec3d& p : {pose.jaws[0].toMm, pose.jaws[1].toMm, pose.tipMm}) {
        EXPECT_GE(scan.surface().distanceMm(p[0], p[1], p[2]), SyntheticInstruments::kClearanceMm + 0.5) << k;
        EXPECT_LT(p[2], scan.surface().heightMm(p[0], p[1])) << "instrument above the tissue";
      }
    }
  }
  EXPECT_GE(framesWithInstrument, 5);

  // The union mesh holds the instruments at every frame: a point on a jaw's surface at some frame is on it.
  const TriangleMesh mesh = scan.instrumentSurfaceMesh();
  ASSERT_GT(mesh.triangles.size(), 1000u);
  const int k = (instruments.span(0).first + instruments.span(0).second) / 2;
  const InstrumentPose pose = instruments.posesAt(k).front();
  const cv::Vec3d onJaw = pose.jaws[0].toMm + cv::Vec3d(0, 0, -pose.jaws[0].radiusMm);
  EXPECT_LT(instruments.distanceMm(onJaw, scan.tissueFrames()), 0.05);
  double nearestVertex = 1e9;
  for (const cv::Point3f& v : mesh.verticesMm) nearestVertex = std::min(nearestVertex, cv::norm(cv::Vec3d(v.x, v.y, v.z) - onJaw));
  EXPECT_LT(nearestVertex, 1.0);
  // Tissue points are never within 1 mm of an instrument (so a model point there is an instrument artefact).
  for (int j = 0; j < 200; ++j) {
    const double x = scan.scannedDomainMm().x + scan.scannedDomainMm().width * ((j * 37) % 200) / 200.0;
    const double y = scan.scannedDomainMm().y + scan.scannedDomainMm().height * ((j * 91) % 200) / 200.0;
    ASSERT_GT(instruments.distanceMm(cv::Vec3d(x, y, scan.surface().heightMm(x, y)), scan.tissueFrames()), 1.0);
  }
}

TEST(SyntheticHardMode, TheCameraGoesOutAndComesBackNearWhereItLeft) {
  SyntheticScanOptions options = hardScan();
  options.hardMode.breathingAmplitudeMm = 0;
  options.hardMode.instruments = 0;
  const SyntheticScan scan(options);
  const int start = options.hardMode.cameraOutStart, end = options.hardMode.cameraOutEnd;
  for (int k = 0; k < scan.frameCount(); ++k) EXPECT_EQ(scan.tissueInView(k), k < start || k >= end) << k;
  EXPECT_EQ(static_cast<int>(scan.tissueFrames().size()), scan.frameCount() - (end - start));
  for (int k : {start, (start + end) / 2, end - 1}) {
    const SyntheticScanFrame out = scan.renderFrame(k);
    EXPECT_FALSE(out.tissueInView);
    EXPECT_EQ(cv::countNonZero(out.depthMm == out.depthMm), 0) << "no tissue, no depth";
  }
  // Back about 10 mm and 10 degrees from where it left, then following its path (about its normal step apart).
  const Eigen::Matrix4d left = scan.T_world_camera(start - 1), back = scan.T_world_camera(end);
  const double mm = (back.block<3, 1>(0, 3) - left.block<3, 1>(0, 3)).norm();
  const double deg = Eigen::AngleAxisd(Eigen::Matrix3d(left.block<3, 3>(0, 0).transpose() * back.block<3, 3>(0, 0))).angle() * 180 / M_PI;
  EXPECT_NEAR(mm, 10.0, 1e-6);
  EXPECT_NEAR(deg, 10.0, 1e-6);
  const double step = (scan.T_world_camera(end + 1).block<3, 1>(0, 3) - back.block<3, 1>(0, 3)).norm();
  EXPECT_LT(step, 1.0);
  const SyntheticScanFrame returned = scan.renderFrame(end);
  EXPECT_GT(cv::countNonZero(returned.depthMm == returned.depthMm), returned.depthMm.total() / 2);

  // Written: no trajectory line for the frames out, a mask per frame, the scene description.
  const std::filesystem::path folder = std::filesystem::path(TM_TEST_OUTPUT_DIR) / "synthetic_hard_mode";
  std::filesystem::remove_all(folder);
  SyntheticScanOptions small = options;
  small.frames = 12;
  small.hardMode.cameraOutStart = 4;
  small.hardMode.cameraOutEnd = 7;
  small.hardMode.instruments = 1;
  small.hardMode.breathingAmplitudeMm = 1.5;
  const SyntheticScan written(small);
  writeSyntheticScan(written, folder.string());
  const Trajectory trajectory = readTumTrajectory((folder / "groundtruth" / "trajectory.txt").string());
  ASSERT_EQ(trajectory.size(), 9u);
  EXPECT_NEAR(trajectory[3].timeS, 3 / 30.0, 1e-6);
  EXPECT_NEAR(trajectory[4].timeS, 7 / 30.0, 1e-6);
  for (int k = 0; k < small.frames; ++k) {
    EXPECT_TRUE(std::filesystem::exists(folder / "groundtruth" / cv::format("instrument_mask_%06d.png", k))) << k;
  }
  for (const char* file : {"static_surface.ply", "instruments.ply", "scene.yml", "surface.ply"}) {
    EXPECT_TRUE(std::filesystem::exists(folder / "groundtruth" / file)) << file;
  }
}

TEST(SyntheticHardMode, IsDeterministicFromTheSeed) {
  SyntheticScanOptions options = hardScan();
  options.hardMode.smoke = true;
  const SyntheticScan a(options), b(options);
  options.seed = 4;
  const SyntheticScan other(options);
  for (int k : {8, 21, 30}) {
    const SyntheticScanFrame fa = a.renderFrame(k), fb = b.renderFrame(k), fo = other.renderFrame(k);
    EXPECT_EQ(cv::norm(fa.leftRectified, fb.leftRectified, cv::NORM_INF), 0) << k;
    EXPECT_EQ(cv::norm(fa.rightRectified, fb.rightRectified, cv::NORM_INF), 0) << k;
    EXPECT_EQ(cv::norm(fa.instrumentMask, fb.instrumentMask, cv::NORM_INF), 0) << k;
    EXPECT_GT(cv::norm(fa.leftRectified, fo.leftRectified, cv::NORM_L1), 0) << k;
  }
  // Smoke veils the tissue: less contrast than the same frame without it.
  options.seed = 3;
  options.hardMode.smoke = false;
  const SyntheticScan clear(options);
  cv::Scalar meanSmoke, sdSmoke, meanClear, sdClear;
  cv::meanStdDev(a.renderFrame(8).leftRectified, meanSmoke, sdSmoke);
  cv::meanStdDev(clear.renderFrame(8).leftRectified, meanClear, sdClear);
  EXPECT_LT(sdSmoke[2], sdClear[2]);
}

TEST(SyntheticHardMode, RejectsInvalidOptions) {
  SyntheticScanOptions options = hardScan();
  options.hardMode.cameraOutStart = 0;  // no tissue before the camera leaves
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.cameraOutEnd = options.frames;  // never back
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.breathingAmplitudeMm = -1;
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.instruments = 9;
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.breathingPeriodS = 0;
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.breathingRadiusMm = 1;
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.breathHoldStartS = 1.0;
  options.hardMode.breathHoldEndS = 0.5;  // ends before it starts
  EXPECT_THROW(SyntheticScan{options}, Error);
  options = hardScan();
  options.hardMode.breathingAmplitudeMm = 0;  // nothing to hold
  options.hardMode.breathHoldStartS = 0;
  options.hardMode.breathHoldEndS = 1;
  EXPECT_THROW(SyntheticScan{options}, Error);
}
