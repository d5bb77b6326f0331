// Rig: Rig.from_file (every calibration layout the command line reads), Rig.rectified, the rectified intrinsics,
// the rectification maps and rectify().
#include "Arrays.h"
#include "Bindings.h"
#include "Parameters.h"
#include "Rig.h"

#include "Core/Error.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <pybind11/stl.h>

namespace tissuemosaic::python {

namespace {

std::optional<cv::Size> sizeArgument(const py::object& size) {
  if (size.is_none()) return std::nullopt;
  const py::tuple pair = py::tuple(py::sequence(size));
  if (pair.size() != 2) throw py::value_error("image_size: expected (width, height)");
  const int width = pair[0].cast<int>(), height = pair[1].cast<int>();
  if (width <= 0 || height <= 0) throw py::value_error("image_size: expected positive (width, height)");
  return cv::Size(width, height);
}

py::object sizeTuple(const std::optional<cv::Size>& size) {
  if (!size) return py::none();
  return py::make_tuple(size->width, size->height);
}

std::shared_ptr<Rig> fromFile(const py::object& path, const py::object& extrinsics, const py::object& right,
                              bool rectified) {
  CalibrationFiles files;
  files.calib = pathText(path, "path");
  if (!extrinsics.is_none()) files.extrinsics = pathText(extrinsics, "extrinsics");
  if (!right.is_none()) files.right = pathText(right, "right");
  if (!files.extrinsics.empty() && !files.right.empty()) {
    throw py::value_error("give extrinsics (stereo_calib sample) or right (ROS camera_info), not both");
  }
  StereoGeometrySpec spec;
  {
    py::gil_scoped_release release;
    spec.calibration = readCalibrationFiles(files);
  }
  spec.framesRectified = rectified;
  const std::string description = "calibration '" + files.calib + "' (" + spec.calibration->layout + ")" +
                                  (rectified ? ", frames already rectified" : "");
  return std::make_shared<Rig>(std::move(spec), description);
}

std::shared_ptr<Rig> fromPinhole(double focalPx, double baselineMm, std::optional<double> cxPx,
                                 std::optional<double> cyPx, double doffsPx, const py::object& imageSize) {
  StereoGeometrySpec spec;
  spec.focalPx = focalPx;
  spec.baselineMm = baselineMm;
  spec.cxPx = cxPx;
  spec.cyPx = cyPx;
  spec.doffsPx = doffsPx;
  const std::string description = cv::format("rectified: focal %g px, baseline %g mm", focalPx, baselineMm);
  return std::make_shared<Rig>(std::move(spec), description, sizeArgument(imageSize));
}

py::dict intrinsics(const Rig& rig, const py::object& imageSize) {
  const std::shared_ptr<const StereoGeometry> geometry = rig.resolveFor(sizeArgument(imageSize));
  const RectifiedGeometry& g = geometry->rectified;
  py::dict out;
  out["width"] = g.imageSize.width;
  out["height"] = g.imageSize.height;
  out["focal_px"] = g.focalPx;
  out["cx_px"] = g.cxLeftPx;
  out["cy_px"] = g.cyPx;
  out["doffs_px"] = g.doffsPx;
  out["baseline_mm"] = g.baselineMm;
  out["K"] = toArray(cv::Mat(cv::Matx33d(g.focalPx, 0, g.cxLeftPx, 0, g.focalPx, g.cyPx, 0, 0, 1)));
  out["Q"] = g.Q.empty() ? py::object(py::none()) : py::object(toArray(g.Q.clone()));
  return out;
}

py::dict maps(const Rig& rig, const py::object& imageSize) {
  const std::shared_ptr<const StereoGeometry> geometry = rig.resolveFor(sizeArgument(imageSize));
  require(geometry->calibration.has_value(), "a rig of rectified frames (Rig.rectified) has no rectification maps");
  // The rectifier's own R and P (cv::stereoRectify's, or the file's given rectification), as float maps for cv2.remap.
  const StereoRectifier rectifier(*geometry->calibration);
  const StereoCalibration& c = *geometry->calibration;
  cv::Mat leftX, leftY, rightX, rightY;
  cv::initUndistortRectifyMap(c.K1, c.D1, rectifier.leftRectificationRotation(), rectifier.leftProjection(),
                              c.imageSize, CV_32FC1, leftX, leftY);
  cv::initUndistortRectifyMap(c.K2, c.D2, rectifier.rightRectificationRotation(), rectifier.rightProjection(),
                              c.imageSize, CV_32FC1, rightX, rightY);
  py::dict out;
  out["left"] = py::make_tuple(toArray(leftX), toArray(leftY));
  out["right"] = py::make_tuple(toArray(rightX), toArray(rightY));
  return out;
}

py::tuple rectify(const Rig& rig, const py::array& left, const py::array& right, bool bgr) {
  const cv::Mat leftImage = engineImage(left, bgr, "left"), rightImage = engineImage(right, bgr, "right");
  cv::Mat leftRectified, rightRectified;
  {
    py::gil_scoped_release release;
    require(leftImage.size() == rightImage.size(), cv::format("the left image is %dx%d but the right one %dx%d",
                                                              leftImage.cols, leftImage.rows, rightImage.cols,
                                                              rightImage.rows));
    const std::shared_ptr<const StereoGeometry> geometry = rig.resolve(leftImage.size(), "the images given");
    if (geometry->rectifier) {
      geometry->rectifier->rectify(leftImage, rightImage, leftRectified, rightRectified);
    } else {
      leftRectified = leftImage;
      rightRectified = rightImage;
    }
  }
  return py::make_tuple(toUserImage(leftRectified, bgr), toUserImage(rightRectified, bgr));
}

py::object calibrationDict(const Rig& rig) {
  if (!rig.spec().calibration) return py::none();
  const StereoCalibration& c = rig.spec().calibration->calibration;
  py::dict out;
  const std::pair<const char*, const cv::Mat*> matrices[] = {{"K1", &c.K1}, {"D1", &c.D1}, {"K2", &c.K2},
                                                              {"D2", &c.D2}, {"R", &c.R},   {"T_mm", &c.T}};
  for (const auto& [name, matrix] : matrices) out[name] = toArray(matrix->clone());
  out["image_size"] = sizeTuple(c.imageSize.empty() ? std::nullopt : std::optional<cv::Size>(c.imageSize));
  return out;
}

}  // namespace

void bindRig(py::module_& module) {
  py::class_<Rig, std::shared_ptr<Rig>>(module, "Rig", R"(A stereo rig: a calibration file, or the geometry of rectified frames.

Frames given with a rig are taken as the rig describes them: raw (unrectified) for a calibration unless
``rectified=True`` (the engine rectifies them), rectified for ``Rig.rectified``. Units: millimetres and pixels.)")
      .def_static("from_file", &fromFile, py::arg("path"), py::arg("extrinsics") = py::none(),
                  py::arg("right") = py::none(), py::arg("rectified") = false,
                  R"(Reads a calibration in any layout the command line reads (docs/CALIBRATION.md): OpenCV
stereoCalibrate names (K1 D1 K2 D2 R T), OpenCV's stereo_calib sample / SCARED / SurgT (intrinsics.yml with
``extrinsics='extrinsics.yml'``), ROS camera_info (the left eye's file with ``right='right.yaml'``), Kalibr
camchain.yaml, MATLAB stereoParameters. ``rectified=True``: the frames are already rectified with it (as
``tissuemosaic reconstruct --rectified``). Raises tissuemosaic.Error naming the missing or malformed key.)")
      .def_static("rectified", &fromPinhole, py::arg("focal_px"), py::arg("baseline_mm"), py::arg("cx_px") = py::none(),
                  py::arg("cy_px") = py::none(), py::arg("doffs_px") = 0.0, py::arg("image_size") = py::none(),
                  R"(The geometry of rectified frames: focal length (px), baseline (mm), the left principal point
(default: the image centre) and doffs = cx_right - cx_left (depth = f B / (d + doffs)). image_size=(width, height)
is optional: the frames give it.)")
      .def_property_readonly("layout", [](const Rig& rig) -> py::object {
            if (!rig.spec().calibration) return py::none();
            return py::str(rig.spec().calibration->layout);
          }, "the calibration file's layout (None for Rig.rectified)")
      .def_property_readonly("image_size", [](const Rig& rig) { return sizeTuple(rig.imageSize()); },
                             "(width, height) the rig is for, or None when the frames give it")
      .def_property_readonly("frames_rectified", [](const Rig& rig) {
            return !rig.spec().calibration || rig.spec().framesRectified;
          }, "True when the frames given with this rig are taken as rectified")
      .def_property_readonly("description", &Rig::description)
      .def("calibration", &calibrationDict, "K1 D1 K2 D2 R T_mm (X_right = R X_left + T) and image_size, or None")
      .def("intrinsics", &intrinsics, py::arg("image_size") = py::none(),
           "the rectified left camera: dict(width, height, focal_px, cx_px, cy_px, doffs_px, baseline_mm, K, Q)")
      .def("maps", &maps, py::arg("image_size") = py::none(),
           "the rectification maps for cv2.remap: dict(left=(map_x, map_y), right=(map_x, map_y)), float32")
      .def("rectify", &rectify, py::arg("left"), py::arg("right"), py::arg("bgr") = false,
           "the rectified pair (the frames unchanged for a rig of rectified frames); images as given (RGB unless bgr)")
      .def("__repr__", [](const Rig& rig) { return "<tissuemosaic.Rig " + rig.description() + ">"; });
}

}  // namespace tissuemosaic::python
