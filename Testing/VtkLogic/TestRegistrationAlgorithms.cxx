// Registration against ground truth: known rigid and similarity transforms from noisy landmarks, ICP from a
// 10 degree / 10 mm perturbation with 20% of the scan off the CT surface, and distance statistics against
// analytic cases (a plane, a sphere).
#include "TestRegistrationScene.h"
#include "Core/Error.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceDistance.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPlaneSource.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

using namespace tissuemosaic;
using namespace tissuemosaic::test;

namespace {

/// Largest displacement between two transforms over a point set: the error a user sees on the model.
double maxDisplacementMm(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, const std::vector<Eigen::Vector3d>& points) {
  double largest = 0;
  const auto pa = transformedPoints(points, a), pb = transformedPoints(points, b);
  for (std::size_t i = 0; i < points.size(); ++i) largest = std::max(largest, (pa[i] - pb[i]).norm());
  return largest;
}

std::vector<Eigen::Vector3d> randomPoints(int n, double spreadMm, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(-spreadMm, spreadMm);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  return points;
}

}  // namespace

TEST(RegistrationLandmarks, ExactRigidTransformRecovered) {
  const Eigen::Matrix4d truth = rigidTransform({1, -2, 0.5}, 73, {0, 0, 0}, {12, -40, 250});
  const auto model = randomPoints(4, 40, 1);
  const auto target = transformedPoints(model, truth);
  const LandmarkRegistration fit = registerLandmarks(model, target, false);
  EXPECT_LT((fit.targetFromModel - truth).norm(), 1e-9);
  EXPECT_NEAR(fit.scale, 1.0, 1e-12);
  EXPECT_LT(fit.rmseMm, 1e-9);
}

TEST(RegistrationLandmarks, NoisyRigidAndSimilarityTransformsRecovered) {
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0, 0.3);  // a careful landmark pick: 0.3 mm per axis
  for (const bool withScale : {false, true}) {
    const double scale = withScale ? 1.08 : 1.0;
    Eigen::Matrix4d truth = rigidTransform({0.3, 1, -0.2}, 35, {10, 0, 5}, {-30, 18, 120});
    truth.topLeftCorner<3, 3>() *= scale;
    const auto model = randomPoints(12, 40, withScale ? 3 : 2);
    auto target = transformedPoints(model, truth);
    for (auto& point : target) point += Eigen::Vector3d(noise(random), noise(random), noise(random));
    const LandmarkRegistration fit = registerLandmarks(model, target, withScale);
    const double rotationError = rotationAngleDeg(fit.targetFromModel * truth.inverse());
    const double displacement = maxDisplacementMm(fit.targetFromModel, truth, model);
    std::printf("landmarks (%s, 12 pairs, 0.3 mm noise): rotation error %.3f deg, max displacement %.3f mm, "
                "scale %.4f (true %.4f), landmark RMSE %.3f mm\n",
                withScale ? "similarity" : "rigid", rotationError, displacement, fit.scale, scale, fit.rmseMm);
    EXPECT_LT(rotationError, 0.5);
    EXPECT_LT(displacement, 0.6);
    EXPECT_NEAR(fit.scale, scale, withScale ? 0.005 : 1e-12);
    // Residual RMS of a 6 (7) parameter fit to 12 points with 0.3 mm per axis: about 0.3 * sqrt(3 * (36 - 6) / 36).
    EXPECT_NEAR(fit.rmseMm, 0.3 * std::sqrt(3.0 * 30 / 36), 0.2);
    ASSERT_EQ(fit.residualsMm.size(), 12u);
  }
}

TEST(RegistrationLandmarks, TooFewOrCollinearLandmarksAreErrors) {
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {10, 0, 0}};
  EXPECT_THROW(
      {
        try {
          registerLandmarks(two, two, false);
        } catch (const Error& error) {
          EXPECT_NE(std::string(error.what()).find("at least 3"), std::string::npos) << error.what();
          throw;
        }
      },
      Error);
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {10, 0.001, 0}, {20, 0, 0.001}, {30, 0, 0}};
  const std::vector<Eigen::Vector3d> triangle = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {5, 5, 3}};
  try {
    registerLandmarks(line, triangle, false);
    ADD_FAILURE() << "collinear model landmarks accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("collinear"), std::string::npos) << error.what();
  }
  EXPECT_THROW(registerLandmarks(triangle, line, true), Error);
  EXPECT_THROW(registerLandmarks(triangle, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, false), Error);  // lengths differ
  EXPECT_NO_THROW(registerLandmarks(triangle, triangle, false));
}

