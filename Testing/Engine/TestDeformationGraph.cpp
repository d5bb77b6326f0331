// The embedded deformation graph (Logic/Engine/Deformation) against exact answers and the generator's ground truth:
// nodes cover the points they were made from, weights blend to 1, the rest graph and a graph moved rigidly warp
// exactly; fitted to the synthetic scans' breathing tissue (point-to-plane, associated as ICP does) the warped rest
// surface lies on the frame's true surface while the still tissue stays still.
#include "Deformation/DeformationFit.h"
#include "Deformation/DeformationGraph.h"
#include "Deformation/InfluenceCache.h"
#include "Deformation/RigidPart.h"

#include "SyntheticBreathing.h"
#include "SyntheticScan.h"
#include "TissueSurface.h"

#include "Core/Error.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

using namespace tissuemosaic;
using namespace tissuemosaic::synthetic;

namespace {

using PointList = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;

PointList gridOnPlane(double halfWidthMm, double stepMm) {
  PointList points;
  for (double y = -halfWidthMm; y <= halfWidthMm; y += stepMm)
    for (double x = -halfWidthMm; x <= halfWidthMm; x += stepMm) points.emplace_back(x, y, 0.1 * x);
  return points;
}

}  // namespace

TEST(DeformationGraph, NodesCoverEveryPointAndWeightsBlendToOne) {
  DeformationGraphParameters parameters;
  parameters.nodeSpacingMm = 5;
  DeformationGraph graph(parameters);
  const PointList points = gridOnPlane(30, 0.5);
  const int added = graph.cover(points);
  EXPECT_EQ(added, graph.nodeCount());
  EXPECT_GT(graph.nodeCount(), 20);
  EXPECT_LT(graph.nodeCount(), 400);
  EXPECT_EQ(graph.cover(points), 0) << "covered points add no node";
  for (const Eigen::Vector3d& p : points) {
    double nearest = 1e9;
    for (const DeformationNode& node : graph.nodes()) nearest = std::min(nearest, (node.positionMm - p).norm());
    ASSERT_LE(nearest, parameters.nodeSpacingMm * std::sqrt(3.0)) << "a point far from every node";
    const NodeInfluence influence = graph.influence(p);
    ASSERT_GE(influence.count, 1);
    double sum = 0;
    for (int n = 0; n < influence.count; ++n) sum += influence.weight[n];
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_LT((graph.warp(p) - p).norm(), 1e-12) << "the graph at rest moves nothing";
  }
  for (const auto& list : graph.neighbours()) EXPECT_EQ(static_cast<int>(list.size()), parameters.neighbourNodes);
  EXPECT_EQ(graph.influence(Eigen::Vector3d(500, 0, 0)).count, 0) << "far from the model: no node moves it";
}

TEST(DeformationGraph, NodesMovedByOneRigidMotionMovePointsByIt) {
  DeformationGraph graph;
  const PointList points = gridOnPlane(25, 1.0);
  graph.cover(points);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d T(3, -1, 2);
  for (DeformationNode& node : graph.nodes()) {  // x -> R x + T written as each node's motion about itself
    node.rotation = R;
    node.translationMm = R * node.positionMm + T - node.positionMm;
  }
  for (const Eigen::Vector3d& p : points) ASSERT_LT((graph.warp(p) - (R * p + T)).norm(), 1e-9);
  const Eigen::Vector3d n(0, 0.6, 0.8);
  EXPECT_LT((graph.warpNormal(n, graph.influence(points[40])) - R * n).norm(), 1e-9);
}

using Points3 = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;

TEST(DeformationGraph, InfluencesKeptBetweenFramesEqualFreshOnes) {
  // A grid of points, a graph over its first half, then over all: the cache finds the influences of the points near
  // the new nodes again and keeps the rest, and every influence equals the graph's own.
  Points3 points;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 40; ++x) points.emplace_back(x * 1.0, y * 1.0, 0.1 * x);
  const Points3 half(points.begin(), points.begin() + 400);
  DeformationGraph graph;
  graph.cover(half);
  InfluenceCache cache;
  EXPECT_EQ(cache.update(graph, half), 400);
  EXPECT_EQ(cache.update(graph, half), 0) << "nothing changed: nothing found again";
  graph.cover(points);
  const int foundAgain = cache.update(graph, points);
  EXPECT_GE(foundAgain, 400) << "the new points";
  EXPECT_LT(foundAgain, 800) << "points far from the new nodes are kept";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const NodeInfluence fresh = graph.influence(points[i]);
    ASSERT_EQ(cache[i].count, fresh.count) << "point " << i;
    for (int n = 0; n < fresh.count; ++n) {
      ASSERT_EQ(cache[i].node[n], fresh.node[n]) << "point " << i;
      ASSERT_EQ(cache[i].weight[n], fresh.weight[n]) << "point " << i;
    }
  }
}

