#pragma once
/// @file vtkTissueMosaicEvaluationReport.h
/// @brief The inputs and the figures of `tissuemosaic eval`, shared with the Python module's evaluate(): the model's
/// points and the reference surface read as the command reads them, and the report's keys in the command's order.
#include "vtkTissueMosaicModelEvaluation.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <string>
#include <utility>
#include <vector>

namespace tissuemosaic {

/// The model's finite points (.ply by the engine's checked reader, other formats through VTK, coordinates as
/// stored); nonFinite counts those left out. Throws Error for a model without (finite) points or an unreadable file.
std::vector<Eigen::Vector3d> readEvaluationModelPoints(const std::string& path, std::size_t* nonFinite);
/// Finite points of a model in memory; Error when none is finite (what names the model in the message).
std::vector<Eigen::Vector3d> evaluationModelPoints(std::vector<Eigen::Vector3d> points, std::size_t* nonFinite,
                                                   const std::string& what);
/// The reference surface (a .ply mesh by the engine's reader, other formats through VTK).
vtkSmartPointer<vtkPolyData> readEvaluationReference(const std::string& path);
/// A TUM trajectory; Error when it holds no pose.
Trajectory readEvaluationTrajectory(const std::string& path);

/// The report's keys in a fixed order, the contract's six first (rmse_mm, mean_mm, p95_mm, coverage, ate_mm,
/// rpe_mm; nlohmann::json itself would sort them by name), then the details (docs/EVALUATION.md).
using EvaluationReport = std::vector<std::pair<std::string, nlohmann::json>>;
EvaluationReport evaluationReport(const ModelEvaluation& evaluation, const EvaluationOptions& options,
                                  std::size_t nonFinitePoints);
/// One JSON object, a key per line (a matrix stays on its line): what `eval --json` prints.
std::string evaluationReportJson(const EvaluationReport& report);

}  // namespace tissuemosaic
