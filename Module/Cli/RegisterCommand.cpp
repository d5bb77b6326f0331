// tissuemosaic register: the reconstructed model registered to a CT/MR surface model (landmarks, then ICP), with
// the paper's accuracy evaluation (per-point distance to the CT surface, RMSE, mean, percentiles, histogram).
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicItkTransformFile.h"
#include "vtkTissueMosaicLandmarksFile.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceDistance.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <nlohmann/json.hpp>
#include <vtkPolyData.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Registers the reconstructed model (a point cloud or mesh) to a CT/MR surface model: a least-squares fit of
landmark pairs (rigid, or with a uniform scale), then optionally ICP (point-to-plane, trimmed, Tukey kernel, so
that scanned parts missing from the CT model do not pull). Then every model point's distance to the CT surface
gives the RMSE, mean, median, 95th percentile, maximum and a histogram.

Frames: everything is computed in LPS mm. Model files are read in the frame they declare (Slicer's SPACE mark),
LPS when they declare none, as 3D Slicer does; our reconstructions carry no mark and are taken as they are.)";

struct RegisterOptions {
  std::string model, target, outTransform, report;
  std::string modelFrame = "file", targetFrame = "file";
  std::optional<std::string> landmarks, modelLandmarks, targetLandmarks, landmarksFrame, initialTransform, outModel,
      outLandmarks, distances, histogram;
  bool scale = false, icp = false;
  IcpParameters icpParameters;
  double binMm = 0.1;
};

nlohmann::json matrixJson(const Eigen::Matrix4d& matrix) {
  nlohmann::json rows = nlohmann::json::array();
  for (int row = 0; row < 4; ++row) rows.push_back({matrix(row, 0), matrix(row, 1), matrix(row, 2), matrix(row, 3)});
  return rows;
}