TEST(DeformationGraph, TheRigidPartIgnoresAPatchThatMovesOnItsOwn) {
  // Nodes over a 60 x 40 mm patch moved by one rigid motion (1 degree, 0.8 mm), a disc among them lifted 3 mm more:
  // the rigid part is the common motion, not pulled by the disc.
  Eigen::Matrix4d truth = Eigen::Matrix4d::Identity();
  truth.topLeftCorner<3, 3>() = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix();
  truth.topRightCorner<3, 1>() = Eigen::Vector3d(0.5, -0.4, 0.5);
  Points3 rest, live;
  std::vector<double> weights;
  for (double y = -20; y <= 20; y += 4) {
    for (double x = -30; x <= 30; x += 4) {
      const Eigen::Vector3d g(x, y, 80 + 0.05 * x * x / 10);
      Eigen::Vector3d moved = truth.topLeftCorner<3, 3>() * g + truth.topRightCorner<3, 1>();
      if (std::hypot(x - 10, y) < 10) moved.z() -= 3.0;  // the breathing disc, toward the scope
      rest.push_back(g);
      live.push_back(moved);
      weights.push_back(1.0 + 0.1 * (static_cast<int>(x) % 3));
    }
  }
  const Eigen::Matrix4d found = robustRigidMotion(rest, live, weights, 1.0);
  double worstMm = 0;
  for (const Eigen::Vector3d& g : rest) {
    const Eigen::Vector3d a = found.topLeftCorner<3, 3>() * g + found.topRightCorner<3, 1>();
    const Eigen::Vector3d b = truth.topLeftCorner<3, 3>() * g + truth.topRightCorner<3, 1>();
    worstMm = std::max(worstMm, (a - b).norm());
  }
  EXPECT_LT(worstMm, 1e-6) << "the disc pulled the rigid part";
  // Fewer than three points: no rigid part.
  EXPECT_TRUE(robustRigidMotion({rest[0], rest[1]}, {live[0], live[1]}, {1.0, 1.0}, 1.0).isIdentity());
}

TEST(DeformationGraph, InvalidParametersAreRefused) {
  DeformationGraphParameters p;
  p.nodeSpacingMm = 0;
  EXPECT_THROW(DeformationGraph{p}, Error);
  DeformationFitParameters fit;
  fit.huberMm = -1;
  DeformationGraph graph;
  EXPECT_THROW(fitDeformation(graph, {}, fit), Error);
}

TEST(DeformationFit, NoCorrespondencesLeaveTheGraphAtRest) {
  DeformationGraph graph;
  graph.cover(gridOnPlane(20, 1.0));
  const DeformationFitResult result = fitDeformation(graph, {});
  EXPECT_EQ(result.correspondences, 0);
  for (const DeformationNode& node : graph.nodes()) EXPECT_EQ(node.translationMm.norm(), 0.0);
}

namespace {

/// A still scope over tissue whose middle breathes 3 mm toward the scope (flat top 10 mm, still beyond 18 mm).
SyntheticScanOptions breathingScan() {
  SyntheticScanOptions options;
  options.width = 160;
  options.height = 120;
  options.frames = 40;
  options.seed = 7;
  options.supersampling = 1;
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80;
  options.hardMode.breathingAmplitudeMm = 3;
  options.hardMode.breathingPeriodS = 2;  // the peak at 1 s: frame 30 at 30 fps
  options.hardMode.breathingRadiusMm = 18;
  return options;
}

}  // namespace

