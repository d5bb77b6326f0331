// The deformation graph in the pipeline (fusion.deformation on, docs/DEFORMATION.md) on a still scope over tissue
// whose middle breathes 3 mm, against the generator's truth, beside the rigid pipeline on the same frames: at the
// breath's peak the live surface (the canonical samples warped) lies on the frame's true surface and the canonical
// samples on the rest surface, where the unwarped samples are off by the breath; the fused model follows the tissue
// too: the breathing part is fused (covered at rest, where the rigid model leaves a hole or a smear), the canonical
// model lies on the rest surface, the live model on the peak's surface, and the poses are no worse than the rigid
// pipeline's.
#include "SyntheticBreathing.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "Fusion/PointModel.h"
#include "Reconstruction/ReconstructionPipeline.h"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

using namespace tissuemosaic;

namespace {

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

synthetic::SyntheticScanOptions breathingStillScope() {
  synthetic::SyntheticScanOptions options;
  options.width = 320;
  options.height = 240;
  options.frames = 31;  // the breath peaks at frame 30 (1 s)
  options.seed = 7;
  options.supersampling = 1;
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80;
  options.hardMode.breathingAmplitudeMm = 3;
  options.hardMode.breathingPeriodS = 2;
  options.hardMode.breathingRadiusMm = 14;  // a local swell: the still tissue around it holds the camera
  return options;
}

/// Share of a part of the rest surface (a 1 mm grid, in view of the still camera) that has a model point within
/// 1 mm: the breathing part (where the breath lifts the tissue more than 1 mm) or the still part.
double coverage(const synthetic::SyntheticScan& scan, const ModelPoints& model, bool breathingPart) {
  const Eigen::Matrix4d T_camera_world = scan.T_world_camera(0).inverse();
  const RectifiedGeometry& g = scan.geometry();
  int inPart = 0, covered = 0;
  for (double y = -40; y <= 40; y += 1.0) {
    for (double x = -40; x <= 40; x += 1.0) {
      if (breathingPart ? !(scan.breathing().peakDisplacementMm(x, y) > 1.0) : !scan.breathing().isStatic(x, y)) continue;
      const Eigen::Vector3d rest(x, y, scan.surface().heightMm(x, y));
      const Eigen::Vector3d c = T_camera_world.topLeftCorner<3, 3>() * rest + T_camera_world.topRightCorner<3, 1>();
      const double u = g.focalPx * c.x() / c.z() + g.cxLeftPx, v = g.focalPx * c.y() / c.z() + g.cyPx;
      if (!(c.z() > 0 && u > 8 && v > 8 && u < g.imageSize.width - 8 && v < g.imageSize.height - 8)) continue;
      ++inPart;
      double nearest = 1e9;
      for (const cv::Point3f& p : model.cloud.pointsMm) {
        nearest = std::min(nearest, (Eigen::Vector3d(p.x, p.y, p.z) - rest).squaredNorm());
      }
      if (nearest <= 1.0) ++covered;
    }
  }
  return inPart > 0 ? static_cast<double>(covered) / inPart : 0.0;
}

/// Distances (mm) of the model's points over the breathing part (where it rises more than 1 mm) to a surface.
std::vector<double> distancesOverBreathing(const synthetic::SyntheticScan& scan, const ModelPoints& model,
                                           const ModelPoints& restModel, const synthetic::TissueSurface& surface) {
  std::vector<double> distances;
  for (std::size_t i = 0; i < model.size(); ++i) {
    const cv::Point3f& r = restModel.cloud.pointsMm[i];
    if (!(scan.breathing().peakDisplacementMm(r.x, r.y) > 1.0)) continue;
    const cv::Point3f& p = model.cloud.pointsMm[i];
    distances.push_back(std::abs(surface.distanceMm(p.x, p.y, p.z)));
  }
  return distances;
}

double rms(const std::vector<double>& values) {
  double sum = 0;
  for (const double v : values) sum += v * v;
  return values.empty() ? 0.0 : std::sqrt(sum / values.size());
}

}  // namespace

