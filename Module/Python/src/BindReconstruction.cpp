// Reconstruction: process() frame by frame (the GIL released), the frame result, model(), save(), trajectory() and
// the runtime table.
#include "Arrays.h"
#include "Bindings.h"
#include "Parameters.h"
#include "Reconstruction.h"

#include "Core/Error.h"
#include "IO/PointCloudPly.h"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <Eigen/Geometry>

#include <cmath>

namespace tissuemosaic::python {

namespace {

/// One frame's result, converted for Python once (the engine's FrameResult stays in C++).
struct PyFrameResult {
  int frameIndex = 0;
  std::string status, sceneMotion, message;
  py::array_t<double> pose;
  bool isKeyFrame = false;
  py::dict agreement;
  int inliers = 0;
  std::size_t modelPoints = 0;
  py::dict timesMs;
  py::object disparity = py::none();
  double engineMs = 0;
  std::string repr() const {
    return "<tissuemosaic.FrameResult frame " + std::to_string(frameIndex) + " " + status +
           (isKeyFrame ? " key frame" : "") + ", " + std::to_string(modelPoints) + " model points>";
  }
};

py::object numberOrNone(double value) { return std::isfinite(value) ? py::object(py::float_(value)) : py::none(); }

PyFrameResult convert(const FrameResult& result, double engineMs) {
  PyFrameResult out;
  out.frameIndex = result.frameIndex;
  out.status = frameStatusName(result.status);
  out.sceneMotion = sceneMotionName(result.sceneMotion);
  out.message = result.trackingMessage;
  out.pose = toArray(result.T_world_camera);
  out.isKeyFrame = result.keyFrame;
  out.agreement["level"] = agreementLevelName(result.agreementLevel);
  out.agreement["measured"] = result.agreement.measured;
  out.agreement["median_depth_difference_mm"] = numberOrNone(result.agreement.medianDepthDifferenceMm);
  out.agreement["share_within_1mm"] = numberOrNone(result.agreement.shareWithin1mm);
  out.agreement["overlap"] = result.agreement.overlap();
  out.inliers = result.inliers;
  out.modelPoints = result.modelPoints;
  const StageTimesMs& t = result.timesMs;
  const std::pair<const char*, double> stages[] = {{"stereo", t.stereo}, {"orb_voting", t.orbVoting}, {"pnp", t.pnp},
                                                   {"agreement", t.agreement}, {"refinement", t.refinement},
                                                   {"tsdf", t.tsdf}, {"total", t.total}};
  for (const auto& [name, value] : stages) out.timesMs[name] = value;
  if (!result.disparityPx.empty()) out.disparity = toArray(result.disparityPx);
  out.engineMs = engineMs;
  return out;
}

/// An Nx3 array that owns the vector (moved, not copied).
template <class Element, class Scalar>
py::array ownedRows(std::vector<Element>&& rows) {
  static_assert(sizeof(Element) == 3 * sizeof(Scalar), "packed 3-vectors");
  auto* owned = new std::vector<Element>(std::move(rows));
  py::capsule owner(owned, [](void* pointer) { delete static_cast<std::vector<Element>*>(pointer); });
  return py::array_t<Scalar>({static_cast<py::ssize_t>(owned->size()), py::ssize_t{3}},
                             reinterpret_cast<const Scalar*>(owned->data()), owner);
}

struct Model {
  py::array points, colours, normals;
  std::size_t size() const { return static_cast<std::size_t>(points.shape(0)); }
};

Model toModel(ModelPoints&& model) {
  Model out;
  out.points = ownedRows<cv::Point3f, float>(std::move(model.cloud.pointsMm));
  out.colours = ownedRows<cv::Vec3b, std::uint8_t>(std::move(model.cloud.colorsRgb));
  out.normals = ownedRows<cv::Point3f, float>(std::move(model.cloud.normals));
  return out;
}

py::object toOpen3d(const Model& model) {
  py::module_ o3d;
  try {
    o3d = py::module_::import("open3d");
  } catch (py::error_already_set& error) {
    throw py::import_error("Model.to_open3d() needs Open3D (Debian: apt-get install python3-open3d; pip: open3d)");
  }
  const py::module_ np = py::module_::import("numpy");
  py::object cloud = o3d.attr("geometry").attr("PointCloud")();
  const py::object vectors = o3d.attr("utility").attr("Vector3dVector");
  cloud.attr("points") = vectors(model.points.attr("astype")(np.attr("float64")));
  if (model.colours.shape(0) == model.points.shape(0)) {
    cloud.attr("colors") = vectors(model.colours.attr("astype")(np.attr("float64")) / py::float_(255.0));
  }
  if (model.normals.shape(0) == model.points.shape(0)) {
    cloud.attr("normals") = vectors(model.normals.attr("astype")(np.attr("float64")));
  }
  return cloud;
}

/// TUM rows: t tx ty tz qx qy qz qw (mm), what the trajectory files hold.
py::array_t<double> tumArray(const Trajectory& trajectory) {
  py::array_t<double> out({static_cast<py::ssize_t>(trajectory.size()), py::ssize_t{8}});
  auto rows = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Matrix4d& T = trajectory[i].T_world_camera;
    const Eigen::Quaterniond q(Eigen::Matrix3d(T.topLeftCorner<3, 3>()));
    const double values[8] = {trajectory[i].timeS, T(0, 3), T(1, 3), T(2, 3), q.x(), q.y(), q.z(), q.w()};
    for (int c = 0; c < 8; ++c) rows(static_cast<py::ssize_t>(i), c) = values[c];
  }
  return out;
}

std::unique_ptr<Reconstruction> makeReconstruction(std::shared_ptr<Rig> rig, const py::object& params,
                                                   const std::string& device, const py::object& startPose,
                                                   bool keepDisparity) {
  Eigen::Matrix4d T_world_start = Eigen::Matrix4d::Identity();
  if (!startPose.is_none()) {
    const auto pose = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(startPose);
    if (!pose || pose.ndim() != 2 || pose.shape(0) != 4 || pose.shape(1) != 4) {
      throw py::value_error("start_pose: expected a 4x4 T_world_camera (mm)");
    }
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) T_world_start(r, c) = pose.at(r, c);
  }
  ReconstructionParameters parameters = readParameters(params);
  const Device chosen = readDevice(device);
  py::gil_scoped_release release;  // the pipeline is built here when the rig knows the frames' size
  return std::make_unique<Reconstruction>(std::move(rig), std::move(parameters), chosen, T_world_start,
                                          keepDisparity);
}

