// Descriptor matching guided by a tracked pose (ProjectionGuidedMatching.h) on the analytic feature scene: the
// matches against the true projections, the distrust of a pose that is off, and bad input.
#include "RefinementTestScene.h"

#include "Core/Error.h"
#include "Refinement/ProjectionGuidedMatching.h"

#include <gtest/gtest.h>

#include <set>

using namespace tissuemosaic;
using namespace tissuemosaic::refinement_test;

namespace {

PinholeIntrinsics intrinsicsOf(const RectifiedGeometry& g) { return {g.focalPx, g.focalPx, g.cxLeftPx, g.cyPx}; }

struct GuidedScene {
  RectifiedGeometry geometry = testGeometry();
  FeatureScene scene{1500, 3};
  Eigen::Matrix4d T_world_camera = truePose(5);
  /// The frame: 0.5 px noise, 4 flipped bits, 200 outliers with random descriptors.
  StereoFeatures frame = scene.observe(T_world_camera, geometry, 0.5, 0.0, 4, 200, 99);

  /// The true pixel of scene point q in the frame.
  Eigen::Vector2d trueProjection(int q) const {
    const Eigen::Matrix4d T = T_world_camera.inverse();
    const Eigen::Vector3d c = T.block<3, 3>(0, 0) * scene.pointsWorldMm[static_cast<std::size_t>(q)] + T.block<3, 1>(0, 3);
    return {geometry.focalPx * c.x() / c.z() + geometry.cxLeftPx, geometry.focalPx * c.y() / c.z() + geometry.cyPx};
  }

  ProjectionGuidedMatches match(const Eigen::Matrix4d& T_world_trackedCamera) const {
    return matchProjectedPoints(scene.pointsWorldMm, scene.descriptors, frame.keypoints, frame.descriptors,
                                T_world_trackedCamera.inverse(), intrinsicsOf(geometry), ProjectionGuidedMatchParameters{});
  }
};

}  // namespace

// A tracked pose off by 0.3 degrees and 0.3 mm (about 3 px): nearly every feature the frame sees is found, every
// match is the true one, and the matches are trusted.
TEST(ProjectionGuidedMatching, FindsTheTrueMatchesNearTheProjections) {
  const GuidedScene s;
  std::mt19937 random(5);
  const ProjectionGuidedMatches found = s.match(perturb(s.T_world_camera, 0.3, 0.3, random));
  const int seen = s.frame.withDepth - 200;
  int correct = 0;
  std::set<int> trains;
  for (const ProjectionGuidedMatch& m : found.matches) {
    const cv::Point2f& px = s.frame.keypoints[static_cast<std::size_t>(m.train)].pt;
    correct += (Eigen::Vector2d(px.x, px.y) - s.trueProjection(m.query)).norm() < 2.5;  // 5 sigma of the noise
    trains.insert(m.train);
  }
  std::printf("%zu matches (%d candidates) of %d features seen, %d correct, median offset (%.2f, %.2f) px\n",
              found.matches.size(), found.candidates, seen, correct, found.medianOffsetPx.x(), found.medianOffsetPx.y());
  EXPECT_TRUE(found.trusted);
  EXPECT_GT(static_cast<int>(found.matches.size()), 0.95 * seen);
  EXPECT_EQ(correct, static_cast<int>(found.matches.size()));
  EXPECT_EQ(trains.size(), found.matches.size());  // each keypoint matched once
  EXPECT_GT(found.medianOffsetPx.norm(), 0.5);      // the pose error shows as a common offset ...
  EXPECT_LT(found.medianOffsetPx.norm(), 8.0);      // ... of a few pixels
  for (std::size_t i = 1; i < found.matches.size(); ++i) EXPECT_LT(found.matches[i - 1].query, found.matches[i].query);
}

// A tracked pose off by 3 degrees moves the true matches out of the search radius: what remains is not trusted.
TEST(ProjectionGuidedMatching, DistrustsAPoseThatIsOff) {
  const GuidedScene s;
  std::mt19937 random(5);
  for (int trial = 0; trial < 5; ++trial) {
    const ProjectionGuidedMatches found = s.match(perturb(s.T_world_camera, 3.0, 2.0, random));
    std::printf("trial %d: %zu agreeing of %d candidates, median offset (%.1f, %.1f) px\n", trial, found.matches.size(),
                found.candidates, found.medianOffsetPx.x(), found.medianOffsetPx.y());
    EXPECT_FALSE(found.trusted) << "trial " << trial;
  }
}

TEST(ProjectionGuidedMatching, RefusesInconsistentInput) {
  const GuidedScene s;
  const PinholeIntrinsics k = intrinsicsOf(s.geometry);
  const Eigen::Matrix4d T = s.T_world_camera.inverse();
  const ProjectionGuidedMatchParameters parameters;
  EXPECT_THROW(matchProjectedPoints(s.scene.pointsWorldMm, s.scene.descriptors.rowRange(0, 10), s.frame.keypoints,
                                    s.frame.descriptors, T, k, parameters), Error);
  EXPECT_THROW(matchProjectedPoints(s.scene.pointsWorldMm, s.scene.descriptors, s.frame.keypoints,
                                    s.frame.descriptors.colRange(0, 16), T, k, parameters), Error);
  ProjectionGuidedMatchParameters noRadius;
  noRadius.searchRadiusPx = 0;
  EXPECT_THROW(matchProjectedPoints(s.scene.pointsWorldMm, s.scene.descriptors, s.frame.keypoints,
                                    s.frame.descriptors, T, k, noRadius), Error);
  // Nothing to match is no error.
  EXPECT_TRUE(matchProjectedPoints({}, cv::Mat(0, 32, CV_8U), s.frame.keypoints, s.frame.descriptors, T, k, parameters)
                  .matches.empty());
}