TEST(RegistrationIcp, RecoversTruthFromTenDegreeTenMillimetrePerturbationWithOffSurfacePoints) {
  const auto mesh = heightFieldMesh(45, 0.5);
  const TargetSurface target(mesh);
  const ScanSample scan = scanSample(8000, 25, 0.1, 11);
  const double offShare = static_cast<double>(scan.offSurfaceCount) / scan.pointsMm.size();
  ASSERT_GT(offShare, 0.17);
  ASSERT_LT(offShare, 0.23);
  double trueSquares = 0;
  for (double d : scan.trueDistanceMm) trueSquares += d * d;
  const double trueRmse = std::sqrt(trueSquares / scan.trueDistanceMm.size());

  // The model lives in its own (camera) frame; truth maps it onto the CT.
  const Eigen::Matrix4d truth = rigidTransform({1, 2, 3}, 30, {0, 0, 0}, {40, -20, 100});
  const auto modelPoints = transformedPoints(scan.pointsMm, truth.inverse());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : scan.pointsMm) centroid += p;
  centroid /= static_cast<double>(scan.pointsMm.size());

  const Eigen::Vector3d axes[] = {{1, 0, 0}, {0.3, -1, 0.4}, {-0.5, 0.2, 1}};
  const Eigen::Vector3d shifts[] = {{10, 0, 0}, {0, -6, 8}, {-5.77, 5.77, -5.77}};
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Matrix4d perturbation = rigidTransform(axes[trial], 10, centroid, shifts[trial]);
    const Eigen::Matrix4d start = perturbation * truth;
    ASSERT_NEAR(rotationAngleDeg(start * truth.inverse()), 10.0, 1e-9);

    const IcpResult icp = refineIcp(modelPoints, target, start);
    const double rotationError = rotationAngleDeg(icp.targetFromModel * truth.inverse());
    const Eigen::Vector3d centroidError =
        (icp.targetFromModel * truth.inverse()).topLeftCorner<3, 3>() * centroid +
        (icp.targetFromModel * truth.inverse()).topRightCorner<3, 1>() - centroid;
    const double displacement = maxDisplacementMm(icp.targetFromModel, truth, modelPoints);

    std::vector<double> signedDistances;
    const auto distances =
        distancesToSurface(target, transformedPoints(modelPoints, icp.targetFromModel), &signedDistances);
    const DistanceStatistics statistics = distanceStatistics(distances);
    std::printf("ICP trial %d: %d iterations (%s), rotation error %.4f deg, translation error at the centroid "
                "%.4f mm, max displacement %.4f mm; RMSE %.4f mm vs true %.4f mm (%.1f%% off-surface points), "
                "inlier RMSE %.4f mm over %.1f%%\n",
                trial, icp.iterations, icp.converged ? "converged" : "not converged", rotationError,
                centroidError.norm(), displacement, statistics.rmseMm, trueRmse, 100 * offShare, icp.inlierRmseMm,
                100 * icp.inlierFraction);
    EXPECT_TRUE(icp.converged);
    EXPECT_LT(rotationError, 0.2);
    EXPECT_LT(centroidError.norm(), 0.2);
    EXPECT_LT(displacement, 0.2);
    EXPECT_NEAR(statistics.rmseMm, trueRmse, 0.05);
    // The on-surface points' residual is the 0.1 mm sensor noise.
    EXPECT_NEAR(icp.inlierRmseMm, 0.1, 0.02);
  }
}

TEST(RegistrationIcp, PlainLeastSquaresWouldBePulledByOffSurfacePoints) {
  // The same scene with trimming and the kernel switched off ends measurably worse: the robust parts matter.
  const auto mesh = heightFieldMesh(45, 0.5);
  const TargetSurface target(mesh);
  const ScanSample scan = scanSample(4000, 25, 0.1, 5);
  IcpParameters plain;
  plain.inlierFraction = 1.0;
  plain.tukeyCutoff = 1e6;
  const IcpResult robust = refineIcp(scan.pointsMm, target, Eigen::Matrix4d::Identity());
  const IcpResult naive = refineIcp(scan.pointsMm, target, Eigen::Matrix4d::Identity(), plain);
  const double robustError = maxDisplacementMm(robust.targetFromModel, Eigen::Matrix4d::Identity(), scan.pointsMm);
  const double naiveError = maxDisplacementMm(naive.targetFromModel, Eigen::Matrix4d::Identity(), scan.pointsMm);
  std::printf("ICP from the truth: robust drifts %.4f mm, plain least squares %.4f mm\n", robustError, naiveError);
  EXPECT_LT(robustError, 0.05);
  EXPECT_GT(naiveError, 0.3);
}

