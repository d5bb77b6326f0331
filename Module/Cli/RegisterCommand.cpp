// tissuemosaic register: the reconstructed model registered to a CT/MR surface model (landmarks, then ICP), with
// the paper's accuracy evaluation (per-point distance to the CT surface, RMSE, mean, percentiles, histogram).
#include "Arguments.h"
#include "Commands.h"
#include "Core/Error.h"
#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicItkTransformFile.h"
#include "vtkTissueMosaicLandmarksFile.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceDistance.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include <nlohmann/json.hpp>
#include <vtkPolyData.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>

namespace tissuemosaic::cli {

namespace {

const char* const help = R"(usage: tissuemosaic register --model MODEL --target CT --out-transform t.tfm --report report.json
                            [--landmarks pairs.mrk.json | --model-landmarks A --target-landmarks B]
                            [--scale] [--icp] [options]

Registers the reconstructed model (a point cloud or mesh) to a CT/MR surface model: a least-squares fit of
landmark pairs (rigid, or with a uniform scale), then optionally ICP (point-to-plane, trimmed, Tukey kernel, so
that scanned parts missing from the CT model do not pull). Then every model point's distance to the CT surface
gives the RMSE, mean, median, 95th percentile, maximum and a histogram.

Frames: everything is computed in LPS mm. Model files are read in the frame they declare (Slicer's SPACE mark),
LPS when they declare none, as 3D Slicer does; our reconstructions carry no mark and are taken as they are.

  --model PATH                reconstructed model (.ply .vtp .vtk .stl .obj)
  --target PATH               CT/MR surface model (.stl .vtp .vtk .ply .obj), must have triangles
  --model-frame F             file|lps|ras: frame of the model file (default file: its mark, else LPS)
  --target-frame F            file|lps|ras: frame of the target file (default file)
  --landmarks PATH            .mrk.json with two markups lists: the model's landmarks, then the target's
  --model-landmarks PATH      landmarks picked on the model (.mrk.json or .fcsv) ...
  --target-landmarks PATH     ... and on the target; paired by equal labels, else by order (>= 3 pairs)
  --landmarks-frame F         lps|ras for landmark files that declare no coordinate system
  --initial-transform PATH    start from a .tfm written by this command instead of landmarks
  --scale                     landmark fit with a uniform scale (similarity) instead of rigid
  --icp                       refine with ICP (rotation and translation; the landmark scale is kept)
  --max-icp-iterations N      (default 100)
  --icp-inlier-fraction F     share of closest correspondences used per step (default 0.8)
  --icp-max-distance MM       correspondences farther never used (default: no limit)
  --out-transform PATH        ITK .tfm (LPS) holding T_model_target, the inverse of model->target, because ITK
                              and Slicer read transform files as resampling transforms (fixed -> moving):
                              in Slicer, put the model under the loaded transform to move it onto the CT
  --report PATH               JSON: rmse_mm, mean_mm, median_mm, p95_mm, max_mm, points, icp_iterations, ...
  --out-model PATH            registered model (.vtp .ply .vtk; LPS) with point arrays DistanceMm and
                              SignedDistanceMm (the distance map)
  --out-landmarks PATH        the landmark pairs as .mrk.json (model list in the model's frame, then target)
  --distances PATH            per-point CSV: index, registered x y z (LPS mm), distance, signed distance
  --histogram PATH            PNG bar plot of the distance histogram
  --bin-mm W                  histogram bin width in mm (default 0.1)
)";

nlohmann::json matrixJson(const Eigen::Matrix4d& matrix) {
  nlohmann::json rows = nlohmann::json::array();
  for (int row = 0; row < 4; ++row) rows.push_back({matrix(row, 0), matrix(row, 1), matrix(row, 2), matrix(row, 3)});
  return rows;
}

SurfaceModelFile readModel(const Arguments& arguments, const std::string& pathOption, const std::string& frameOption) {
  return readSurfaceModel(arguments.required(pathOption),
                          parseModelFrameChoice(arguments.text(frameOption, "file")));
}

}  // namespace

int runRegister(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"model", "target", "model-frame", "target-frame", "landmarks", "model-landmarks",
                       "target-landmarks", "landmarks-frame", "initial-transform", "scale", "icp",
                       "max-icp-iterations", "icp-inlier-fraction", "icp-max-distance", "out-transform", "report",
                       "out-model", "out-landmarks", "distances", "histogram", "bin-mm", "help"});
  const std::string transformPath = arguments.required("out-transform");
  const std::string reportPath = arguments.required("report");
  const bool withIcp = arguments.has("icp");
  const bool pairsFile = arguments.has("landmarks");
  const bool twoFiles = arguments.has("model-landmarks") || arguments.has("target-landmarks");
  if (pairsFile && twoFiles) throw Error("give either --landmarks or --model-landmarks with --target-landmarks, not both");
  if (twoFiles && !(arguments.has("model-landmarks") && arguments.has("target-landmarks"))) {
    throw Error("--model-landmarks and --target-landmarks go together");
  }
  if ((pairsFile || twoFiles) && arguments.has("initial-transform")) {
    throw Error("give either landmarks or --initial-transform, not both");
  }
  if (!pairsFile && !twoFiles && !arguments.has("initial-transform") && !withIcp) {
    throw Error("nothing to register with: give --landmarks (or --model-landmarks and --target-landmarks), "
                "--initial-transform, or --icp");
  }
  if (arguments.has("scale") && !pairsFile && !twoFiles) throw Error("--scale needs landmarks");
  std::optional<AnatomicalFrame> landmarksFrame;
  if (arguments.has("landmarks-frame")) landmarksFrame = parseFrame(arguments.required("landmarks-frame"));
  const double binMm = arguments.number("bin-mm", 0.1);
  if (!(binMm > 0)) throw Error("--bin-mm must be a positive number of mm");

