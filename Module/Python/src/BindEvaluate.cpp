// evaluate(): a model scored against a reference surface as `tissuemosaic eval --json` scores it (the same readers,
// evaluateModel and report; docs/EVALUATION.md). Needs the VTK logic: builds without it raise.
#include "Bindings.h"
#include "Parameters.h"

#include "Core/Error.h"

#if defined(TM_PYTHON_WITH_EVALUATION)
#include "vtkTissueMosaicEvaluationReport.h"
#endif

#include <Eigen/Geometry>
#include <pybind11/numpy.h>

namespace tissuemosaic::python {

namespace {

#if defined(TM_PYTHON_WITH_EVALUATION)
/// A path, a Model (its .points) or an Nx3 array, as finite points.
std::vector<Eigen::Vector3d> modelPoints(const py::object& model, std::size_t* nonFinite) {
  if (py::isinstance<py::str>(model) || py::hasattr(model, "__fspath__")) {
    const std::string path = pathText(model, "model");
    py::gil_scoped_release release;
    return readEvaluationModelPoints(path, nonFinite);
  }
  const py::object source = py::hasattr(model, "points") ? model.attr("points") : model;
  const auto points = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(source);
  if (!points || points.ndim() != 2 || points.shape(1) != 3) {
    throw py::value_error("model: expected a path, a Model or an Nx3 array of points (mm)");
  }
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(points.shape(0)));
  for (py::ssize_t i = 0; i < points.shape(0); ++i) out[i] = {points.at(i, 0), points.at(i, 1), points.at(i, 2)};
  return evaluationModelPoints(std::move(out), nonFinite, "the model");
}

/// A TUM file, or Nx8 rows (t tx ty tz qx qy qz qw) as Reconstruction.trajectory() gives them.
Trajectory trajectoryArgument(const py::object& trajectory, const char* what) {
  if (py::isinstance<py::str>(trajectory) || py::hasattr(trajectory, "__fspath__")) {
    return readEvaluationTrajectory(pathText(trajectory, what));
  }
  const auto rows = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(trajectory);
  if (!rows || rows.ndim() != 2 || rows.shape(1) != 8) {
    throw py::value_error(std::string(what) + ": expected a TUM file or Nx8 rows (t tx ty tz qx qy qz qw)");
  }
  Trajectory out;
  for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
    TimedPose pose;
    pose.timeS = rows.at(i, 0);
    const Eigen::Quaterniond q(rows.at(i, 7), rows.at(i, 4), rows.at(i, 5), rows.at(i, 6));
    pose.T_world_camera.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix();
    pose.T_world_camera.topRightCorner<3, 1>() = Eigen::Vector3d(rows.at(i, 1), rows.at(i, 2), rows.at(i, 3));
    out.push_back(pose);
  }
  require(!out.empty(), std::string(what) + " holds no pose");
  return out;
}
#endif

py::object evaluate(const py::object& model, const py::object& reference, const py::object& trajectory,
                    const py::object& referenceTrajectory, const std::string& align,
                    const std::string& trajectoryAlignment, double coverageRadiusMm, double timeToleranceS,
                    bool excludeBeyondReferenceEdge) {
#if defined(TM_PYTHON_WITH_EVALUATION)
  if (trajectory.is_none() != referenceTrajectory.is_none()) {
    throw py::value_error("trajectory and reference_trajectory go together");
  }
  EvaluationOptions options;
  require(align == "icp" || align == "none", "unknown align '" + align + "': expected icp or none");
  options.icp = align == "icp";
  require(trajectoryAlignment == "rigid" || trajectoryAlignment == "none",
          "unknown trajectory_alignment '" + trajectoryAlignment + "': expected rigid or none");
  options.alignTrajectories = trajectoryAlignment == "rigid";
  options.coverageRadiusMm = coverageRadiusMm;
  options.timeToleranceS = timeToleranceS;
  options.excludeBeyondReferenceEdge = excludeBeyondReferenceEdge;
  options.validate();
  std::size_t nonFinite = 0;
  const std::vector<Eigen::Vector3d> points = modelPoints(model, &nonFinite);
  const std::string referencePath = pathText(reference, "reference");
  std::optional<EvaluationTrajectories> trajectories;
  if (!trajectory.is_none()) {
    trajectories = EvaluationTrajectories{trajectoryArgument(trajectory, "trajectory"),
                                          trajectoryArgument(referenceTrajectory, "reference_trajectory")};
  }
  std::string json;
  {
    py::gil_scoped_release release;
    const TargetSurface surface(readEvaluationReference(referencePath));
    const ModelEvaluation evaluation = evaluateModel(points, surface, trajectories ? &*trajectories : nullptr, options);
    json = evaluationReportJson(evaluationReport(evaluation, options, nonFinite));
  }
  return py::module_::import("json").attr("loads")(json);
#else
  (void)model, (void)reference, (void)trajectory, (void)referenceTrajectory, (void)align, (void)trajectoryAlignment,
      (void)coverageRadiusMm, (void)timeToleranceS, (void)excludeBeyondReferenceEdge;
  throw py::value_error("evaluate() needs the VTK logic: this module was built without it (-DTM_WITH_GUI=OFF)");
#endif
}

}  // namespace

void bindEvaluate(py::module_& module) {
  module.def("evaluate", &evaluate, py::arg("model"), py::arg("reference"), py::arg("trajectory") = py::none(),
             py::arg("reference_trajectory") = py::none(), py::arg("align") = "none",
             py::arg("trajectory_alignment") = "rigid", py::arg("coverage_radius_mm") = 1.0,
             py::arg("time_tolerance_s") = 0.02, py::arg("exclude_beyond_reference_edge") = false,
             R"(Scores a model against a reference surface as ``tissuemosaic eval --json`` does (docs/EVALUATION.md)
and returns its figures as a dict with the same keys: rmse_mm, mean_mm, p95_mm, coverage, ate_mm, rpe_mm, then
median_mm, max_mm, share_within_1mm, points, ... model: a path, a Model or an Nx3 array (mm); reference: a mesh
file (.ply with triangles, .stl, .vtp, .vtk, .obj); trajectory and reference_trajectory: TUM files or Nx8 arrays
(Reconstruction.trajectory()), which place the model by their rigid alignment. align="icp" refines the placement.)");
}

}  // namespace tissuemosaic::python