TEST(RegistrationIcp, BadInputIsAnError) {
  const auto mesh = heightFieldMesh(10, 1);
  const TargetSurface target(mesh);
  EXPECT_THROW(refineIcp({}, target, Eigen::Matrix4d::Identity()), Error);
  IcpParameters bad;
  bad.inlierFraction = 0;
  EXPECT_THROW(refineIcp({{0, 0, 0}}, target, Eigen::Matrix4d::Identity(), bad), Error);
  // Every point far beyond the correspondence limit.
  IcpParameters near;
  near.maxDistanceMm = 1;
  EXPECT_THROW(refineIcp({{0, 0, 500}, {1, 0, 500}, {0, 1, 500}}, target, Eigen::Matrix4d::Identity(), near), Error);
  vtkNew<vtkPolyData> pointsOnly;
  EXPECT_THROW(TargetSurface{pointsOnly}, Error);
}

TEST(RegistrationDistances, PointsAtKnownHeightsAboveAPlane) {
  vtkNew<vtkPlaneSource> plane;  // z = 0, normal +z
  plane->SetOrigin(-50, -50, 0);
  plane->SetPoint1(50, -50, 0);
  plane->SetPoint2(-50, 50, 0);
  plane->SetResolution(7, 9);
  plane->Update();
  const TargetSurface target(plane->GetOutput());
  // 1000 heights 0.0005, 0.0015, ..., 0.9995 mm, alternately above and below (none on a bin edge): mean 0.5,
  // median 0.5, p95 (linear between order statistics 949 and 950) 0.94955, max 0.9995.
  std::vector<Eigen::Vector3d> points;
  std::vector<double> heights;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> xy(-45, 45);
  for (int k = 0; k < 1000; ++k) {
    const double h = (k % 2 ? -1 : 1) * (k + 0.5) / 1000.0;
    heights.push_back(h);
    points.emplace_back(xy(random), xy(random), h);
  }
  std::vector<double> signedDistances;
  const auto distances = distancesToSurface(target, points, &signedDistances);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(distances[i], std::abs(heights[i]), 1e-9);
    EXPECT_NEAR(signedDistances[i], heights[i], 1e-9);
  }
  const DistanceStatistics statistics = distanceStatistics(distances);
  double sumSquares = 0;
  for (int k = 0; k < 1000; ++k) sumSquares += (k + 0.5) * (k + 0.5) / 1e6;
  EXPECT_EQ(statistics.count, 1000u);
  EXPECT_NEAR(statistics.meanMm, 0.5, 1e-9);
  EXPECT_NEAR(statistics.medianMm, 0.5, 1e-9);
  EXPECT_NEAR(statistics.p95Mm, 0.94955, 1e-9);
  EXPECT_NEAR(statistics.maxMm, 0.9995, 1e-9);
  EXPECT_NEAR(statistics.rmseMm, std::sqrt(sumSquares / 1000), 1e-9);

  const DistanceHistogram histogram = distanceHistogram(distances, 0.25);
  ASSERT_EQ(histogram.counts.size(), 4u);
  for (std::size_t bin = 0; bin < 4; ++bin) EXPECT_EQ(histogram.counts[bin], 250u) << "bin " << bin;
  EXPECT_EQ(histogram.overflow, 0u);
  const DistanceHistogram capped = distanceHistogram(distances, 0.25, 2);
  EXPECT_EQ(capped.counts.size(), 2u);
  EXPECT_EQ(capped.overflow, 500u);
}

TEST(RegistrationDistances, PointsAtKnownDistancesFromASphere) {
  vtkNew<vtkSphereSource> sphere;  // radius 20 mm; the facets lie at most 0.002 mm inside the true sphere
  sphere->SetRadius(20);
  sphere->SetThetaResolution(300);
  sphere->SetPhiResolution(300);
  sphere->Update();
  const TargetSurface target(sphere->GetOutput());
  std::mt19937 random(9);
  std::normal_distribution<double> direction(0, 1);
  std::uniform_real_distribution<double> offset(-3, 3);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> truth;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d unit = Eigen::Vector3d(direction(random), direction(random), direction(random)).normalized();
    const double d = offset(random);
    points.push_back((20 + d) * unit);
    truth.push_back(d);
  }
  std::vector<double> signedDistances;
  const auto distances = distancesToSurface(target, points, &signedDistances);
  double sumSquares = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(distances[i], std::abs(truth[i]), 0.005) << "point " << i;
    if (std::abs(truth[i]) > 0.01) EXPECT_EQ(signedDistances[i] > 0, truth[i] > 0) << "point " << i;
    sumSquares += truth[i] * truth[i];
  }
  EXPECT_NEAR(distanceStatistics(distances).rmseMm, std::sqrt(sumSquares / 2000), 0.005);
  EXPECT_NEAR(percentile({3, 1, 2, 4}, 50), 2.5, 1e-12);
  EXPECT_NEAR(percentile({3, 1, 2, 4}, 95), 3.85, 1e-12);
  EXPECT_THROW(distanceStatistics({}), Error);
}

