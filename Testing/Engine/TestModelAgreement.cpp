// The model agreement (Fusion/ModelAgreement.h) and the motion evidence on analytic planes: a frame agrees with the
// model it was fused into and its median difference follows its depth noise; a wrong pose collapses it; a model out
// of view is not judged. Points that a frame contradicts by more than the threshold lose weight and leave; points
// with something well in front of them (an instrument) do not, unless fused once and seen through for long (a stereo
// error behind the tissue); static points keep their weight.
#include "FusionTestScene.h"

#include "Core/Error.h"
#include "Fusion/PointFusion.h"

#include <gtest/gtest.h>

using namespace tissuemosaic;
using namespace tissuemosaic::test;

namespace {

constexpr int kStride = 2;

/// The plane Z = 100 mm with the part x < splitXMm (world) at zOtherMm instead (e.g. tissue that moved), as a
/// left-view disparity seen from T_world_camera.
cv::Mat splitPlaneDisparity(const RectifiedGeometry& g, const Eigen::Matrix4d& T_world_camera, double splitXMm,
                            double zOtherMm) {
  PlanePatch still, moved;
  moved.offsetMm = zOtherMm;
  cv::Mat disparity = patchDisparity(g, still, T_world_camera);
  const cv::Mat other = patchDisparity(g, moved, T_world_camera);
  for (int y = 0; y < g.imageSize.height; ++y) {
    for (int x = 0; x < g.imageSize.width; ++x) {
      const double xWorld = (x - g.cxLeftPx) * 100.0 / g.focalPx + T_world_camera(0, 3);  // where the ray meets Z = 100
      if (xWorld < splitXMm) disparity.at<float>(y, x) = other.at<float>(y, x);
    }
  }
  return disparity;
}

/// A model of the plane Z = 100 fused `times` times from the identity pose (every point's weight = times).
PointFusion fusedPlane(const RectifiedGeometry& g, int times, const FusionParameters& parameters = {}) {
  PointFusion fusion(g, parameters, Device::Cpu);
  for (int i = 0; i < times; ++i) fusion.integrate(patchMeasurement(g, PlanePatch{}, Eigen::Matrix4d::Identity()), Eigen::Matrix4d::Identity());
  return fusion;
}

/// Half the width (mm) of the plane Z = 100 seen from the identity pose.
double halfViewWidthMm(const RectifiedGeometry& g) { return 0.5 * g.imageSize.width * 100.0 / g.focalPx; }

/// The world x of the edge of the view's left quarter on that plane (splitPlaneDisparity's split).
double leftQuarterEdgeMm(const RectifiedGeometry& g) { return -0.5 * halfViewWidthMm(g); }

std::size_t pointsWithXBelow(const ModelPoints& model, double xMm) {
  std::size_t n = 0;
  for (const cv::Point3f& p : model.cloud.pointsMm) n += p.x < xMm;
  return n;
}

}  // namespace

