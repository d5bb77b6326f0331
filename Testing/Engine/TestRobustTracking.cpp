// The whole pipeline on small hard-mode scans (SyntheticHardMode.h) against their ground truth: a still camera over
// breathing tissue stays still; frames without tissue are lost (no pose, not fused) and the camera is relocalised
// in the same world frame when the tissue comes back; moving tissue and instruments leave the model. Each bound is
// shown to fail with the behaviour switched off (the motion handling, the motion evidence).
#include "SyntheticBreathing.h"
#include "SyntheticInstruments.h"
#include "SyntheticInVivo.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Reconstruction/QualityLog.h"
#include "Reconstruction/ReconstructionPipeline.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstdlib>

using namespace tissuemosaic;

namespace {

synthetic::SyntheticScanOptions smallHardScan() {
  synthetic::SyntheticScanOptions options;
  // 480x270: at 320x180 too few ORB features carry a relocalised pose (2 mm, 1.5 deg off at 320x180 against
  // 0.5 mm, 0.4 deg here).
  options.width = 480;
  options.height = 270;
  options.seed = 3;
  options.supersampling = 1;
  return options;
}

double rotationDeg(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
  return Eigen::AngleAxisd(Eigen::Matrix3d(a.block<3, 3>(0, 0).transpose() * b.block<3, 3>(0, 0))).angle() * 180 / M_PI;
}

struct PipelineRun {
  std::vector<FrameResult> frames;
  ModelPoints model;
};

PipelineRun reconstruct(const synthetic::SyntheticScan& scan, const ReconstructionParameters& given) {
  const ReconstructionParameters& parameters = given;
  ReconstructionPipeline pipeline(scan.geometry(), parameters, Device::Cpu, scan.T_world_camera(0));
  PipelineRun run;
  for (int k = 0; k < scan.frameCount(); ++k) {
    const synthetic::SyntheticScanFrame frame = scan.renderFrame(k);
    FrameResult result = pipeline.process(frame.leftRectified, frame.rightRectified, frame.timeS);
    result.leftRectified = result.rightRectified = result.disparityPx = cv::Mat();
    run.frames.push_back(std::move(result));
  }
  run.model = pipeline.modelSnapshot();
  if (std::getenv("TM_TEST_VERBOSE")) {
    for (const FrameResult& f : run.frames) {
      const Eigen::Matrix4d truth = scan.T_world_camera(f.frameIndex);
      std::printf("frame %2d %-11s key %d inliers %4d moving %4d removed %6d err %.3f mm %.3f deg agree %.3f/%.3f %s\n",
                  f.frameIndex, frameStatusName(f.status), f.keyFrame, f.inliers, f.movingMatches, f.pointsRemoved,
                  f.tracked ? (f.T_world_camera.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).norm() : -1.0,
                  f.tracked ? rotationDeg(truth, f.T_world_camera) : -1.0, f.agreement.shareWithin1mm,
                  f.agreement.medianDepthDifferenceMm, f.trackingMessage.c_str());
    }
  }
  return run;
}

/// The largest distance and rotation of the estimated camera from its start over a run.
void largestMotion(const PipelineRun& run, double& mm, double& deg) {
  mm = deg = 0;
  const Eigen::Matrix4d start = run.frames.front().T_world_camera;
  for (const FrameResult& f : run.frames) {
    if (!f.tracked) continue;
    mm = std::max(mm, (f.T_world_camera.block<3, 1>(0, 3) - start.block<3, 1>(0, 3)).norm());
    deg = std::max(deg, rotationDeg(start, f.T_world_camera));
  }
}

/// The in-vivo still-scope test's bounds: today's limit with a margin, not the goal (0.5 mm, 0.3 deg). Measured
/// 3.27 mm, 0.20 deg (this 2-core CPU, 2026-11-28; 3.20 mm, 1.68 deg before the weak-texture rule): the estimate
/// follows the whole view's breath (docs/SCENE_MOTION.md, "Limits"); a tighter estimate must lower these.
constexpr double kInVivoStillMm = 4.0, kInVivoStillDeg = 0.5;

}  // namespace