TEST(DeformationPipeline, FollowsBreathingTissueAndFusesIt) {
  const synthetic::SyntheticScan scan(breathingStillScope());
  ReconstructionParameters rigidParameters, deformingParameters;
  deformingParameters.fusion.deformation = true;
  ReconstructionPipeline rigid(scan.geometry(), rigidParameters, Device::Cpu, scan.T_world_camera(0));
  ReconstructionPipeline deforming(scan.geometry(), deformingParameters, Device::Cpu, scan.T_world_camera(0));
  ASSERT_EQ(rigid.deformationGraph(), nullptr);
  ASSERT_NE(deforming.deformationGraph(), nullptr);
  FrameResult early, peak;
  double stereoFloorMm = 0, rigidCameraErrorMm = 0, deformingCameraErrorMm = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    const FrameResult a = rigid.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    const FrameResult b = deforming.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    ASSERT_EQ(a.tracked, b.tracked) << "frame " << k;
    EXPECT_FALSE(a.deformation.fitted);
    EXPECT_EQ(a.timesMs.deformation, 0.0);
    if (b.tracked && k > 0) EXPECT_TRUE(b.deformation.fitted) << "frame " << k;
    const Eigen::Vector3d truth = scan.T_world_camera(k).topRightCorner<3, 1>();
    rigidCameraErrorMm = std::max(rigidCameraErrorMm, (a.T_world_camera.topRightCorner<3, 1>() - truth).norm());
    deformingCameraErrorMm = std::max(deformingCameraErrorMm, (b.T_world_camera.topRightCorner<3, 1>() - truth).norm());
    if (k == 3) early = b;
    if (k == 0) {  // the stereo's own error at rest: the floor the samples can reach at this resolution
      std::vector<double> atRest;
      for (const Eigen::Vector3d& c : deforming.deformation()->canonicalPoints())
        atRest.push_back(std::abs(scan.surface().distanceMm(c.x(), c.y(), c.z())));
      stereoFloorMm = median(atRest);
    }
    if (k == scan.frameCount() - 1) peak = b;
  }

  // The samples against the truth: the live ones against the peak's surface, the canonical ones against the rest.
  const DeformationTracker& field = *deforming.deformation();
  const DeformationTracker::Points live = field.livePoints();
  const synthetic::TissueSurface now = scan.surfaceAt(scan.frameCount() - 1);
  // Over the tissue that rose more than 1 mm at the peak: the breathing part.
  std::vector<double> liveMm, canonicalMm, unwarpedMm;
  for (std::size_t i = 0; i < live.size(); ++i) {
    const Eigen::Vector3d& c = field.canonicalPoints()[i];
    if (!(scan.breathing().peakDisplacementMm(c.x(), c.y()) > 1.0)) continue;
    liveMm.push_back(std::abs(now.distanceMm(live[i].x(), live[i].y(), live[i].z())));
    canonicalMm.push_back(std::abs(scan.surface().distanceMm(c.x(), c.y(), c.z())));
    unwarpedMm.push_back(std::abs(now.distanceMm(c.x(), c.y(), c.z())));
  }
  ASSERT_GT(liveMm.size(), 20u) << "samples over the breathing part";
  const double liveMedian = median(liveMm), canonicalMedian = median(canonicalMm), unwarpedMedian = median(unwarpedMm);
  std::printf("[ measured ] peak (frame 30): %zu samples (%zu over the breathing part), %d nodes; there, median "
              "distance of the live surface to the true surface %.3f mm (unwarped %.3f), of the canonical samples to "
              "the rest surface %.3f mm (the stereo's own at rest %.3f); %.1f%% of all within 1 mm of the frame's "
              "depth against %.1f%% unwarped; largest node motion %.2f mm (frame 3: %.2f); fit %.1f ms\n",
              live.size(), liveMm.size(), peak.deformation.nodes, liveMedian, unwarpedMedian, canonicalMedian,
              stereoFloorMm, 100 * peak.deformation.liveShareWithin1mm, 100 * peak.deformation.rigidShareWithin1mm,
              peak.deformation.maxNodeMotionMm, early.deformation.maxNodeMotionMm, peak.deformation.milliseconds);
  // At 320x240 one pixel of disparity is about 4 mm of depth: the stereo's own error (0.6 mm) is the floor.
  EXPECT_GT(unwarpedMedian, stereoFloorMm + 1.0) << "the tissue must have moved for the test to mean anything";
  EXPECT_LT(liveMedian, stereoFloorMm + 0.15);
  EXPECT_LT(canonicalMedian, stereoFloorMm + 0.15);
  EXPECT_GT(peak.deformation.liveShareWithin1mm, peak.deformation.rigidShareWithin1mm + 0.05);
  EXPECT_GT(peak.deformation.maxNodeMotionMm, 2.0) << "the swell's top rose 3 mm";

  // The fused model: at rest (canonical) and where the tissue is at the peak (live), against the truth.
  const ModelPoints rigidModel = rigid.modelSnapshot(), canonical = deforming.modelSnapshot();
  const ModelPoints liveModel = deforming.liveModelSnapshot();
  ASSERT_EQ(canonical.size(), liveModel.size());
  const double rigidCoverage = coverage(scan, rigidModel, true), canonicalCoverage = coverage(scan, canonical, true);
  // The stereo's noise leaves some of the surface without a point within 1 mm at this resolution, still or not.
  const double stillCoverage = coverage(scan, canonical, false);
  const std::vector<double> canonicalToRest = distancesOverBreathing(scan, canonical, canonical, scan.surface());
  const std::vector<double> liveToNow = distancesOverBreathing(scan, liveModel, canonical, now);
  const std::vector<double> canonicalToNow = distancesOverBreathing(scan, canonical, canonical, now);
  const std::vector<double> rigidToRest = distancesOverBreathing(scan, rigidModel, rigidModel, scan.surface());
  ASSERT_GT(canonicalToRest.size(), 50u) << "model points over the breathing part";
  std::printf("[ measured ] fused model: breathing part covered at rest %.1f%% (rigid model %.1f%%, still part %.1f%%); over it, the "
              "canonical model lies %.3f mm RMS (median %.3f) from the rest surface (rigid model %.3f RMS, %zu points), "
              "the live model %.3f mm RMS (median %.3f) from the peak's surface (canonical %.3f); %zu points (rigid "
              "%zu); largest camera error %.3f mm (rigid %.3f)\n",
              100 * canonicalCoverage, 100 * rigidCoverage, 100 * stillCoverage, rms(canonicalToRest), median(canonicalToRest),
              rms(rigidToRest), rigidToRest.size(), rms(liveToNow), median(liveToNow), median(canonicalToNow),
              canonical.size(), rigidModel.size(), deformingCameraErrorMm, rigidCameraErrorMm);
  EXPECT_LT(rigidCoverage, 0.1) << "the rigid model should leave the breathing part out or smear it";
  EXPECT_GT(canonicalCoverage, stillCoverage - 0.15) << "the breathing part should be fused like the still part";
  EXPECT_LT(rms(canonicalToRest), 0.6);
  EXPECT_LT(rms(canonicalToRest), rms(rigidToRest) / 4);
  EXPECT_LT(rms(liveToNow), 0.7) << "the live model should lie on the peak's surface";
  EXPECT_LT(median(liveToNow), median(canonicalToNow) / 4);
  EXPECT_LT(deformingCameraErrorMm, rigidCameraErrorMm + 0.05);
}

TEST(DeformationPipeline, TheParameterFileSwitchesItOnAndRefusesOtherValues) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "tm_deformation_parameters";
  std::filesystem::create_directories(folder);
  const auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = (folder / name).string();
    std::ofstream(path) << "%YAML:1.0\n---\n" << text;
    return path;
  };
  EXPECT_FALSE(ReconstructionParameters{}.fusion.deformation) << "off by default: the rigid pipeline";
  EXPECT_TRUE(ReconstructionParameters::readFile(write("on.yml", "fusion:\n  deformation: on\n")).fusion.deformation);
  EXPECT_FALSE(ReconstructionParameters::readFile(write("off.yml", "fusion:\n  deformation: off\n")).fusion.deformation);
  try {
    ReconstructionParameters::readFile(write("bad.yml", "fusion:\n  deformation: maybe\n"));
    FAIL() << "a value other than on or off was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("deformation must be \"on\" or \"off\""), std::string::npos) << error.what();
  }
  std::filesystem::remove_all(folder);
}