TEST(ModelAgreement, AFrameAgreesWithItsModelAndNotWithAWrongPose) {
  const RectifiedGeometry g = fusionGeometry();
  const PointFusion fusion = fusedPlane(g, 1);
  const Eigen::Matrix4d identity = Eigen::Matrix4d::Identity();
  const AgreementParameters limits;

  // The frame it was fused from, with 0.3 mm of depth noise: median |difference| of N(0, 0.3) is 0.674 * 0.3.
  cv::RNG rng(7);
  const cv::Mat noisy = patchDisparity(g, PlanePatch{}, identity, 0.3, &rng);
  const ModelAgreement good = fusion.measureAgreement(noisy, identity, kStride);
  std::printf("agreement at the true pose, 0.3 mm noise: %d of %d samples overlap, median %.3f mm, %.4f within 1 mm\n",
              good.overlapSamples, good.measuredSamples, good.medianDepthDifferenceMm, good.shareWithin1mm);
  ASSERT_TRUE(good.measured);
  EXPECT_EQ(good.measuredSamples, (g.imageSize.width / kStride) * (g.imageSize.height / kStride));
  EXPECT_GT(good.overlap(), 0.95);
  EXPECT_NEAR(good.medianDepthDifferenceMm, 0.674 * 0.3, 0.02);
  EXPECT_NEAR(good.shareWithin1mm, 0.9991, 0.001);  // P(|N(0, 0.3)| <= 1) = 0.99914
  EXPECT_EQ(limits.level(good), AgreementLevel::Good);
  EXPECT_FALSE(limits.collapsed(good));

  // The same frame at a pose 5 mm off along the view: every sample 5 mm off.
  const ModelAgreement off = fusion.measureAgreement(noisy, cameraPose({0, 0, 5}), kStride);
  ASSERT_TRUE(off.measured);
  EXPECT_NEAR(off.medianDepthDifferenceMm, 5.0, 0.1);
  EXPECT_LT(off.shareWithin1mm, 0.01);
  EXPECT_EQ(limits.level(off), AgreementLevel::Poor);
  EXPECT_TRUE(limits.collapsed(off));
  // 1.5 mm off: not collapsed (tissue can move that much), but red.
  const ModelAgreement shifted = fusion.measureAgreement(noisy, cameraPose({0, 0, 1.5}), kStride);
  EXPECT_FALSE(limits.collapsed(shifted));
  EXPECT_EQ(limits.level(shifted), AgreementLevel::Poor);

  // Looking away from the model: nothing to compare, nothing judged.
  const ModelAgreement away = fusion.measureAgreement(noisy, cameraPose({0, 0, 0}, Eigen::Vector3d::UnitY(), 90), kStride);
  EXPECT_FALSE(away.measured);
  EXPECT_EQ(away.overlapSamples, 0);
  EXPECT_EQ(limits.level(away), AgreementLevel::None);
  EXPECT_FALSE(limits.collapsed(away));
  // No model yet: not measured either.
  const PointFusion empty(g, FusionParameters{}, Device::Cpu);
  EXPECT_FALSE(empty.measureAgreement(noisy, identity, kStride).measured);
  EXPECT_THROW(fusion.measureAgreement(cv::Mat(10, 10, CV_32F), identity, kStride), Error);
  EXPECT_THROW(fusion.measureAgreement(noisy, identity, 0), Error);
}

TEST(ModelAgreement, PointsThatKeepMovingLeaveTheModelAndStillOnesStay) {
  const RectifiedGeometry g = fusionGeometry();
  PointFusion fusion = fusedPlane(g, 5);
  const Eigen::Matrix4d identity = Eigen::Matrix4d::Identity();
  const std::size_t before = fusion.pointCount();
  const double split = leftQuarterEdgeMm(g);  // the left quarter of the view moves
  const std::size_t movingBefore = pointsWithXBelow(fusion.download(), split - 0.5);
  ASSERT_GT(movingBefore, before / 6);

  // The left quarter rose 2 mm toward the scope (breathing). The first contradicting frame only raises the motion
  // evidence (one frame's stereo outlier costs nothing); each later one takes 1 of the weight of 5.
  const cv::Mat risen = splitPlaneDisparity(g, identity, split, 98.0);
  for (int frame = 0; frame < 5; ++frame) {
    const ModelAgreement a = fusion.measureAgreement(risen, identity, kStride);
    ASSERT_GE(a.shareWithin1mm, 0.7);
    EXPECT_EQ(fusion.updateMotion(risen, identity, a), 0) << "frame " << frame << ": weight left";
  }
  const ModelAgreement last = fusion.measureAgreement(risen, identity, kStride);
  EXPECT_NEAR(fusion.motionThresholdMm(last), FusionParameters{}.motionMinThresholdMm, 1e-12);
  const int removed = fusion.updateMotion(risen, identity, last);
  const ModelPoints model = fusion.download();
  std::printf("motion: %d of %zu points left after 6 frames; %zu still points kept\n", removed, before, model.size());
  EXPECT_GE(removed, static_cast<int>(movingBefore));
  EXPECT_EQ(pointsWithXBelow(model, split - 0.5), 0u) << "moved points left the model";
  EXPECT_EQ(fusion.pointCount(), model.size());
  for (float w : model.weights) ASSERT_EQ(w, 5.0f) << "still points keep their weight";
  // The points that left stay as markers of moving tissue: the next key frame, seeing the risen tissue within
  // movedTissueRadiusMm of them, does not fuse it again; the still part merges as usual.
  const SurfaceMeasurement risenSurface = measureSurface(risen, uniformImage(g), g, Device::Cpu);
  const FusionStats refused = fusion.integrate(risenSurface, identity);
  EXPECT_EQ(pointsWithXBelow(fusion.download(), split - 0.5), 0u) << "moved tissue fused again";
  EXPECT_EQ(refused.added, 0);
  EXPECT_GE(refused.merged, static_cast<int>(model.size()) - 10);

  // With the markers off (radius 0), the same key frame adds the risen tissue where the model has no points.
  FusionParameters noMarkers;
  noMarkers.movedTissueRadiusMm = 0;
  PointFusion unmarked = fusedPlane(g, 5, noMarkers);
  for (int frame = 0; frame < 6; ++frame) unmarked.updateMotion(risen, identity, unmarked.measureAgreement(risen, identity, kStride));
  ASSERT_EQ(pointsWithXBelow(unmarked.download(), split - 0.5), 0u);
  unmarked.integrate(risenSurface, identity);
  EXPECT_GE(pointsWithXBelow(unmarked.download(), split - 0.5), movingBefore / 2);
}