TEST(RobustTracking, AStillCameraOverBreathingTissueStaysStill) {
  synthetic::SyntheticScanOptions options = smallHardScan();
  options.frames = 45;
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;  // the scope held still
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.breathingPeriodS = 1;
  const synthetic::SyntheticScan scan(options);
  for (int k = 1; k < scan.frameCount(); ++k) ASSERT_EQ(scan.T_world_camera(k), scan.T_world_camera(0));

  const PipelineRun robust = reconstruct(scan, ReconstructionParameters{});
  // The same without the motion handling: every match within H steers the pose, nothing is kept out.
  ReconstructionParameters naive;
  naive.tracking.dynamicResidualPx = 0;
  naive.tracking.dynamicDisparityPx = 0;
  naive.tracking.dynamicExcludeScore = 1;
  const PipelineRun plain = reconstruct(scan, naive);
  double mm = 0, deg = 0, plainMm = 0, plainDeg = 0;
  largestMotion(robust, mm, deg);
  largestMotion(plain, plainMm, plainDeg);
  int moving = 0;
  for (const FrameResult& f : robust.frames) moving += f.movingMatches;
  std::printf("still camera over breathing tissue (2 mm, 1 s): estimated motion at most %.3f mm, %.3f deg "
              "(%d matches kept out as moving); without the motion handling %.3f mm, %.3f deg\n",
              mm, deg, moving, plainMm, plainDeg);
  for (const FrameResult& f : robust.frames) ASSERT_TRUE(f.tracked) << "frame " << f.frameIndex << ": " << f.trackingMessage;
  // At 320x180 the key frames' refinement alone moves a still camera by up to ~0.1 mm (the same scan without
  // breathing); breathing must add little to that, and does add more without the motion handling.
  constexpr double kStillMm = 0.15, kStillDeg = 0.1;
  EXPECT_GT(moving, 0);
  EXPECT_LE(mm, kStillMm);
  EXPECT_LE(deg, kStillDeg);
  EXPECT_GT(plainMm, kStillMm) << "the bound should fail without the motion handling";
  EXPECT_GT(plainDeg, kStillDeg) << "the bound should fail without the motion handling";
}

TEST(RobustTracking, AStillCameraOverAWholeViewThatBreathesFollowsTheBreathWithinBoundsAndReturns) {
  // The in-vivo case of a scope held still over the abdomen: the whole view breathes (rigidly in its middle, bending
  // toward the edges) while instruments work over it, so that almost no tissue in view stands still and nothing
  // tells the camera's motion from the tissue's. The estimate follows the breath (measured: up to 5.0 mm and
  // 3.0 deg at its peak, 480x270); what must hold is that it stays within the held-out in-vivo bar's 5 degrees
  // with room, every frame is tracked, and it comes back with the breath instead of drifting.
  synthetic::SyntheticScanOptions options = smallHardScan();
  options.frames = 60;  // one breath
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80;
  options.hardMode.breathingAmplitudeMm = 3;
  options.hardMode.breathingPeriodS = 2;
  options.hardMode.breathingRadiusMm = 40;  // the view is about 77 x 43 mm at 80 mm: only its corners stand still
  options.hardMode.instruments = 2;
  const synthetic::SyntheticScan scan(options);
  const PipelineRun run = reconstruct(scan, ReconstructionParameters{});
  double mm = 0, deg = 0;
  largestMotion(run, mm, deg);
  const Eigen::Matrix4d start = run.frames.front().T_world_camera, end = run.frames.back().T_world_camera;
  const double endMm = (end.block<3, 1>(0, 3) - start.block<3, 1>(0, 3)).norm(), endDeg = rotationDeg(start, end);
  std::printf("still camera, whole view breathing 3 mm with 2 instruments: estimated motion at most %.3f mm, "
              "%.3f deg; after the breath %.3f mm, %.3f deg\n", mm, deg, endMm, endDeg);
  for (const FrameResult& f : run.frames) ASSERT_TRUE(f.tracked) << "frame " << f.frameIndex << ": " << f.trackingMessage;
  EXPECT_LE(deg, 4.0);
  EXPECT_LE(mm, 6.5);
  EXPECT_LE(endMm, 0.5);
  EXPECT_LE(endDeg, 0.3);
}