// A closest point on a shared edge or vertex lies on every triangle around it at the same distance; the locator may
// return any of them (its bins are filled in parallel), which made ICP's result differ by about 1e-5 mm between runs.
// The lowest triangle id holding the point is taken, whatever the triangles' order.
TEST(RegistrationIcp, ClosestPointsOnSharedEdgesAndVerticesTakeTheLowestTriangle) {
  // A roof: two slopes meeting at the ridge x = 0 (z = 1), and a pyramid's tip at (5, 0, 1) over four faces.
  const auto mesh = [](bool reversed) {
    vtkNew<vtkPoints> points;
    for (const auto& p : {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(0, -1, 1), Eigen::Vector3d(1, -1, 0),
                          Eigen::Vector3d(-1, 1, 0), Eigen::Vector3d(0, 1, 1), Eigen::Vector3d(1, 1, 0),
                          Eigen::Vector3d(4, -1, 0), Eigen::Vector3d(6, -1, 0), Eigen::Vector3d(6, 1, 0),
                          Eigen::Vector3d(4, 1, 0), Eigen::Vector3d(5, 0, 1)}) {
      points->InsertNextPoint(p.data());
    }
    std::vector<std::array<vtkIdType, 3>> triangles{{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4},
                                                    {6, 7, 10}, {7, 8, 10}, {8, 9, 10}, {9, 6, 10}};
    if (reversed) std::reverse(triangles.begin(), triangles.end());
    vtkNew<vtkCellArray> polys;
    for (const auto& t : triangles) polys->InsertNextCell(3, t.data());
    vtkNew<vtkPolyData> surface;
    surface->SetPoints(points);
    surface->SetPolys(polys);
    return vtkSmartPointer<vtkPolyData>(surface.GetPointer());
  };
  for (const bool reversed : {false, true}) {
    const TargetSurface surface(mesh(reversed));
    // Above the ridge: the closest point is on the edge (0, -0.2, 1) of the two middle triangles.
    const TargetSurface::Closest ridge = surface.closest(Eigen::Vector3d(0, -0.2, 3));
    EXPECT_LT((ridge.pointLps - Eigen::Vector3d(0, -0.2, 1)).norm(), 1e-12);
    EXPECT_EQ(ridge.cellId, reversed ? 4 : 0) << "the lower of the two triangles that share the ridge";
    // Above the tip: every face of the pyramid holds it.
    const TargetSurface::Closest tip = surface.closest(Eigen::Vector3d(5, 0, 4));
    EXPECT_LT((tip.pointLps - Eigen::Vector3d(5, 0, 1)).norm(), 1e-12);
    EXPECT_EQ(tip.cellId, reversed ? 0 : 4);
  }
  // Above every vertex of a finely triangulated plane: the point is the vertex, held by up to six triangles that the
  // locator's bins split between them.
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(0, 0, 0);
  plane->SetPoint1(37, 0, 0);
  plane->SetPoint2(0, 29, 0);
  plane->SetResolution(60, 45);
  plane->Update();
  const TargetSurface grid(plane->GetOutput());
  vtkPolyData* triangles = grid.triangles();
  vtkNew<vtkIdList> around;
  int vertices = 0, notLowest = 0;
  for (vtkIdType v = 0; v < triangles->GetNumberOfPoints(); ++v) {
    Eigen::Vector3d point;
    triangles->GetPoint(v, point.data());
    triangles->GetPointCells(v, around);
    vtkIdType lowest = triangles->GetNumberOfCells();
    for (vtkIdType i = 0; i < around->GetNumberOfIds(); ++i) lowest = std::min(lowest, around->GetId(i));
    const TargetSurface::Closest closest = grid.closest(point + Eigen::Vector3d(0, 0, 1));
    ++vertices;
    notLowest += closest.cellId != lowest;
  }
  EXPECT_EQ(notLowest, 0) << "of " << vertices << " vertices";
}