// Tissue that left the model (here pushed 2 mm toward the scope) and then comes back and rests is fused again once
// markerRestFrames frames in a row have measured it back at its markers; tissue that rests where it was pushed is
// fused there once as many frames have measured it there; tissue that keeps moving back and forth (breathing) does
// neither; with markerRestFrames 0 the markers stay for good.
TEST(ModelAgreement, TissueThatComesToRestIsFusedAgainAndBreathingTissueIsNot) {
  const RectifiedGeometry g = fusionGeometry();
  const Eigen::Matrix4d identity = Eigen::Matrix4d::Identity();
  const double split = leftQuarterEdgeMm(g);
  const cv::Mat risen = splitPlaneDisparity(g, identity, split, 98.0);
  const cv::Mat still = splitPlaneDisparity(g, identity, split, 100.0);
  const SurfaceMeasurement stillSurface = measureSurface(still, uniformImage(g), g, Device::Cpu);
  constexpr int kRestFrames = 4;
  FusionParameters resting;
  resting.markerRestFrames = kRestFrames;
  const auto frames = [&](PointFusion& fusion, const cv::Mat& disparity, int count) {
    for (int frame = 0; frame < count; ++frame) {
      fusion.updateMotion(disparity, identity, fusion.measureAgreement(disparity, identity, kStride));
    }
  };

  PointFusion fusion = fusedPlane(g, 5, resting);
  const std::size_t before = fusion.pointCount();
  const std::size_t moving = pointsWithXBelow(fusion.download(), split - 0.5);
  frames(fusion, risen, 6);
  ASSERT_EQ(pointsWithXBelow(fusion.download(), split - 0.5), 0u);
  const std::size_t markers = fusion.movedTissueMarkerCount();
  ASSERT_GE(markers, moving);
  // Back for one frame fewer than needed: still markers, and a key frame does not fuse the tissue there.
  frames(fusion, still, kRestFrames - 1);
  EXPECT_EQ(fusion.movedTissueMarkerCount(), markers);
  EXPECT_EQ(fusion.integrate(stillSurface, identity).added, 0);
  EXPECT_EQ(pointsWithXBelow(fusion.download(), split - 0.5), 0u);
  // One more: every marker is a point again, with the weight of one observation, and the next key frame merges.
  frames(fusion, still, 1);
  EXPECT_EQ(fusion.movedTissueMarkerCount(), 0u);
  EXPECT_EQ(fusion.pointCount(), before);
  const FusionStats merged = fusion.integrate(stillSurface, identity);
  EXPECT_EQ(merged.added, 0);
  const ModelPoints model = fusion.download();
  std::size_t revived = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (model.cloud.pointsMm[i].x >= split - 0.5) continue;
    ++revived;
    EXPECT_EQ(model.weights[i], 2.0f) << "revived, then merged once";
    EXPECT_NEAR(model.cloud.pointsMm[i].z, 100.0, 1e-3);
  }
  std::printf("rest: %zu markers, %zu points live again after %d frames at rest\n", markers, revived, kRestFrames);
  EXPECT_EQ(revived, moving);

  // Breathing: back at rest for kRestFrames - 1 frames, then risen again, over and over: never fused again.
  PointFusion breathing = fusedPlane(g, 5, resting);
  frames(breathing, risen, 6);
  const std::size_t breathingMarkers = breathing.movedTissueMarkerCount();
  for (int breath = 0; breath < 5; ++breath) {
    frames(breathing, still, kRestFrames - 1);
    frames(breathing, risen, 1);
  }
  EXPECT_EQ(breathing.movedTissueMarkerCount(), breathingMarkers);
  EXPECT_EQ(pointsWithXBelow(breathing.download(), split - 0.5), 0u);

  // Held 2 mm toward the scope (a held breath): one frame fewer than needed and the markers still keep a key frame
  // from fusing the tissue there; one more and they retire, and the key frame fuses it where it rests.
  PointFusion held = fusedPlane(g, 5, resting);
  frames(held, risen, 6);
  const std::size_t heldMarkers = held.movedTissueMarkerCount();
  const SurfaceMeasurement risenSurface = measureSurface(risen, uniformImage(g), g, Device::Cpu);
  frames(held, risen, kRestFrames - 1);
  EXPECT_EQ(held.movedTissueMarkerCount(), heldMarkers);
  EXPECT_EQ(held.integrate(risenSurface, identity).added, 0);
  frames(held, risen, 1);
  EXPECT_EQ(held.movedTissueMarkerCount(), 0u);
  EXPECT_EQ(held.retiredMarkerCount(), heldMarkers);
  EXPECT_EQ(held.pointCount(), before - heldMarkers);
  const FusionStats added = held.integrate(risenSurface, identity);
  const ModelPoints heldModel = held.download();
  std::size_t fusedWhereItRests = 0;
  for (const cv::Point3f& point : heldModel.cloud.pointsMm) {
    fusedWhereItRests += point.x < split - 0.5 && std::abs(point.z - 98.0) < 1e-3;
  }
  std::printf("held: %zu markers retired, %d points added, %zu of them where the tissue rests\n", heldMarkers,
              added.added, fusedWhereItRests);
  EXPECT_GE(fusedWhereItRests, moving / 2);

  // markerRestFrames 0: the markers stay whatever the frames show.
  FusionParameters forGood;
  forGood.markerRestFrames = 0;
  PointFusion kept = fusedPlane(g, 5, forGood);
  frames(kept, risen, 6);
  const std::size_t keptMarkers = kept.movedTissueMarkerCount();
  frames(kept, still, 20);
  frames(kept, risen, 20);
  EXPECT_EQ(kept.movedTissueMarkerCount(), keptMarkers);
  EXPECT_EQ(kept.retiredMarkerCount(), 0u);
  EXPECT_EQ(pointsWithXBelow(kept.download(), split - 0.5), 0u);
}

