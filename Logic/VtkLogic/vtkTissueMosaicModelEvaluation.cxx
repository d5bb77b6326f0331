#include "vtkTissueMosaicModelEvaluation.h"

#include "Core/Error.h"
#include "Core/ParameterError.h"
#include "Core/ParallelFor.h"

#include <Eigen/Geometry>

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticPointLocator.h>

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace tissuemosaic {

namespace {

struct Triangle {
  Eigen::Vector3d a, b, c;
};

std::vector<Triangle> trianglesOf(vtkPolyData* mesh) {
  std::vector<Triangle> triangles;
  triangles.reserve(static_cast<std::size_t>(mesh->GetNumberOfPolys()));
  auto cells = vtkSmartPointer<vtkCellArrayIterator>::Take(mesh->GetPolys()->NewIterator());
  for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell()) {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    cells->GetCurrentCell(size, ids);
    if (size != 3) continue;  // TargetSurface holds triangles only
    Triangle t;
    mesh->GetPoint(ids[0], t.a.data());
    mesh->GetPoint(ids[1], t.b.data());
    mesh->GetPoint(ids[2], t.c.data());
    triangles.push_back(t);
  }
  return triangles;
}

std::string timeRange(const Trajectory& trajectory) {
  double first = std::numeric_limits<double>::infinity(), last = -first;
  for (const TimedPose& pose : trajectory) {
    first = std::min(first, pose.timeS);
    last = std::max(last, pose.timeS);
  }
  return cv::format("%zu poses, t = %.3f .. %.3f s", trajectory.size(), first, last);
}

}  // namespace

SurfaceCoverage surfaceCoverage(const TargetSurface& surface, const std::vector<Eigen::Vector3d>& points,
                                double radiusMm) {
  require(std::isfinite(radiusMm) && radiusMm > 0, "the coverage radius must be a positive number of mm");
  require(!points.empty(), "coverage: the model has no points");
  vtkNew<vtkPoints> cloudPoints;
  cloudPoints->SetDataTypeToDouble();
  cloudPoints->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) cloudPoints->SetPoint(static_cast<vtkIdType>(i), points[i].data());
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(cloudPoints);
  vtkNew<vtkStaticPointLocator> locator;  // its queries are thread-safe once built
  locator->SetDataSet(cloud);
  locator->BuildLocator();

  const std::vector<Triangle> triangles = trianglesOf(surface.triangles());
  double longestEdgeMm = 0;
  for (const Triangle& t : triangles) {
    longestEdgeMm = std::max({longestEdgeMm, (t.b - t.a).norm(), (t.c - t.b).norm(), (t.a - t.c).norm()});
  }
  // Distance to the nearest point, or infinity beyond radius + the longest edge, where only "far" matters.
  const double searchMm = radiusMm + longestEdgeMm;
  const auto nearestMm = [&](const Eigen::Vector3d& x, double within) {
    double distance2 = 0;
    return locator->FindClosestPointWithinRadius(within, x.data(), distance2) >= 0
               ? std::sqrt(distance2)
               : std::numeric_limits<double>::infinity();
  };
  const double sampleEdgeMm = radiusMm / 4;
  constexpr int maxSplits = 512;
  std::vector<double> areaMm2(triangles.size()), coveredMm2(triangles.size());
  parallelFor<CpuBackend>(static_cast<int64_t>(triangles.size()), [&](int64_t index) {
    const Triangle& t = triangles[static_cast<std::size_t>(index)];
    const Eigen::Vector3d ab = t.b - t.a, ac = t.c - t.a;
    const double area = 0.5 * ab.cross(ac).norm();
    const double longest = std::max({ab.norm(), ac.norm(), (t.c - t.b).norm()});
    areaMm2[static_cast<std::size_t>(index)] = area;
    const double da = nearestMm(t.a, searchMm), db = nearestMm(t.b, searchMm), dc = nearestMm(t.c, searchMm);
    if (std::min({da, db, dc}) + longest <= radiusMm) {
      coveredMm2[static_cast<std::size_t>(index)] = area;
      return;
    }
    if (std::max({da, db, dc}) - longest > radiusMm) return;
    // The boundary of the covered area may cross this triangle: n^2 equal sub-triangles, n (n + 1) / 2 "upward" ones
    // with centroids at ((i + 1/3) ab + (j + 1/3) ac) / n, n (n - 1) / 2 "downward" ones at (i + 2/3, j + 2/3).
    const int n = std::clamp(static_cast<int>(std::ceil(longest / sampleEdgeMm)), 1, maxSplits);
    const auto coveredAt = [&](double a, double b) {
      return nearestMm(t.a + (a * ab + b * ac) / n, radiusMm) <= radiusMm;
    };
    int covered = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        covered += coveredAt(i + 1.0 / 3, j + 1.0 / 3);
        if (i + j + 1 < n) covered += coveredAt(i + 2.0 / 3, j + 2.0 / 3);
      }
    }
    coveredMm2[static_cast<std::size_t>(index)] = area * covered / (static_cast<double>(n) * n);
  }, 64);
  SurfaceCoverage coverage;
  coverage.radiusMm = radiusMm;
  // Summed in a fixed order: the same result for any number of threads.
  coverage.surfaceAreaMm2 = std::accumulate(areaMm2.begin(), areaMm2.end(), 0.0);
  coverage.coveredAreaMm2 = std::accumulate(coveredMm2.begin(), coveredMm2.end(), 0.0);
  return coverage;
}

