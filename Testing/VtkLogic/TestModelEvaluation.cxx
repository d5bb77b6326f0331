// The evaluation of a reconstruction against a reference surface (vtkTissueMosaicModelEvaluation) on cases whose
// answers are known analytically: points at a known normal offset, half of a plane covered, a model and trajectory
// moved by a known rigid transform with known noise, and an ICP-recoverable perturbation.
#include "EvaluationTestScene.h"
#include "Core/Error.h"
#include "vtkTissueMosaicModelEvaluation.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace tissuemosaic;
using namespace tissuemosaic::test;

namespace {

/// A square of the plane through `origin` spanned by the orthonormal axes u, v: [-half, half]^2, triangulated on a
/// grid of `cells` x `cells` squares (cells = 1: two triangles).
vtkSmartPointer<vtkPolyData> planeMesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
                                       const Eigen::Vector3d& v, double halfMm, int cells) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const int side = cells + 1;
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const Eigen::Vector3d p =
          origin + (-halfMm + 2 * halfMm * i / cells) * u + (-halfMm + 2 * halfMm * j / cells) * v;
      points->InsertNextPoint(p.data());
    }
  }
  vtkNew<vtkCellArray> triangles;
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const vtkIdType a = j * side + i, b = a + 1, c = a + side, d = c + 1;
      const vtkIdType first[3] = {a, b, d}, second[3] = {a, d, c};
      triangles->InsertNextCell(3, first);
      triangles->InsertNextCell(3, second);
    }
  }
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->SetPoints(points);
  mesh->SetPolys(triangles);
  return mesh;
}

/// A regular grid of points on the z = heightMm plane over [x0, x1] x [y0, y1].
std::vector<Eigen::Vector3d> gridPoints(double x0, double x1, double y0, double y1, double spacingMm, double heightMm) {
  std::vector<Eigen::Vector3d> points;
  for (double y = y0; y <= y1 + 1e-9; y += spacingMm) {
    for (double x = x0; x <= x1 + 1e-9; x += spacingMm) points.emplace_back(x, y, heightMm);
  }
  return points;
}

}  // namespace

TEST(ModelEvaluation, PointsAtAKnownNormalOffsetAreThatFar) {
  // A tilted plane: every point sampled inside it and moved 0.3 mm along the normal (to either side) is 0.3 mm away.
  const Eigen::Vector3d u = Eigen::Vector3d(1, 0.2, 0.3).normalized();
  const Eigen::Vector3d v = u.cross(Eigen::Vector3d(0.1, 1, -0.2)).normalized().cross(u).normalized();
  const Eigen::Vector3d normal = u.cross(v);
  const Eigen::Vector3d origin(5, -3, 40);
  const TargetSurface plane(planeMesh(origin, u, v, 30, 60));
  std::mt19937 random(5);
  std::uniform_real_distribution<double> inside(-28, 28);
  std::vector<Eigen::Vector3d> model;
  for (int k = 0; k < 4000; ++k) {
    model.push_back(origin + inside(random) * u + inside(random) * v + (k % 2 ? 0.3 : -0.3) * normal);
  }
  const ModelEvaluation flat = evaluateModel(model, plane, nullptr);
  EXPECT_EQ(flat.alignment, "none");
  EXPECT_EQ(flat.distances.count, 4000u);
  EXPECT_NEAR(flat.distances.rmseMm, 0.3, 1e-9);
  EXPECT_NEAR(flat.distances.meanMm, 0.3, 1e-9);
  EXPECT_NEAR(flat.distances.p95Mm, 0.3, 1e-9);
  EXPECT_NEAR(flat.distances.maxMm, 0.3, 1e-9);
  EXPECT_FALSE(flat.trajectory.has_value());

  // A curved surface meshed at 0.5 mm: the offset along the true normal, up to the mesh's sag (< 0.003 mm).
  const TargetSurface curved(heightFieldMesh(30, 0.5));
  model.clear();
  for (int k = 0; k < 4000; ++k) {
    const double x = inside(random), y = inside(random);
    model.push_back(Eigen::Vector3d(x, y, height(x, y)) + 0.3 * surfaceNormal(x, y));
  }
  const ModelEvaluation bent = evaluateModel(model, curved, nullptr);
  std::printf("curved surface, 0.3 mm offset: rmse %.5f mean %.5f p95 %.5f mm\n", bent.distances.rmseMm,
              bent.distances.meanMm, bent.distances.p95Mm);
  EXPECT_NEAR(bent.distances.rmseMm, 0.3, 0.003);
  EXPECT_NEAR(bent.distances.meanMm, 0.3, 0.003);
}