TEST(ModelAgreement, WhatPassesInFrontIsNoEvidenceAndWithoutPenaltyNothingLeaves) {
  const RectifiedGeometry g = fusionGeometry();
  const Eigen::Matrix4d identity = Eigen::Matrix4d::Identity();
  const double split = leftQuarterEdgeMm(g);

  // An instrument 10 mm in front of the left quarter, held there: beyond the occlusion margin, so no point that two
  // key frames agreed on loses weight (points fused once: ModelAgreement.AStereoErrorBehindTheTissue...).
  PointFusion covered = fusedPlane(g, 2);
  const cv::Mat occluded = splitPlaneDisparity(g, identity, split, 90.0);
  for (int frame = 0; frame < 3 * FusionParameters{}.seenThroughFrames; ++frame) {
    const ModelAgreement a = covered.measureAgreement(occluded, identity, kStride);
    EXPECT_EQ(covered.updateMotion(occluded, identity, a), 0);
  }
  for (const float weight : covered.download().weights) ASSERT_EQ(weight, 2.0f);
  // One passing over points fused once: fewer frames than seenThroughFrames, no weight lost.
  PointFusion fusion = fusedPlane(g, 1);
  for (int frame = 0; frame + 1 < FusionParameters{}.seenThroughFrames; ++frame) {
    const ModelAgreement a = fusion.measureAgreement(occluded, identity, kStride);
    EXPECT_EQ(fusion.updateMotion(occluded, identity, a), 0);
  }
  for (const float weight : fusion.download().weights) ASSERT_EQ(weight, 1.0f);
  fusion = fusedPlane(g, 1);
  // Seen through: the left quarter now measured 3 mm behind the points (they float in free space). One such frame
  // is no more than a stereo outlier; the second in a row takes the weight of 1.
  const cv::Mat behind = splitPlaneDisparity(g, identity, split, 103.0);
  const ModelAgreement a = fusion.measureAgreement(behind, identity, kStride);
  EXPECT_EQ(fusion.updateMotion(behind, identity, a), 0) << "a single contradicting frame costs no weight";
  EXPECT_GT(fusion.updateMotion(behind, identity, a), 1000);
  EXPECT_EQ(pointsWithXBelow(fusion.download(), split - 0.5), 0u);

  // motionPenalty 0 switches the evidence off: the same frame removes nothing.
  FusionParameters off;
  off.motionPenalty = 0;
  PointFusion kept = fusedPlane(g, 1, off);
  const std::size_t count = kept.pointCount();
  for (int frame = 0; frame < 3; ++frame) {
    EXPECT_EQ(kept.updateMotion(behind, identity, kept.measureAgreement(behind, identity, kStride)), 0);
  }
  EXPECT_EQ(kept.pointCount(), count);
  // A frame that agrees too little with the model (its pose or the whole view may be off) gives no evidence.
  PointFusion doubtful = fusedPlane(g, 1);
  const cv::Mat mostlyMoved = splitPlaneDisparity(g, identity, 0.8 * halfViewWidthMm(g), 103.0);
  const ModelAgreement poor = doubtful.measureAgreement(mostlyMoved, identity, kStride);
  ASSERT_LT(poor.shareWithin1mm, FusionParameters{}.motionMinAgreementShare);
  for (int frame = 0; frame < 3; ++frame) EXPECT_EQ(doubtful.updateMotion(mostlyMoved, identity, poor), 0);
}