void runRegister(const RegisterOptions& options) {
  const std::string& transformPath = options.outTransform;
  const std::string& reportPath = options.report;
  const bool withIcp = options.icp;
  const bool pairsFile = options.landmarks.has_value();
  const bool twoFiles = options.modelLandmarks || options.targetLandmarks;
  if (pairsFile && twoFiles) throw UsageError("give either --landmarks or --model-landmarks with --target-landmarks, not both");
  if (twoFiles && !(options.modelLandmarks && options.targetLandmarks)) {
    throw UsageError("--model-landmarks and --target-landmarks go together");
  }
  if ((pairsFile || twoFiles) && options.initialTransform) {
    throw UsageError("give either landmarks or --initial-transform, not both");
  }
  if (!pairsFile && !twoFiles && !options.initialTransform && !withIcp) {
    throw UsageError("nothing to register with: give --landmarks (or --model-landmarks and --target-landmarks), "
                     "--initial-transform, or --icp");
  }
  if (options.scale && !pairsFile && !twoFiles) throw UsageError("--scale needs landmarks");
  if (options.outLandmarks && !pairsFile && !twoFiles) throw UsageError("--out-landmarks needs landmarks");
  std::optional<AnatomicalFrame> landmarksFrame;
  if (options.landmarksFrame) landmarksFrame = parseFrame(*options.landmarksFrame);
  if (!(options.binMm >= 1e-6 && options.binMm <= 1e6)) {
    throw Error("--bin-mm must be a number of mm within [0.000001, 1000000], got " + std::to_string(options.binMm));
  }
  // Every output is checked before any work: a bad path found after the run would leave the others written.
  requireWritableOutput(transformPath, "transform file (--out-transform)");
  requireWritableOutput(reportPath, "report (--report)");
  if (options.outModel) requireWritableOutput(*options.outModel, "registered model (--out-model)");
  if (options.outLandmarks) requireWritableOutput(*options.outLandmarks, "landmark file (--out-landmarks)");
  if (options.distances) requireWritableOutput(*options.distances, "distance report (--distances)");
  if (options.histogram) requireWritableOutput(*options.histogram, "histogram plot (--histogram)");

  const SurfaceModelFile model = readSurfaceModel(options.model, parseModelFrameChoice(options.modelFrame));
  const SurfaceModelFile target = readSurfaceModel(options.target, parseModelFrameChoice(options.targetFrame));
  const TargetSurface targetSurface(target.polyDataLps);
  std::size_t nonFinitePoints = 0;
  const std::vector<Eigen::Vector3d> allModelPoints = polyDataPoints(model.polyDataLps);
  const std::vector<Eigen::Vector3d> modelPoints = finitePoints(allModelPoints, &nonFinitePoints);
  require(!modelPoints.empty(), "the model '" + options.model + "' has no finite point: all " +
                                    std::to_string(allModelPoints.size()) + " have NaN or infinite coordinates");
  if (nonFinitePoints > 0) {
    std::cerr << "note: " << nonFinitePoints << " of the model's " << allModelPoints.size()
              << " points have NaN or infinite coordinates and are left out\n";
  }

  nlohmann::json report;
  report["frame"] = "LPS";
  report["model_file_frame"] = frameName(model.fileFrame);
  report["target_file_frame"] = frameName(target.fileFrame);

  Eigen::Matrix4d targetFromModel = Eigen::Matrix4d::Identity();
  std::optional<LandmarkPairs> pairs;
  if (pairsFile) {
    pairs = readLandmarkPairs(*options.landmarks, landmarksFrame);
  } else if (twoFiles) {
    pairs = pairLandmarks(readLandmarks(*options.modelLandmarks, landmarksFrame),
                          readLandmarks(*options.targetLandmarks, landmarksFrame));
  }
  if (pairs) {
    const LandmarkRegistration fit = registerLandmarks(pairs->modelLps, pairs->targetLps, options.scale);
    targetFromModel = fit.targetFromModel;
    report["landmark_pairs"] = pairs->modelLps.size();
    report["landmarks_paired_by"] = pairs->pairedByLabel ? "label" : "order";
    report["landmark_rmse_mm"] = fit.rmseMm;
    report["landmark_residuals_mm"] = fit.residualsMm;
    report["scale"] = fit.scale;
    std::printf("landmarks: %zu pairs (by %s), RMSE %.3f mm, scale %.5f\n", pairs->modelLps.size(),
                pairs->pairedByLabel ? "label" : "order", fit.rmseMm, fit.scale);
  } else if (options.initialTransform) {
    targetFromModel = readModelToTargetTransform(*options.initialTransform);
  }

  report["icp_iterations"] = 0;
  if (withIcp) {
    const IcpResult icp = refineIcp(modelPoints, targetSurface, targetFromModel, options.icpParameters);
    targetFromModel = icp.targetFromModel;
    report["icp_iterations"] = icp.iterations;
    report["icp_converged"] = icp.converged;
    report["icp_inlier_rmse_mm"] = icp.inlierRmseMm;
    report["icp_inlier_fraction"] = icp.inlierFraction;
    std::printf("ICP: %d iterations (%s), inlier RMSE %.3f mm over %.1f%% of the points\n", icp.iterations,
                icp.converged ? "converged" : "iteration limit", icp.inlierRmseMm, 100 * icp.inlierFraction);
  }
  report["transform_target_from_model"] = matrixJson(targetFromModel);

  const std::vector<Eigen::Vector3d> registered = transformedPoints(modelPoints, targetFromModel);
  std::vector<double> signedDistances;
  const std::vector<double> distances = distancesToSurface(targetSurface, registered, &signedDistances);
  const DistanceStatistics statistics = distanceStatistics(distances);
  const DistanceHistogram histogram = distanceHistogram(distances, options.binMm);
  report["points"] = statistics.count;
  report["non_finite_points_left_out"] = nonFinitePoints;
  report["rmse_mm"] = statistics.rmseMm;
  report["mean_mm"] = statistics.meanMm;
  report["median_mm"] = statistics.medianMm;
  report["p95_mm"] = statistics.p95Mm;
  report["max_mm"] = statistics.maxMm;
  report["histogram"] = {{"bin_mm", histogram.binWidthMm}, {"counts", histogram.counts}, {"overflow", histogram.overflow}};

  OutputBatch outputs;  // every output replaces its file together with the others, or not at all
  writeModelToTargetTransform(transformPath, targetFromModel);
  report["transform_file"] = transformPath;
  report["transform_file_direction"] = "ITK resampling convention: the file holds T_model_target (target -> model)";
  if (options.outModel) {
    auto registeredModel = transformedPolyData(model.polyDataLps, targetFromModel);
    // One value per point of the file: NaN at the points left out for their non-finite coordinates.
    std::vector<double> allDistances, allSignedDistances;
    for (std::size_t i = 0, next = 0; i < allModelPoints.size(); ++i) {
      const bool finite = allModelPoints[i].allFinite();
      allDistances.push_back(finite ? distances[next] : std::nan(""));
      allSignedDistances.push_back(finite ? signedDistances[next] : std::nan(""));
      next += finite;
    }
    addDistanceArrays(registeredModel, allDistances, allSignedDistances);
    writeSurfaceModel(*options.outModel, registeredModel, AnatomicalFrame::LPS);
  }
  if (options.outLandmarks) {
    LandmarkList modelList{"model landmarks", {}, AnatomicalFrame::LPS};
    LandmarkList targetList{"target landmarks", {}, AnatomicalFrame::LPS};
    for (std::size_t i = 0; i < pairs->labels.size(); ++i) {
      modelList.points.push_back({pairs->labels[i], pairs->modelLps[i]});
      targetList.points.push_back({pairs->labels[i], pairs->targetLps[i]});
    }
    writeLandmarkFile(*options.outLandmarks, {modelList, targetList});
  }
  if (options.distances) writeDistanceCsv(*options.distances, registered, distances, signedDistances);
  if (options.histogram) writeHistogramPng(*options.histogram, histogram, statistics);

  writeStreamAtomically(reportPath, "report", [&](std::ostream& file) { file << report.dump(2) << '\n'; });
  outputs.commit();
  std::printf("distance to the target over %zu points: RMSE %.3f mm, mean %.3f, median %.3f, p95 %.3f, max %.3f mm\n",
              statistics.count, statistics.rmseMm, statistics.meanMm, statistics.medianMm, statistics.p95Mm,
              statistics.maxMm);
}

}  // namespace