// A partial reference (the plane z = 0 over [-10, 10]^2 at 0.5 mm, with a hole where the triangles' centres lie
// within 4 mm of (2, -1)) and a model 0.2 mm above it that reaches over the hole and 3 mm beyond the outline: with
// excludeBeyondReferenceEdge exactly the points whose foot is in no triangle are left out, and every other point
// scores 0.2 mm; without it, the points over the gaps score their distance to the rim.
TEST(ModelEvaluation, PointsBeyondTheReferencesEdgeCanBeLeftOut) {
  vtkSmartPointer<vtkPolyData> plane = planeMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                                                 Eigen::Vector3d::UnitY(), 10, 40);
  vtkNew<vtkCellArray> kept;
  std::vector<std::array<Eigen::Vector3d, 3>> keptTriangles;
  const vtkIdType* ids = nullptr;
  vtkIdType count = 0;
  for (vtkIdType c = 0; c < plane->GetNumberOfCells(); ++c) {
    plane->GetCellPoints(c, count, ids);
    std::array<Eigen::Vector3d, 3> corners;
    for (int k = 0; k < 3; ++k) plane->GetPoint(ids[k], corners[k].data());
    const Eigen::Vector3d centre = (corners[0] + corners[1] + corners[2]) / 3;
    if ((centre.head<2>() - Eigen::Vector2d(2, -1)).norm() < 4) continue;
    kept->InsertNextCell(count, ids);
    keptTriangles.push_back(corners);
  }
  plane->SetPolys(kept);
  const TargetSurface reference(plane);
  // Off the grid lines (0.37 mm steps from -12.9): no foot on a triangle's edge, where inside and outside meet.
  const std::vector<Eigen::Vector3d> model = gridPoints(-12.9, 12.9, -12.9, 12.9, 0.37, 0.2);
  const auto footInSomeTriangle = [&](const Eigen::Vector3d& point) {
    for (const auto& t : keptTriangles) {
      const Eigen::Vector2d a = t[0].head<2>(), b = t[1].head<2>(), c = t[2].head<2>(), p = point.head<2>();
      const auto side = [](const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::Vector2d& q) {
        return (d.x() - o.x()) * (q.y() - o.y()) - (d.y() - o.y()) * (q.x() - o.x());
      };
      const double s0 = side(a, b, p), s1 = side(b, c, p), s2 = side(c, a, p);
      if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) return true;
    }
    return false;
  };
  std::size_t beyond = 0;
  for (const Eigen::Vector3d& point : model) beyond += !footInSomeTriangle(point);
  ASSERT_GT(beyond, 1000u);  // over the hole (about 50 mm^2) and the 3 mm band around the outline
  ASSERT_LT(beyond, model.size() / 2);

  const ModelEvaluation all = evaluateModel(model, reference, nullptr);
  EXPECT_EQ(all.distances.count, model.size());
  EXPECT_EQ(all.pointsBeyondReferenceEdge, 0u);
  EXPECT_GT(all.distances.rmseMm, 0.5);  // the gaps' points count their distance to the rim

  EvaluationOptions options;
  options.excludeBeyondReferenceEdge = true;
  const ModelEvaluation scored = evaluateModel(model, reference, nullptr, options);
  EXPECT_EQ(scored.pointsBeyondReferenceEdge, beyond);
  EXPECT_EQ(scored.distances.count, model.size() - beyond);
  EXPECT_NEAR(scored.distances.rmseMm, 0.2, 1e-9);
  EXPECT_NEAR(scored.distances.maxMm, 0.2, 1e-9);
  std::printf("partial reference: %zu of %zu points beyond its edge; rmse %.4f mm with them, %.4f without\n", beyond,
              model.size(), all.distances.rmseMm, scored.distances.rmseMm);

  // A model wholly beyond the edge: nothing to score is an error, not an empty result.
  const std::vector<Eigen::Vector3d> outside = gridPoints(11, 12, 11, 12, 0.5, 0.2);
  EXPECT_THROW(evaluateModel(outside, reference, nullptr, options), Error);
}