// A stereo error fused behind the tissue (here a later key frame measures the left quarter 10 mm too deep, behind the
// tissue the model holds) is never measured again where it lies: later frames see the model's own surface in front
// of it. Fused once and seen through for seenThroughFrames frames in a row, it leaves without a marker; one frame
// fewer costs nothing, nor anything to a point two key frames agreed on, nor anything under an instrument held in
// front of the tissue (nearer than the model's surface).
TEST(ModelAgreement, AStereoErrorBehindTheTissueLeavesOnceFramesKeepSeeingThroughIt) {
  const RectifiedGeometry g = fusionGeometry();
  const Eigen::Matrix4d identity = Eigen::Matrix4d::Identity();
  const double split = leftQuarterEdgeMm(g);
  const cv::Mat withError = splitPlaneDisparity(g, identity, split, 110.0);
  const cv::Mat tissue = splitPlaneDisparity(g, identity, split, 100.0);
  const cv::Mat instrument = splitPlaneDisparity(g, identity, split, 90.0);
  const SurfaceMeasurement withErrorSurface = measureSurface(withError, uniformImage(g), g, Device::Cpu);
  const SurfaceMeasurement tissueSurface = measureSurface(tissue, uniformImage(g), g, Device::Cpu);
  const FusionParameters parameters;
  ASSERT_EQ(parameters.seenThroughFrames, 5);
  const auto frames = [&](PointFusion& fusion, const cv::Mat& disparity, int count) {
    for (int frame = 0; frame < count; ++frame) {
      fusion.updateMotion(disparity, identity, fusion.measureAgreement(disparity, identity, kStride));
    }
  };
  const auto countWhere = [&](const PointFusion& fusion, double zMm) {
    std::size_t n = 0;
    for (const cv::Point3f& p : fusion.download().cloud.pointsMm) n += p.x < split - 0.5 && std::abs(p.z - zMm) < 1e-3;
    return n;
  };
  const auto modelWithError = [&](const FusionParameters& p, int errorKeyFrames) {
    PointFusion fusion(g, p, Device::Cpu);
    fusion.integrate(tissueSurface, identity);
    for (int k = 0; k < errorKeyFrames; ++k) fusion.integrate(withErrorSurface, identity);
    return fusion;
  };

  PointFusion once = modelWithError(parameters, 1);
  const std::size_t errors = countWhere(once, 110.0), tissuePoints = countWhere(once, 100.0);
  ASSERT_GT(errors, 1000u);
  ASSERT_GT(tissuePoints, 1000u);
  frames(once, tissue, parameters.seenThroughFrames - 1);
  EXPECT_EQ(countWhere(once, 110.0), errors) << "seen through for fewer frames";
  frames(once, tissue, 1);
  std::printf("%zu points fused 10 mm behind the tissue left after %d frames; %zu retired, %zu moved-tissue markers; "
              "%zu tissue points kept\n", errors, parameters.seenThroughFrames, once.retiredMarkerCount(),
              once.movedTissueMarkerCount(), countWhere(once, 100.0));
  EXPECT_EQ(countWhere(once, 110.0), 0u);
  EXPECT_EQ(countWhere(once, 100.0), tissuePoints);
  EXPECT_GE(once.retiredMarkerCount(), errors * 9 / 10) << "retired: they keep nothing from being fused";

  // An instrument held 10 mm in front of tissue fused once: it is nearer than the model's surface, no evidence.
  PointFusion covered = modelWithError(parameters, 0);
  frames(covered, instrument, 3 * parameters.seenThroughFrames);
  EXPECT_EQ(countWhere(covered, 100.0), tissuePoints);
  // Two key frames made the error (weight 2): kept, as any point two key frames agreed on.
  PointFusion twice = modelWithError(parameters, 2);
  frames(twice, tissue, 3 * parameters.seenThroughFrames);
  EXPECT_EQ(countWhere(twice, 110.0), errors);
  // seenThroughFrames 0: the error stays.
  FusionParameters off;
  off.seenThroughFrames = 0;
  PointFusion kept = modelWithError(off, 1);
  frames(kept, tissue, 3 * parameters.seenThroughFrames);
  EXPECT_EQ(countWhere(kept, 110.0), errors);
}