TEST(RobustTracking, AStillScopeOverInVivoTissueIsTrackedAtEveryFrameNearItsTruePose) {
  // The in-vivo preset (SyntheticInVivo.h) at 360x288: a still scope over dark, blood-red tissue that breathes over
  // the whole view with a lateral slide, a pulse, two instruments at the border, one pressing in, wet highlights,
  // motion blur and interlaced fields. Before the scope's motion prior, frames whose depth the model contradicted
  // (the tissue had moved) were lost although their pose continued the scope's (still) motion.
  synthetic::SyntheticScanOptions options;
  synthetic::applyInVivoPreset(options);
  options.width = 360;
  options.height = 288;
  options.frames = 60;
  options.seed = 3;
  options.supersampling = 1;
  const synthetic::SyntheticScan scan(options);
  const PipelineRun run = reconstruct(scan, ReconstructionParameters{});
  double worstMm = 0, worstDeg = 0;
  int tissueMoving = 0;
  for (const FrameResult& f : run.frames) {
    ASSERT_TRUE(f.tracked) << "frame " << f.frameIndex << ": " << f.trackingMessage;
    const Eigen::Matrix4d truth = scan.T_world_camera(f.frameIndex);
    worstMm = std::max(worstMm, (f.T_world_camera.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).norm());
    worstDeg = std::max(worstDeg, rotationDeg(truth, f.T_world_camera));
    tissueMoving += f.sceneMotion == SceneMotion::Tissue || f.sceneMotion == SceneMotion::Both;
  }
  std::printf("in-vivo preset, still scope, 360x288, 60 frames: worst camera error %.3f mm, %.3f deg; %d frames say "
              "the tissue moved\n", worstMm, worstDeg, tissueMoving);
  EXPECT_LE(worstMm, kInVivoStillMm);
  EXPECT_LE(worstDeg, kInVivoStillDeg);
}

TEST(RobustTracking, FramesWithoutTissueAreLostAndTheCameraIsRelocalised) {
  synthetic::SyntheticScanOptions options = smallHardScan();
  options.frames = 46;
  options.hardMode.cameraOutStart = 20;
  options.hardMode.cameraOutEnd = 32;
  const synthetic::SyntheticScan scan(options);
  const PipelineRun run = reconstruct(scan, ReconstructionParameters{});
  QualityLog log;
  for (const FrameResult& f : run.frames) log.add(f);
  std::printf("camera out 20:32: lost spans %s, relocalised at %s\n", log.lostSpansJson().c_str(),
              log.relocalisationsJson().c_str());
  for (const FrameResult& f : run.frames) {
    const int k = f.frameIndex;
    if (scan.tissueInView(k)) continue;
    EXPECT_FALSE(f.tracked) << "frame " << k << " has no tissue but got a pose";
    EXPECT_FALSE(f.keyFrame);
  }
  ASSERT_EQ(log.lostSpans().size(), 1u);
  EXPECT_EQ(log.lostSpans()[0].first, 20);
  ASSERT_EQ(log.relocalisations().size(), 1u);
  const int back = log.relocalisations()[0];
  EXPECT_GE(back, 32);
  EXPECT_LE(back, 36) << "relocalised within 5 frames of the return";
  // Back in the same world frame: the poses after the return are the true ones.
  double worstMm = 0, worstDeg = 0;
  for (const FrameResult& f : run.frames) {
    if (f.frameIndex < back) continue;
    ASSERT_TRUE(f.tracked) << "frame " << f.frameIndex << ": " << f.trackingMessage;
    const Eigen::Matrix4d truth = scan.T_world_camera(f.frameIndex);
    worstMm = std::max(worstMm, (f.T_world_camera.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).norm());
    worstDeg = std::max(worstDeg, rotationDeg(truth, f.T_world_camera));
    EXPECT_TRUE(f.agreement.measured) << f.frameIndex;
    EXPECT_GT(f.agreement.shareWithin1mm, 0.7) << f.frameIndex;  // 0.76 where the pose is 0.55 mm off
  }
  std::printf("after the return: worst position error %.3f mm, rotation %.3f deg\n", worstMm, worstDeg);
  EXPECT_LT(worstMm, 1.0);
  EXPECT_LT(worstDeg, 0.5);
}