TEST(ModelEvaluation, HalfOfAPlaneSampledCoversHalfOfItPlusTheRadius) {
  // Plane [-20, 20]^2 at z = 0; model points every 0.1 mm over x <= 0. Covered: x <= r' where r' is the reach of the
  // points in the plane: the radius for points on it, sqrt(r^2 - h^2) for points h above it.
  const TargetSurface fine(planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 20, 40));
  const TargetSurface twoTriangles(planeMesh({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 20, 1));
  const std::vector<Eigen::Vector3d> onPlane = gridPoints(-20, 0, -20, 20, 0.1, 0);
  const std::vector<Eigen::Vector3d> above = gridPoints(-20, 0, -20, 20, 0.1, 0.3);
  const double radius = 0.5;
  const SurfaceCoverage a = surfaceCoverage(fine, onPlane, radius);
  const SurfaceCoverage b = surfaceCoverage(twoTriangles, onPlane, radius);
  const SurfaceCoverage c = surfaceCoverage(fine, above, radius);
  std::printf("half plane: coverage %.5f (fine mesh), %.5f (two triangles), %.5f (points 0.3 mm above); "
              "expected %.5f, %.5f\n", a.share(), b.share(), c.share(), 20.5 / 40, 20.4 / 40);
  EXPECT_NEAR(a.surfaceAreaMm2, 1600, 1e-9);
  EXPECT_NEAR(b.surfaceAreaMm2, 1600, 1e-9);
  EXPECT_NEAR(a.share(), 20.5 / 40, 0.002);
  EXPECT_NEAR(b.share(), 20.5 / 40, 0.002);
  EXPECT_NEAR(c.share(), (20 + std::sqrt(0.5 * 0.5 - 0.3 * 0.3)) / 40, 0.002);
  // Nothing near: nothing covered; everything near: all of it.
  EXPECT_EQ(surfaceCoverage(fine, {Eigen::Vector3d(0, 0, 50)}, 1.0).coveredAreaMm2, 0.0);
  EXPECT_NEAR(surfaceCoverage(fine, gridPoints(-20, 20, -20, 20, 0.5, 0), 1.0).share(), 1.0, 1e-12);
  EXPECT_THROW(surfaceCoverage(fine, onPlane, 0), Error);
  EXPECT_THROW(surfaceCoverage(fine, {}, 1), Error);
}

TEST(ModelEvaluation, TrajectoryAlignmentBringsAMovedModelBack) {
  // The reconstruction lives in its own world: model and trajectory are the truth moved by the inverse of
  // T_reference_model; then the trajectory's positions get 0.2 mm noise per axis.
  const auto mesh = heightFieldMesh(30, 0.5);
  const TargetSurface reference(mesh);
  const Eigen::Matrix4d T_reference_model = rigidTransform({1, -1, 2}, 40, {0, 0, 0}, {30, -50, 80});
  const std::vector<Eigen::Vector3d> model = transformedPoints(polyDataPoints(mesh), T_reference_model.inverse());
  EvaluationTrajectories trajectories{moved(cameraPath(300), T_reference_model.inverse()), cameraPath(300)};

  const ModelEvaluation exact = evaluateModel(model, reference, &trajectories);
  EXPECT_EQ(exact.alignment, "trajectory");
  ASSERT_TRUE(exact.trajectory.has_value());
  EXPECT_EQ(exact.trajectory->poses, 300u);
  EXPECT_LT(exact.trajectory->ateRmseMm, 1e-9);
  EXPECT_LT(exact.distances.maxMm, 1e-6);
  EXPECT_NEAR(exact.coverage.share(), 1.0, 1e-9);

  std::mt19937 random(2);
  std::normal_distribution<double> noise(0, 0.2);
  double sumSquares = 0, stepSquares = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < trajectories.model.size(); ++i) {
    const Eigen::Vector3d n(noise(random), noise(random), noise(random));
    trajectories.model[i].T_world_camera.topRightCorner<3, 1>() += n;
    trajectories.model[i].timeS += 0.004;  // the clocks differ a little: still within the 0.02 s tolerance
    sumSquares += n.squaredNorm();
    if (i > 0) stepSquares += (n - previous).squaredNorm();
    previous = n;
  }
  const double noiseRmsMm = std::sqrt(sumSquares / 300);
  // Position noise n_i changes the relative motion of poses i, i+1 by exactly n_i+1 - n_i (rotated).
  const double expectedRpeMm = std::sqrt(stepSquares / 299);
  const ModelEvaluation noisy = evaluateModel(model, reference, &trajectories);
  const Eigen::Matrix4d error = noisy.T_reference_model * T_reference_model.inverse();
  const Eigen::Vector3d centre(0, 0, height(0, 0));
  const double centreErrorMm = (error.topLeftCorner<3, 3>() * centre + error.topRightCorner<3, 1>() - centre).norm();
  std::printf("noise RMS %.4f mm: ATE %.4f mm, RPE %.4f mm (expected %.4f), model RMSE after alignment %.4f mm, "
              "placement error at the surface centre %.4f mm\n", noiseRmsMm, noisy.trajectory->ateRmseMm,
              noisy.trajectory->rpeRmseMm, expectedRpeMm, noisy.distances.rmseMm, centreErrorMm);
  EXPECT_LE(noisy.trajectory->ateRmseMm, noiseRmsMm + 1e-12);
  EXPECT_GE(noisy.trajectory->ateRmseMm, 0.98 * noiseRmsMm);
  EXPECT_NEAR(noisy.trajectory->rpeRmseMm, expectedRpeMm, 1e-9);
  EXPECT_LT(noisy.distances.rmseMm, 0.03) << "the model is brought back by the trajectory alignment";
  // The path's positions span +-15 mm in depth, 80 mm above the surface: the noise tilts the alignment a little,
  // which moves the surface sideways, along itself, where the distances hardly see it.
  EXPECT_LT(centreErrorMm, 0.1);
}

