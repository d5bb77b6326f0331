// The deformation graph in the pipeline (fusion.deformation on, docs/DEFORMATION.md) on a still scope over tissue
// whose middle breathes 3 mm, against the generator's truth: the poses and the fused model are the rigid pipeline's
// bit for bit; at the breath's peak the live surface (the canonical samples warped) lies on the frame's true surface
// and the canonical samples on the rest surface (the 0.3 mm), where the unwarped samples are off by the
// breath; the live surface agrees with the frame's depth where the rigid one no longer does.
#include "SyntheticBreathing.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"
#include "Fusion/PointModel.h"
#include "Reconstruction/ReconstructionPipeline.h"

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

}  // namespace

TEST(DeformationPipeline, FollowsBreathingTissueAndLeavesTheRigidResultsAsTheyWere) {
  const synthetic::SyntheticScan scan(breathingStillScope());
  ReconstructionParameters rigidParameters, deformingParameters;
  deformingParameters.fusion.deformation = true;
  ReconstructionPipeline rigid(scan.geometry(), rigidParameters, Device::Cpu, scan.T_world_camera(0));
  ReconstructionPipeline deforming(scan.geometry(), deformingParameters, Device::Cpu, scan.T_world_camera(0));
  ASSERT_EQ(rigid.deformationGraph(), nullptr);
  ASSERT_NE(deforming.deformationGraph(), nullptr);
  FrameResult early, peak;
  double stereoFloorMm = 0;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    const FrameResult a = rigid.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    const FrameResult b = deforming.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    ASSERT_EQ(a.tracked, b.tracked) << "frame " << k;
    ASSERT_TRUE(a.T_world_camera == b.T_world_camera) << "the deformation changed the pose of frame " << k;
    EXPECT_FALSE(a.deformation.fitted);
    EXPECT_EQ(a.timesMs.deformation, 0.0);
    if (b.tracked && k > 0) EXPECT_TRUE(b.deformation.fitted) << "frame " << k;
    if (k == 3) early = b;
    if (k == 0) {  // the stereo's own error at rest: the floor the samples can reach at this resolution
      std::vector<double> atRest;
      for (const Eigen::Vector3d& c : deforming.deformation()->canonicalPoints())
        atRest.push_back(std::abs(scan.surface().distanceMm(c.x(), c.y(), c.z())));
      stereoFloorMm = median(atRest);
    }
    if (k == scan.frameCount() - 1) peak = b;
  }
  const ModelPoints a = rigid.modelSnapshot(), b = deforming.modelSnapshot();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.cloud.pointsMm.data(), b.cloud.pointsMm.data(), a.size() * sizeof(a.cloud.pointsMm[0])), 0)
      << "the model is not the rigid pipeline's";

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