void EvaluationOptions::validate() const {
  require(std::isfinite(coverageRadiusMm) && coverageRadiusMm >= 0,
          "the coverage radius must be a non-negative number of mm (0: no coverage)");
  require(std::isfinite(timeToleranceS) && timeToleranceS >= 0,
          "the time-stamp tolerance must be a non-negative number of s");
  require(maxAlignmentRotationSdDeg > 0, "the largest alignment uncertainty must be a positive number of degrees");
}

ModelEvaluation evaluateModel(const std::vector<Eigen::Vector3d>& modelPoints, const TargetSurface& reference,
                              const EvaluationTrajectories* trajectories, const EvaluationOptions& options) {
  options.validate();
  require(!modelPoints.empty(), "the model has no points");
  ModelEvaluation evaluation;
  std::vector<std::string> steps;
  if (trajectories) {
    require(!trajectories->model.empty(), "the model trajectory holds no pose");
    require(!trajectories->reference.empty(), "the reference trajectory holds no pose");
    const AssociatedPoses associated =
        associateByTime(trajectories->model, trajectories->reference, options.timeToleranceS);
    if (associated.size() == 0) {
      throw Error(cv::format("the trajectories share no time stamps (within %g s): model %s, reference %s",
                             options.timeToleranceS, timeRange(trajectories->model).c_str(),
                             timeRange(trajectories->reference).c_str()));
    }
    if (!options.alignTrajectories) {
      evaluation.trajectory = trajectoryErrors(associated, TrajectoryAlignment::None);
    } else {
    evaluation.trajectory = trajectoryErrors(associated, TrajectoryAlignment::Rigid);
    if (!(evaluation.trajectory->alignmentRotationSdDeg <= options.maxAlignmentRotationSdDeg)) {
      throw ParameterError(
          "maxAlignmentRotationSdDeg",
          cv::format("the trajectory alignment cannot place the model: its rotation is uncertain by %.3g degrees "
                     "(limit %g), because the %zu associated positions span too little across their main "
                     "direction for their scatter; evaluate a longer trajectory, or leave the trajectories out (and "
                     "use ICP)",
                     evaluation.trajectory->alignmentRotationSdDeg, options.maxAlignmentRotationSdDeg,
                     associated.size()));
    }
    evaluation.T_reference_model = evaluation.trajectory->T_reference_estimate;
    steps.push_back("trajectory");
    }
  }
  if (options.icp) {
    evaluation.icp = refineIcp(modelPoints, reference, evaluation.T_reference_model, options.icpParameters);
    evaluation.T_reference_model = evaluation.icp->targetFromModel;
    steps.push_back("icp");
  }
  if (!steps.empty()) {
    evaluation.alignment = steps.front();
    for (std::size_t i = 1; i < steps.size(); ++i) evaluation.alignment += "+" + steps[i];
  }
  const std::vector<Eigen::Vector3d> placed = transformedPoints(modelPoints, evaluation.T_reference_model);
  std::vector<double> distances;
  distances.reserve(placed.size());
  for (const Eigen::Vector3d& point : placed) {
    const TargetSurface::Closest closest = reference.closest(point);
    if (options.excludeBeyondReferenceEdge && reference.onSurfaceEdge(closest)) {
      ++evaluation.pointsBeyondReferenceEdge;
      continue;
    }
    distances.push_back(closest.distanceMm);
  }
  require(!distances.empty(), "all " + std::to_string(placed.size()) +
                                  " model points lie beyond the reference's edge: none to score");
  evaluation.distances = distanceStatistics(distances);
  if (options.coverageRadiusMm > 0) evaluation.coverage = surfaceCoverage(reference, placed, options.coverageRadiusMm);
  return evaluation;
}

}  // namespace tissuemosaic