TEST(RobustTracking, MovingTissueAndInstrumentsLeaveTheModel) {
  synthetic::SyntheticScanOptions options = smallHardScan();
  options.frames = 50;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.breathingPeriodS = 1;
  options.hardMode.instruments = 2;
  const synthetic::SyntheticScan scan(options);
  const std::vector<int> frames = scan.tissueFrames();
  const auto score = [&](const PipelineRun& run, double& instrumentShare, double& breathingShare) {
    std::size_t nearInstrument = 0, onBreathing = 0;
    for (const cv::Point3f& p : run.model.cloud.pointsMm) {
      nearInstrument += scan.instruments().distanceMm(cv::Vec3d(p.x, p.y, p.z), frames) <= 1.0;
      onBreathing += scan.breathing().peakDisplacementMm(p.x, p.y) > 1.0;
    }
    instrumentShare = static_cast<double>(nearInstrument) / run.model.size();
    breathingShare = static_cast<double>(onBreathing) / run.model.size();
  };
  const PipelineRun run = reconstruct(scan, ReconstructionParameters{});
  ReconstructionParameters noEvidence;
  noEvidence.fusion.motionPenalty = 0;
  const PipelineRun smeared = reconstruct(scan, noEvidence);
  double instruments = 0, breathing = 0, smearedInstruments = 0, smearedBreathing = 0;
  score(run, instruments, breathing);
  score(smeared, smearedInstruments, smearedBreathing);
  int removed = 0;
  for (const FrameResult& f : run.frames) removed += f.pointsRemoved;
  std::printf("model of %zu points (%d left on motion evidence): %.4f%% within 1 mm of an instrument, %.3f%% where "
              "breathing moves the tissue > 1 mm; without the evidence (%zu points): %.4f%%, %.3f%%\n",
              run.model.size(), removed, 100 * instruments, 100 * breathing, smeared.model.size(),
              100 * smearedInstruments, 100 * smearedBreathing);
  for (const FrameResult& f : run.frames) EXPECT_TRUE(f.tracked) << "frame " << f.frameIndex << ": " << f.trackingMessage;
  EXPECT_LE(instruments, 0.001);
  EXPECT_GT(smearedInstruments, instruments);
  EXPECT_LT(breathing, 0.5 * smearedBreathing);
}

// A breath held near its peak (the ventilator paused from 0.5 s on): the points fused at rest leave as the tissue
// rises, and their markers keep key frames from fusing the tissue within 3 mm of them. Once the tissue has rested
// markerRestFrames frames elsewhere the markers retire, and the next key frames fuse it where it rests; with the
// markers kept for good (markerRestFrames 0) the breathing part stays a hole.
TEST(RobustTracking, ABreathHoldIsFusedWhereTheTissueRests) {
  synthetic::SyntheticScanOptions options = smallHardScan();
  options.frames = 45;
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;  // the scope held still over the breathing part
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80;
  options.hardMode.breathingAmplitudeMm = 2;
  options.hardMode.breathingPeriodS = 1;
  options.hardMode.breathHoldStartS = 0.5;
  options.hardMode.breathHoldEndS = 10;
  const synthetic::SyntheticScan scan(options);
  const synthetic::TissueSurface heldSurface = scan.surface().swollen(scan.breathing().swellAt(0.5));
  // Model points on the breathing part's core (it moves more than 1 mm), and of them those on the held surface (at
  // 480x270 and 80 mm a pixel of disparity is 2.6 mm of depth: the stereo is good to about 0.8 mm here).
  const auto score = [&](const PipelineRun& run, std::size_t& core, std::size_t& onHeld) {
    core = onHeld = 0;
    for (const cv::Point3f& p : run.model.cloud.pointsMm) {
      if (scan.breathing().peakDisplacementMm(p.x, p.y) <= 1.0) continue;
      ++core;
      onHeld += std::abs(p.z - heldSurface.heightMm(p.x, p.y)) <= 1.0;  // half way to the surface at rest
    }
  };
  ReconstructionParameters resting;
  resting.fusion.markerRestFrames = 10;
  ReconstructionParameters forGood;
  forGood.fusion.markerRestFrames = 0;
  const PipelineRun run = reconstruct(scan, resting), kept = reconstruct(scan, forGood);
  std::size_t core = 0, onHeld = 0, keptCore = 0, keptOnHeld = 0;
  score(run, core, onHeld);
  score(kept, keptCore, keptOnHeld);
  std::printf("breath held from 0.5 s: %zu model points on the breathing core, %zu on the held surface (markers kept "
              "for good: %zu, %zu)\n", core, onHeld, keptCore, keptOnHeld);
  for (const FrameResult& f : run.frames) EXPECT_TRUE(f.tracked) << "frame " << f.frameIndex << ": " << f.trackingMessage;
  EXPECT_GT(onHeld, 5 * std::max<std::size_t>(keptOnHeld, 100));
  EXPECT_GT(onHeld, 0.9 * core) << "what the core holds is the held surface";
}