TEST(ModelAgreement, ParametersAreValidatedAndRoundTrip) {
  AgreementParameters p;
  p.goodShare = 0.9;
  p.lostMedianMm = 4;
  cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  p.write(out);
  const std::string text = out.releaseAndGetString();
  cv::FileStorage in(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  const AgreementParameters q = AgreementParameters::read(in["agreement"]);
  EXPECT_EQ(q.goodShare, 0.9);
  EXPECT_EQ(q.lostMedianMm, 4.0);
  AgreementParameters bad;
  bad.poorShare = 0.95;  // above goodShare
  EXPECT_THROW(bad.validate(), Error);
  bad = AgreementParameters{};
  bad.sampleStridePx = 0;
  EXPECT_THROW(bad.validate(), Error);
  FusionParameters fusion;
  fusion.motionMinAgreementShare = 1.5;
  EXPECT_THROW(fusion.validate(), Error);
  fusion = FusionParameters{};
  fusion.markerRestFrames = -1;
  EXPECT_THROW(fusion.validate(), Error);
  fusion.markerRestFrames = 90;
  fusion.seenThroughFrames = -1;
  EXPECT_THROW(fusion.validate(), Error);
  fusion.seenThroughFrames = 12;
  cv::FileStorage fusionOut(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fusion.write(fusionOut);
  cv::FileStorage fusionIn(fusionOut.releaseAndGetString(), cv::FileStorage::READ | cv::FileStorage::MEMORY);
  const FusionParameters read = FusionParameters::read(fusionIn["fusion"]);
  EXPECT_EQ(read.markerRestFrames, 90);
  EXPECT_EQ(read.seenThroughFrames, 12);
}