  const SurfaceModelFile model = readModel(arguments, "model", "model-frame");
  const SurfaceModelFile target = readModel(arguments, "target", "target-frame");
  const TargetSurface targetSurface(target.polyDataLps);
  const std::vector<Eigen::Vector3d> modelPoints = polyDataPoints(model.polyDataLps);

  nlohmann::json report;
  report["frame"] = "LPS";
  report["model_file_frame"] = frameName(model.fileFrame);
  report["target_file_frame"] = frameName(target.fileFrame);

  Eigen::Matrix4d targetFromModel = Eigen::Matrix4d::Identity();
  std::optional<LandmarkPairs> pairs;
  if (pairsFile) {
    pairs = readLandmarkPairs(arguments.required("landmarks"), landmarksFrame);
  } else if (twoFiles) {
    pairs = pairLandmarks(readLandmarks(arguments.required("model-landmarks"), landmarksFrame),
                          readLandmarks(arguments.required("target-landmarks"), landmarksFrame));
  }
  if (pairs) {
    const LandmarkRegistration fit = registerLandmarks(pairs->modelLps, pairs->targetLps, arguments.has("scale"));
    targetFromModel = fit.targetFromModel;
    report["landmark_pairs"] = pairs->modelLps.size();
    report["landmarks_paired_by"] = pairs->pairedByLabel ? "label" : "order";
    report["landmark_rmse_mm"] = fit.rmseMm;
    report["landmark_residuals_mm"] = fit.residualsMm;
    report["scale"] = fit.scale;
    std::printf("landmarks: %zu pairs (by %s), RMSE %.3f mm, scale %.5f\n", pairs->modelLps.size(),
                pairs->pairedByLabel ? "label" : "order", fit.rmseMm, fit.scale);
  } else if (arguments.has("initial-transform")) {
    targetFromModel = readModelToTargetTransform(arguments.required("initial-transform"));
  }

  report["icp_iterations"] = 0;
  if (withIcp) {
    IcpParameters parameters;
    parameters.maxIterations = arguments.integer("max-icp-iterations", parameters.maxIterations);
    parameters.inlierFraction = arguments.number("icp-inlier-fraction", parameters.inlierFraction);
    parameters.maxDistanceMm = arguments.number("icp-max-distance", parameters.maxDistanceMm);
    const IcpResult icp = refineIcp(modelPoints, targetSurface, targetFromModel, parameters);
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
  const DistanceHistogram histogram = distanceHistogram(distances, binMm);
  report["points"] = statistics.count;
  report["rmse_mm"] = statistics.rmseMm;
  report["mean_mm"] = statistics.meanMm;
  report["median_mm"] = statistics.medianMm;
  report["p95_mm"] = statistics.p95Mm;
  report["max_mm"] = statistics.maxMm;
  report["histogram"] = {{"bin_mm", histogram.binWidthMm}, {"counts", histogram.counts}, {"overflow", histogram.overflow}};

  writeModelToTargetTransform(transformPath, targetFromModel);
  report["transform_file"] = transformPath;
  report["transform_file_direction"] = "ITK resampling convention: the file holds T_model_target (target -> model)";
  if (arguments.has("out-model")) {
    auto registeredModel = transformedPolyData(model.polyDataLps, targetFromModel);
    addDistanceArrays(registeredModel, distances, signedDistances);
    writeSurfaceModel(arguments.required("out-model"), registeredModel, AnatomicalFrame::LPS);
  }
  if (arguments.has("out-landmarks")) {
    if (!pairs) throw Error("--out-landmarks needs landmarks");
    LandmarkList modelList{"model landmarks", {}, AnatomicalFrame::LPS};
    LandmarkList targetList{"target landmarks", {}, AnatomicalFrame::LPS};
    for (std::size_t i = 0; i < pairs->labels.size(); ++i) {
      modelList.points.push_back({pairs->labels[i], pairs->modelLps[i]});
      targetList.points.push_back({pairs->labels[i], pairs->targetLps[i]});
    }
    writeLandmarkFile(arguments.required("out-landmarks"), {modelList, targetList});
  }
  if (arguments.has("distances")) writeDistanceCsv(arguments.required("distances"), registered, distances, signedDistances);
  if (arguments.has("histogram")) writeHistogramPng(arguments.required("histogram"), histogram, statistics);

  std::ofstream reportFile(reportPath);
  if (!reportFile) throw Error("cannot write report '" + reportPath + "'");
  reportFile << report.dump(2) << '\n';
  if (!reportFile.flush()) throw Error("cannot write report '" + reportPath + "'");
  std::printf("distance to the target over %zu points: RMSE %.3f mm, mean %.3f, median %.3f, p95 %.3f, max %.3f mm\n",
              statistics.count, statistics.rmseMm, statistics.meanMm, statistics.medianMm, statistics.p95Mm,
              statistics.maxMm);
  return 0;
}

}  // namespace tissuemosaic::cli
