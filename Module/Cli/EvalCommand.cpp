// tissuemosaic eval: a reconstructed model (and its camera trajectory) scored against a reference surface with known
// geometry (and the true trajectory): distances, coverage, ATE and RPE. Definitions: docs/EVALUATION.md.
#include "CommonOptions.h"
#include "Commands.h"
#include "Core/Error.h"
#include "vtkTissueMosaicEvaluationReport.h"
#include "vtkTissueMosaicModelEvaluation.h"

#include <opencv2/core/utility.hpp>

#include <iostream>
#include <string>
#include <vector>

namespace tissuemosaic::cli {

namespace {

const char* const details = R"(Scores a reconstruction against a reference surface whose geometry is known: a synthetic scan's
groundtruth/surface.ply (what the scan saw with both eyes) or a CT/MR segmentation.

Placement (every file's coordinates are taken as stored, in mm; no LPS/RAS flip):
  - with both trajectories: poses are associated by time stamp (nearest, one to one, within --time-tolerance);
    the rigid transform (Umeyama, no scale) that best maps the model trajectory's positions onto the reference
    trajectory's is applied to the model trajectory AND to the model (a reconstruction's world is its first camera)
  - without trajectories: the model is taken to be in the reference's frame
  - --align icp then refines the placement by point-to-plane ICP (trimmed, Tukey; as `tissuemosaic register`)
Measures:
  rmse_mm mean_mm p95_mm   distance of every placed model point to the reference surface (closest point on a
                           triangle): RMS, mean, 95th percentile (also median_mm, max_mm, and share_within_1mm:
                           against a synthetic scan's groundtruth/instruments.ply, the share of the model's points
                           within 1 mm of an instrument's surface); points counts them, and with
                           --exclude-beyond-reference-edge points_beyond_reference_edge those left out
  coverage                 share of the reference surface's AREA lying within --coverage-radius-mm of some model
                           point (0..1)
  ate_mm                   absolute trajectory error: RMS of the aligned position differences (null without
                           trajectories; also ate_mean_mm, ate_max_mm, alignment_rotation_sd_deg)
  rpe_mm                   relative pose error: RMS of the translation of (Q_i^-1 Q_i+1)^-1 (P_i^-1 P_i+1) over
                           consecutive associated poses, Q reference, P model (null without trajectories)
  alignment                none | trajectory | icp | trajectory+icp, with transform_reference_from_model (4x4)
Bad input (missing or unreadable files, an empty model, a reference without triangles, trajectories without
common time stamps, or too short or straight to align) stops with a message and exit status 1.)";

struct EvalOptions {
  std::string model, reference;
  std::optional<std::string> trajectory, referenceTrajectory;
  std::string align = "none", trajectoryAlignment = "rigid";
  EvaluationOptions evaluation;
  bool json = false;
};

void printTable(const ModelEvaluation& e, const std::string& model, const std::string& reference,
                std::size_t nonFinitePoints) {
  std::cout << "model      " << model << " (" << e.distances.count << " points"
            << (nonFinitePoints > 0 ? ", " + std::to_string(nonFinitePoints) + " non-finite left out" : "")
            << (e.pointsBeyondReferenceEdge > 0
                    ? ", " + std::to_string(e.pointsBeyondReferenceEdge) + " beyond the reference's edge left out"
                    : "")
            << ")\n"
            << "reference  " << reference << cv::format(" (%.1f mm^2)\n", e.coverage.surfaceAreaMm2)
            << "alignment  " << e.alignment;
  if (e.icp) {
    std::cout << cv::format(" (ICP: %d iterations, %s)", e.icp->iterations,
                            e.icp->converged ? "converged" : "iteration limit");
  }
  std::cout << "\n\ndistance to the reference surface (mm)\n"
            << cv::format("  rmse      %8.4f\n  mean      %8.4f\n  median    %8.4f\n  p95       %8.4f\n"
                          "  max       %8.4f\n  within 1 mm: %.4f %% of the points\n",
                          e.distances.rmseMm, e.distances.meanMm, e.distances.medianMm, e.distances.p95Mm,
                          e.distances.maxMm, 100 * e.distances.shareWithin1mm)
            << cv::format("coverage    %7.2f %% of the reference area within %.2f mm of a model point\n",
                          100 * e.coverage.share(), e.coverage.radiusMm);
  if (e.trajectory) {
    std::cout << cv::format("trajectory  %zu associated poses, alignment rotation sd %.3f deg\n"
                            "  ATE rms   %8.4f mm (mean %.4f, max %.4f)\n  RPE rms   %8.4f mm per step\n",
                            e.trajectory->poses, e.trajectory->alignmentRotationSdDeg, e.trajectory->ateRmseMm,
                            e.trajectory->ateMeanMm, e.trajectory->ateMaxMm, e.trajectory->rpeRmseMm);
  } else {
    std::cout << "trajectory  not given (ATE, RPE: none)\n";
  }
}

void runEval(const EvalOptions& given) {
  if (given.trajectory.has_value() != given.referenceTrajectory.has_value()) {
    throw UsageError("--trajectory and --reference-trajectory go together");
  }
  EvaluationOptions options = given.evaluation;
  require(given.align == "icp" || given.align == "none", "unknown --align '" + given.align + "': expected icp or none");
  options.icp = given.align == "icp";
  require(given.trajectoryAlignment == "rigid" || given.trajectoryAlignment == "none",
          "unknown --trajectory-alignment '" + given.trajectoryAlignment + "': expected rigid or none");
  options.alignTrajectories = given.trajectoryAlignment == "rigid";
  options.validate();
  const std::string& modelPath = given.model;
  const std::string& referencePath = given.reference;

  std::size_t nonFinitePoints = 0;
  const std::vector<Eigen::Vector3d> modelPoints = readEvaluationModelPoints(modelPath, &nonFinitePoints);
  if (nonFinitePoints > 0) {
    std::cerr << "note: " << nonFinitePoints << " of the model's " << modelPoints.size() + nonFinitePoints
              << " points have NaN or infinite coordinates and are left out\n";
  }
  const TargetSurface referenceSurface(readEvaluationReference(referencePath));
  std::optional<EvaluationTrajectories> trajectories;
  if (given.trajectory) {
    trajectories = EvaluationTrajectories{readEvaluationTrajectory(*given.trajectory),
                                          readEvaluationTrajectory(*given.referenceTrajectory)};
  }
  const ModelEvaluation evaluation = evaluateModel(modelPoints, referenceSurface,
                                                   trajectories ? &*trajectories : nullptr, options);
  if (given.json) {
    std::cout << evaluationReportJson(evaluationReport(evaluation, options, nonFinitePoints));
  } else {
    printTable(evaluation, modelPath, referencePath, nonFinitePoints);
  }
}

}  // namespace

void setupEval(CLI::App& tool) {
  auto options = std::make_shared<EvalOptions>();
  EvaluationOptions& evaluation = options->evaluation;
  CLI::App* command = addCommand(tool, "eval", "a reconstruction against a known surface: distances (RMSE, mean, p95), "
                                              "coverage, ATE and RPE", details);
  const auto add = [&](const std::string& name, auto& value, const std::string& description,
                       const std::string& group) { return command->add_option(name, value, description)->group(group); };
  add("--model", options->model, "reconstructed model (.ply .vtp .vtk .stl .obj; points, or a mesh's vertices)",
      heading::input)->type_name("PATH")->required();
  add("--reference", options->reference, "reference surface (.ply .stl .vtp .vtk .obj) with triangles (PLY: "
                                         "triangles only)", heading::input)->type_name("PATH")->required();
  add("--trajectory", options->trajectory, "the model's camera trajectory (TUM: t tx ty tz qx qy qz qw, "
                                           "T_world_camera, mm)", heading::input)->type_name("PATH");
  add("--reference-trajectory", options->referenceTrajectory, "the true trajectory in the reference's frame (TUM); "
                                                              "goes with --trajectory", heading::input)->type_name("PATH");
  command->add_flag("--json", options->json, "print one JSON object instead of a table")->group(heading::output);
  add("--time-tolerance", evaluation.timeToleranceS, "largest time-stamp difference (s) of associated poses",
      heading::options)->capture_default_str();
  add("--max-alignment-sd-deg", evaluation.maxAlignmentRotationSdDeg,
      "refuse a trajectory alignment whose rotation is less certain than this: estimated from the residuals and the "
      "spread of the positions, it is large for short or straight paths, where the alignment would misplace the model",
      heading::options)->capture_default_str();
  add("--trajectory-alignment", options->trajectoryAlignment,
      "rigid: as above; none: the model and its trajectory are already in the reference's frame (e.g. `reconstruct "
      "--start-tum` with the true trajectory): the ATE is measured as it is and the model is not moved",
      heading::options)->type_name("rigid|none")->capture_default_str();
  add("--align", options->align, "refine the placement by ICP", heading::options)
      ->type_name("icp|none")
      ->capture_default_str();
  add("--max-icp-iterations", evaluation.icpParameters.maxIterations, "ICP iterations at most", heading::options)
      ->capture_default_str();
  add("--icp-inlier-fraction", evaluation.icpParameters.inlierFraction, "share of closest correspondences used per ICP "
                                                                        "step", heading::options)->capture_default_str();
  add("--icp-max-distance", evaluation.icpParameters.maxDistanceMm, "correspondences farther (mm) never used "
                                                                    "(default: no limit)", heading::options);
  command->add_flag("--exclude-beyond-reference-edge", evaluation.excludeBeyondReferenceEdge,
                    "leave out of the distances the model points whose closest reference point lies on the "
                    "reference's edge: beyond a partial reference's outline or over a hole in it (a synthetic scan's "
                    "static_surface.ply, where the tissue breathes); counted in points_beyond_reference_edge")
      ->group(heading::options);
  add("--coverage-radius-mm", evaluation.coverageRadiusMm, "coverage radius (0: no coverage, null in the JSON: for a reference such as groundtruth/instruments.ply, whose large area would take long to cover)", heading::options)->capture_default_str();
  command->callback([options] { runEval(*options); });
}

}  // namespace tissuemosaic::cli