TEST(DeformationFit, TheWarpedRestSurfaceFollowsBreathingTissueToItsTrueSurface) {
  const SyntheticScan scan(breathingScan());
  const int frame = 30;
  const TissueSurface& rest = scan.surface();
  const TissueSurface now = scan.surfaceAt(frame);
  const SurfaceSwell& swell = scan.breathing().shape();
  // The rest surface around the breathing part, out to where the tissue is still.
  PointList canonical;
  DeformationCorrespondences correspondences;
  for (double dy = -26; dy <= 26; dy += 1.0) {
    for (double dx = -26; dx <= 26; dx += 1.0) {
      const double x = swell.centreXMm + dx, y = swell.centreYMm + dy;
      canonical.emplace_back(x, y, rest.heightMm(x, y));
    }
  }
  PointList restNormals;
  for (const Eigen::Vector3d& p : canonical) {
    const cv::Vec3d n = rest.normal(p.x(), p.y());
    restNormals.emplace_back(n[0], n[1], n[2]);
  }
  DeformationGraph graph;  // the defaults: nodes every 4 mm
  graph.cover(canonical, restNormals);
  const auto distanceToTruth = [&](const Eigen::Vector3d& p) { return now.distanceMm(p.x(), p.y(), p.z()); };
  double before2 = 0;
  for (const Eigen::Vector3d& p : canonical) before2 += std::pow(distanceToTruth(p), 2);
  const double beforeRms = std::sqrt(before2 / canonical.size());
  ASSERT_GT(beforeRms, 1.0) << "the tissue must have moved for the test to mean anything";

  // ICP-style: associate each warped point with the true surface straight below or above it (the dense depth's
  // part: point to plane), add feature matches (point to point), fit, repeat.
  DeformationFitResult fit;
  for (int round = 0; round < 4; ++round) {
    correspondences.clear();
    for (const Eigen::Vector3d& p : canonical) {
      const Eigen::Vector3d live = graph.warp(p);
      DeformationCorrespondence c;
      c.canonicalMm = p;
      c.targetMm = Eigen::Vector3d(live.x(), live.y(), now.heightMm(live.x(), live.y()));
      const cv::Vec3d n = now.normal(live.x(), live.y());
      c.targetNormal = Eigen::Vector3d(n[0], n[1], n[2]);
      correspondences.push_back(c);
    }
    // Feature matches every 3 mm: the same tissue points, where the truth has moved them.
    for (std::size_t i = 0; i < canonical.size(); i += 3) {
      const Eigen::Vector3d& p = canonical[i];
      const cv::Vec3d moved = scan.displacementMm(p.x(), p.y(), frame);
      DeformationCorrespondence c;
      c.canonicalMm = p;
      c.targetMm = p + Eigen::Vector3d(moved[0], moved[1], moved[2]);
      c.pointToPoint = true;
      correspondences.push_back(c);
    }
    DeformationFitParameters parameters;
    parameters.restNormalWeight = 1e-3;  // the depth sees every point along its normal here: no drift to hold
    fit = fitDeformation(graph, correspondences, parameters);
  }
  double after2 = 0, stillMotionMax = 0;
  for (const Eigen::Vector3d& p : canonical) {
    const Eigen::Vector3d live = graph.warp(p);
    after2 += std::pow(distanceToTruth(live), 2);
    if (scan.breathing().isStatic(p.x(), p.y()) && std::hypot(p.x() - swell.centreXMm, p.y() - swell.centreYMm) > 22)
      stillMotionMax = std::max(stillMotionMax, (live - p).norm());
  }
  const double afterRms = std::sqrt(after2 / canonical.size());
  std::printf("[ measured ] live surface %.3f mm RMS from the true surface (%.3f before), data %.3f mm, "
              "largest node motion %.2f mm, still tissue moved %.3f mm at most\n",
              afterRms, beforeRms, fit.dataRmsMm, fit.maxNodeMotionMm, stillMotionMax);
  EXPECT_LT(afterRms, 0.1) << "warped rest surface against the frame's true surface (before the fit " << beforeRms << " mm)";
  EXPECT_LT(fit.dataRmsMm, 0.1);
  EXPECT_NEAR(fit.maxNodeMotionMm, 3.0, 0.3) << "the flat top rose 3 mm";
  EXPECT_LT(stillMotionMax, 0.1) << "tissue 4 mm and more outside the breathing part stays where it rests";
  EXPECT_LT(fit.iterations, DeformationFitParameters{}.iterations) << "the last round starts converged";
}
