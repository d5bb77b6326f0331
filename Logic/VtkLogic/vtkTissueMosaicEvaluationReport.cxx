#include "vtkTissueMosaicEvaluationReport.h"

#include "Core/Error.h"
#include "IO/MeshPly.h"
#include "IO/PointCloudPly.h"
#include "vtkTissueMosaicAnatomicalFrame.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

namespace tissuemosaic {

namespace {

bool isPly(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".ply";
}

nlohmann::json matrixJson(const Eigen::Matrix4d& matrix) {
  nlohmann::json rows = nlohmann::json::array();
  for (int row = 0; row < 4; ++row) rows.push_back({matrix(row, 0), matrix(row, 1), matrix(row, 2), matrix(row, 3)});
  return rows;
}

}  // namespace

// PLY files are read by the engine's checked readers: VTK 9.1's vtkPLYReader crashes (SIGSEGV, double free) on
// truncated or malformed files instead of reporting them. Other formats go through readSurfaceModel. Coordinates
// are taken as stored (trajectories carry no LPS/RAS mark, so no model file is flipped either).

std::vector<Eigen::Vector3d> evaluationModelPoints(std::vector<Eigen::Vector3d> points, std::size_t* nonFinite,
                                                   const std::string& what) {
  require(!points.empty(), what + " has no points");
  const std::size_t all = points.size();
  points = finitePoints(points, nonFinite);
  require(!points.empty(), what + " has no finite point: all " + std::to_string(all) +
                               " have NaN or infinite coordinates");
  return points;
}

std::vector<Eigen::Vector3d> readEvaluationModelPoints(const std::string& path, std::size_t* nonFinite) {
  std::vector<Eigen::Vector3d> points;
  if (isPly(path)) {
    for (const cv::Point3f& p : readPly(path).pointsMm) points.emplace_back(p.x, p.y, p.z);
  } else {
    points = polyDataPoints(readSurfaceModel(path, ModelFrameChoice::LPS).polyDataLps);
  }
  return evaluationModelPoints(std::move(points), nonFinite, "the model '" + path + "'");
}

vtkSmartPointer<vtkPolyData> readEvaluationReference(const std::string& path) {
  if (!isPly(path)) return readSurfaceModel(path, ModelFrameChoice::LPS).polyDataLps;
  const TriangleMesh mesh = readMeshPly(path);
  require(!mesh.verticesMm.empty(), "the reference '" + path + "' has no points");
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const cv::Point3f& p : mesh.verticesMm) points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> triangles;
  for (const cv::Vec3i& t : mesh.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    triangles->InsertNextCell(3, ids);
  }
  surface->SetPoints(points);
  surface->SetPolys(triangles);
  return surface;  // TargetSurface rejects it when it has no triangles
}

Trajectory readEvaluationTrajectory(const std::string& path) {
  Trajectory trajectory = readTumTrajectory(path);
  require(!trajectory.empty(), "trajectory '" + path + "' holds no pose");
  return trajectory;
}

EvaluationReport evaluationReport(const ModelEvaluation& evaluation, const EvaluationOptions& options,
                                  std::size_t nonFinitePoints) {
  const auto& trajectory = evaluation.trajectory;
  EvaluationReport json = {
      {"rmse_mm", evaluation.distances.rmseMm},
      {"mean_mm", evaluation.distances.meanMm},
      {"p95_mm", evaluation.distances.p95Mm},
      {"coverage", evaluation.coverage.radiusMm > 0 ? nlohmann::json(evaluation.coverage.share()) : nlohmann::json(nullptr)},
      {"ate_mm", trajectory ? nlohmann::json(trajectory->ateRmseMm) : nlohmann::json(nullptr)},
      {"rpe_mm", trajectory ? nlohmann::json(trajectory->rpeRmseMm) : nlohmann::json(nullptr)},
      {"median_mm", evaluation.distances.medianMm},
      {"max_mm", evaluation.distances.maxMm},
      {"share_within_1mm", evaluation.distances.shareWithin1mm},
      {"points", evaluation.distances.count},
      {"points_beyond_reference_edge", evaluation.pointsBeyondReferenceEdge},
      {"coverage_radius_mm", evaluation.coverage.radiusMm},
      {"reference_area_mm2", evaluation.coverage.surfaceAreaMm2},
      {"covered_area_mm2", evaluation.coverage.coveredAreaMm2},
      {"alignment", evaluation.alignment},
      {"transform_reference_from_model", matrixJson(evaluation.T_reference_model)}};
  if (trajectory) {
    json.insert(json.end(), {{"associated_poses", trajectory->poses},
                             {"ate_mean_mm", trajectory->ateMeanMm},
                             {"ate_max_mm", trajectory->ateMaxMm},
                             {"rpe_pairs", trajectory->rpePairs},
                             {"alignment_rotation_sd_deg", trajectory->alignmentRotationSdDeg},
                             {"time_tolerance_s", options.timeToleranceS}});
  }
  if (evaluation.icp) {
    json.insert(json.end(), {{"icp_iterations", evaluation.icp->iterations},
                             {"icp_converged", evaluation.icp->converged},
                             {"icp_inlier_rmse_mm", evaluation.icp->inlierRmseMm}});
  }
  json.emplace_back("non_finite_points_left_out", nonFinitePoints);
  return json;
}

std::string evaluationReportJson(const EvaluationReport& report) {
  std::ostringstream out;
  out << "{\n";
  for (std::size_t i = 0; i < report.size(); ++i) {
    out << "  " << nlohmann::json(report[i].first).dump() << ": " << report[i].second.dump()
        << (i + 1 < report.size() ? ",\n" : "\n");
  }
  out << "}\n";
  return out.str();
}

}  // namespace tissuemosaic