PyFrameResult process(Reconstruction& reconstruction, const py::array& left, const py::array& right, double timeS,
                      bool bgr) {
  // Views of the arrays, no copy: the engine reads RGB frames in their order (ReconstructionPipeline::process).
  const cv::Mat leftImage = imageView(left, "left"), rightImage = imageView(right, "right");
  FrameResult result;
  double engineMs = 0;
  {
    py::gil_scoped_release release;
    result = reconstruction.process(leftImage, rightImage, !bgr, timeS, &engineMs);
  }
  return convert(result, engineMs);
}

}  // namespace

void bindReconstruction(py::module_& module) {
  py::class_<PyFrameResult>(module, "FrameResult", "One frame's result of Reconstruction.process().")
      .def_readonly("frame_index", &PyFrameResult::frameIndex)
      .def_readonly("status", &PyFrameResult::status, "\"tracked\", \"lost\" or \"relocalised\"")
      .def_readonly("pose", &PyFrameResult::pose, "4x4 T_world_camera of the left rectified camera, mm (float64)")
      .def_readonly("is_key_frame", &PyFrameResult::isKeyFrame)
      .def_readonly("agreement", &PyFrameResult::agreement,
                    "the model against the frame's depth: dict(level (none|good|fair|poor), measured, "
                    "median_depth_difference_mm, share_within_1mm, overlap) (docs/SCENE_MOTION.md)")
      .def_readonly("scene_motion", &PyFrameResult::sceneMotion, "unknown, still, camera, tissue or both")
      .def_readonly("message", &PyFrameResult::message, "why tracking was lost (empty when tracked)")
      .def_readonly("inliers", &PyFrameResult::inliers)
      .def_readonly("model_points", &PyFrameResult::modelPoints)
      .def_readonly("times_ms", &PyFrameResult::timesMs, "milliseconds per stage, as the paper's runtime table")
      .def_readonly("engine_ms", &PyFrameResult::engineMs, "milliseconds of the engine's process() alone")
      .def_readonly("disparity", &PyFrameResult::disparity,
                    "the frame's disparity (float32, NaN = none) with keep_disparity=True, else None")
      .def("__repr__", &PyFrameResult::repr);

  py::class_<Model>(module, "Model", "The fused model: world frame = the first left rectified camera, mm.")
      .def_readonly("points", &Model::points, "Nx3 float32, mm")
      .def_readonly("colours", &Model::colours, "Nx3 uint8 RGB")
      .def_readonly("normals", &Model::normals, "Nx3 float32 unit normals")
      .def("__len__", &Model::size)
      .def("to_open3d", &toOpen3d, "an open3d.geometry.PointCloud (needs Open3D)")
      .def("__repr__", [](const Model& m) { return "<tissuemosaic.Model " + std::to_string(m.size()) + " points>"; });

  module.def("read_model", [](const py::object& path) {
        ColoredPointCloud cloud = readPly(pathText(path, "path"));
        ModelPoints points;
        points.cloud = std::move(cloud);
        return toModel(std::move(points));
      }, py::arg("path"), "a model (or any point cloud) PLY file, such as save() writes, as a Model");

  py::class_<Reconstruction>(module, "Reconstruction", R"(The whole pipeline of the paper, frame by frame.

rig: a Rig; frames are taken as it describes them (raw for a calibration, which the engine rectifies; rectified for
Rig.rectified or from_file(..., rectified=True)). params: a dict with the parameter files' keys or a parameters file.
device: "cpu", "cuda" or "auto". start_pose: the first frame's 4x4 T_world_camera (default: identity, the world is
the first left rectified camera). keep_disparity: FrameResult.disparity holds each frame's disparity.)")
      .def(py::init(&makeReconstruction), py::arg("rig"), py::arg("params") = py::none(), py::arg("device") = "auto",
           py::arg("start_pose") = py::none(), py::arg("keep_disparity") = false)
      .def("process", &process, py::arg("left"), py::arg("right"), py::arg("time_s"), py::arg("bgr") = false,
           R"(Processes the next frame: HxWx3 uint8 RGB (bgr=True: BGR) or HxW uint8 grey, both the same size.
time_s: its time stamp (trajectories). Returns a FrameResult; lost tracking is reported there, never raised. The GIL
is released while the engine works; calls on one Reconstruction run one at a time.)")
      .def("model", [](const Reconstruction& r) {
             ModelPoints points;
             {
               py::gil_scoped_release release;
               points = r.model();
             }
             return toModel(std::move(points));
           }, "a copy of the fused model (Model); with fusion.deformation on, the tissue at rest (the canonical model)")
      .def("live_model", [](const Reconstruction& r) {
             ModelPoints points;
             {
               py::gil_scoped_release release;
               points = r.liveModel();
             }
             return toModel(std::move(points));
           }, "a copy of the fused model where the tissue is now (fusion.deformation on: model() moved by the last "
              "frame's deformation; model() itself otherwise)")
      .def("save", [](const Reconstruction& r, const py::object& path, const py::object& trajectory) {
             const std::string modelPath = pathText(path, "path");
             const std::string trajectoryPath = trajectory.is_none() ? "" : pathText(trajectory, "trajectory");
             py::gil_scoped_release release;
             r.save(modelPath, trajectoryPath);
           }, py::arg("path"), py::arg("trajectory") = py::none(),
           "writes the model as `tissuemosaic reconstruct --out` does (.ply; .vtp in builds with VTK), and the key "
           "frames' trajectory (TUM) as --trajectory does")
      .def("trajectory", [](const Reconstruction& r, const std::string& which) {
             if (which == "key_frames") return tumArray(r.keyFrameTrajectory());
             if (which == "frames") return tumArray(r.frameTrajectory());
             throw py::value_error("trajectory: expected \"key_frames\" or \"frames\", got '" + which + "'");
           }, py::arg("which") = "key_frames",
           "Nx8 float64 TUM rows (t tx ty tz qx qy qz qw; T_world_camera, mm): the key frames' refined poses, or every "
           "tracked frame's")
      .def("timing", [](const Reconstruction& r) {
             return py::module_::import("json").attr("loads")(r.timing().toJson());
           }, "the paper's runtime table as a dict: key_frames / other_frames -> count, median_ms, mean_ms, p99_ms")
      .def("timing_table", [](const Reconstruction& r) { return r.timing().format(); },
           "the runtime table as `tissuemosaic reconstruct` prints it")
      .def_property_readonly("frame_count", &Reconstruction::frameCount)
      .def_property_readonly("device", [](const Reconstruction& r) { return deviceLabel(r.device()); })
      .def_property_readonly("disparity_range", &Reconstruction::disparityRangeDescription,
                             "the disparity range used so far, one line");
}

}  // namespace tissuemosaic::python