void setupRegister(CLI::App& tool) {
  auto options = std::make_shared<RegisterOptions>();
  CLI::App* command = addCommand(tool, "register", "registration to a CT/MR surface model (landmarks, ICP) and its "
                                                  "accuracy (RMSE, histogram)", details);
  const auto add = [&](const std::string& name, auto& value, const std::string& description,
                       const std::string& group) { return command->add_option(name, value, description)->group(group); };
  add("--model", options->model, "reconstructed model (.ply .vtp .vtk .stl .obj)", heading::input)->type_name("PATH")->required();
  add("--target", options->target, "CT/MR surface model (.stl .vtp .vtk .ply .obj), must have triangles",
      heading::input)->type_name("PATH")->required();
  add("--model-frame", options->modelFrame, "frame of the model file (default file: its mark, else LPS)",
      heading::input)->type_name("file|lps|ras");
  add("--target-frame", options->targetFrame, "frame of the target file (default file)", heading::input)
      ->type_name("file|lps|ras");
  add("--landmarks", options->landmarks, ".mrk.json with two markups lists: the model's landmarks, then the target's",
      heading::input)->type_name("PATH");
  add("--model-landmarks", options->modelLandmarks, "landmarks picked on the model (.mrk.json or .fcsv) ...",
      heading::input)->type_name("PATH");
  add("--target-landmarks", options->targetLandmarks, "... and on the target; paired by equal labels, else by order "
                                                      "(>= 3 pairs)", heading::input)->type_name("PATH");
  add("--landmarks-frame", options->landmarksFrame, "frame of landmark files that declare no coordinate system",
      heading::input)->type_name("lps|ras");
  add("--initial-transform", options->initialTransform, "start from a .tfm written by this command instead of "
                                                        "landmarks", heading::input)->type_name("PATH");
  add("--out-transform", options->outTransform, "ITK .tfm (LPS) holding T_model_target, the inverse of "
                                                "model->target (ITK and Slicer read transform files as resampling "
                                                "transforms): in Slicer, put the model under it to move it onto the CT",
      heading::output)->type_name("PATH")->required();
  add("--report", options->report, "JSON: rmse_mm, mean_mm, median_mm, p95_mm, max_mm, points, icp_iterations, ...",
      heading::output)->type_name("PATH")->required();
  add("--out-model", options->outModel, "registered model (.vtp .ply .vtk; LPS) with point arrays DistanceMm and "
                                        "SignedDistanceMm (the distance map)", heading::output)->type_name("PATH");
  add("--out-landmarks", options->outLandmarks, "the landmark pairs as .mrk.json (model list in the model's frame, "
                                                "then target)", heading::output)->type_name("PATH");
  add("--distances", options->distances, "per-point CSV: index, registered x y z (LPS mm), distance, signed distance",
      heading::output)->type_name("PATH");
  add("--histogram", options->histogram, "PNG bar plot of the distance histogram", heading::output)->type_name("PATH");
  command->add_flag("--scale", options->scale, "landmark fit with a uniform scale (similarity) instead of rigid")
      ->group(heading::options);
  command->add_flag("--icp", options->icp, "refine with ICP (rotation and translation; the landmark scale is kept)")
      ->group(heading::options);
  add("--max-icp-iterations", options->icpParameters.maxIterations, "ICP iterations at most", heading::options)
      ->capture_default_str();
  add("--icp-inlier-fraction", options->icpParameters.inlierFraction, "share of closest correspondences used per step",
      heading::options)->capture_default_str();
  add("--icp-max-distance", options->icpParameters.maxDistanceMm, "correspondences farther (mm) never used (default: "
                                                                  "no limit)", heading::options);
  add("--bin-mm", options->binMm, "histogram bin width in mm", heading::options)->capture_default_str();
  command->callback([options] { runRegister(*options); });
}

}  // namespace tissuemosaic::cli