TEST(ModelEvaluation, IcpRecoversAPerturbedModel) {
  const TargetSurface reference(heightFieldMesh(30, 0.5));
  std::vector<Eigen::Vector3d> model;
  for (double y = -24; y <= 24; y += 0.4) {
    for (double x = -24; x <= 24; x += 0.4) model.emplace_back(x, y, height(x, y));
  }
  const Eigen::Matrix4d perturbation = rigidTransform({0.3, 1, 0.2}, 3, {0, 0, 0}, {1.0, -0.8, 0.6});
  const std::vector<Eigen::Vector3d> perturbed = transformedPoints(model, perturbation);
  const ModelEvaluation before = evaluateModel(perturbed, reference, nullptr);
  EvaluationOptions options;
  options.icp = true;
  const ModelEvaluation after = evaluateModel(perturbed, reference, nullptr, options);
  std::printf("perturbed by 3 deg and 1.4 mm: RMSE %.4f mm before, %.5f mm after ICP (%d iterations)\n",
              before.distances.rmseMm, after.distances.rmseMm, after.icp->iterations);
  EXPECT_GT(before.distances.rmseMm, 0.3);
  EXPECT_EQ(after.alignment, "icp");
  EXPECT_TRUE(after.icp->converged);
  EXPECT_LT(after.distances.rmseMm, 0.01);
  EXPECT_LT(rotationAngleDeg(after.T_reference_model * perturbation), 0.05);
}

TEST(ModelEvaluation, BadInputIsAnError) {
  const TargetSurface reference(heightFieldMesh(10, 1));
  const std::vector<Eigen::Vector3d> model = {{0, 0, height(0, 0)}, {1, 0, height(1, 0)}};
  EXPECT_THROW(evaluateModel({}, reference, nullptr), Error);
  EvaluationOptions options;
  options.coverageRadiusMm = -1;
  EXPECT_THROW(evaluateModel(model, reference, nullptr, options), Error);

  EvaluationTrajectories later{cameraPath(20), cameraPath(20)};
  for (TimedPose& p : later.model) p.timeS += 100;
  try {
    evaluateModel(model, reference, &later);
    ADD_FAILURE() << "trajectories without common time stamps were accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("share no time stamps"), std::string::npos) << error.what();
  }
  EvaluationTrajectories empty{{}, cameraPath(20)};
  EXPECT_THROW(evaluateModel(model, reference, &empty), Error);

  // Two thirds of a second of a path with 0.3 mm noise: not collinear, but the alignment could turn the model about
  // the path by more than the default limit; a limit above the estimate accepts it.
  EvaluationTrajectories brief{cameraPath(20), cameraPath(20)};
  std::mt19937 random(1);
  std::normal_distribution<double> noise(0, 0.3);
  for (TimedPose& p : brief.model) {
    p.T_world_camera.topRightCorner<3, 1>() += Eigen::Vector3d(noise(random), noise(random), noise(random));
  }
  const double sdDeg =
      trajectoryErrors({brief.model, brief.reference}, TrajectoryAlignment::Rigid).alignmentRotationSdDeg;
  std::printf("20 poses, 0.3 mm noise: alignment rotation sd %.2f deg\n", sdDeg);
  ASSERT_GT(sdDeg, EvaluationOptions().maxAlignmentRotationSdDeg);
  try {
    evaluateModel(model, reference, &brief);
    ADD_FAILURE() << "an ill-conditioned trajectory alignment was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("cannot place the model"), std::string::npos) << error.what();
  }
  options = EvaluationOptions();
  options.maxAlignmentRotationSdDeg = 1.01 * sdDeg;
  EXPECT_NEAR(evaluateModel(model, reference, &brief, options).trajectory->alignmentRotationSdDeg, sdDeg, 1e-12);
}
