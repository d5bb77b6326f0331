// The engine's file readers and the disparity scorer, for scripts without OpenCV: read_image, read_pfm, write_pfm,
// score_disparity (what `tissuemosaic stereo --ground-truth` prints).
#include "Arrays.h"
#include "Bindings.h"
#include "Parameters.h"

#include "Core/Error.h"
#include "IO/DisparityPfm.h"
#include "IO/ImageFile.h"
#include "Stereo/DisparityScore.h"

namespace tissuemosaic::python {

namespace {

cv::Mat floatView(const py::array& array, const char* what) {
  const auto floats = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!floats || floats.ndim() != 2) throw py::value_error(std::string(what) + ": expected an HxW float32 array");
  // A copy (forcecast may have made one already): the score reads it after the GIL is released.
  return cv::Mat(static_cast<int>(floats.shape(0)), static_cast<int>(floats.shape(1)), CV_32F,
                 const_cast<float*>(floats.data()))
      .clone();
}

py::dict score(const py::array& disparity, const py::array& truth, const py::object& mask) {
  const cv::Mat estimate = floatView(disparity, "disparity"), groundTruth = floatView(truth, "truth");
  cv::Mat maskImage;
  if (!mask.is_none()) {
    const auto bytes = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(mask);
    if (!bytes || bytes.ndim() != 2) throw py::value_error("mask: expected an HxW uint8 array (nonzero = evaluate)");
    maskImage = cv::Mat(static_cast<int>(bytes.shape(0)), static_cast<int>(bytes.shape(1)), CV_8U,
                        const_cast<std::uint8_t*>(bytes.data()))
                    .clone();
  }
  const DisparityScore s = scoreDisparity(estimate, groundTruth, maskImage);
  require(s.evaluated > 0, "the ground truth has no known pixel");
  py::dict out;
  out["density"] = s.density;
  out["bad1"] = s.badOver1;
  out["bad2"] = s.badOver2;
  out["mean_abs_error_px"] = s.meanAbsError;
  out["evaluated"] = s.evaluated;
  out["estimated"] = s.estimated;
  return out;
}

}  // namespace

void bindFiles(py::module_& module) {
  module.def("read_image", [](const py::object& path, bool bgr) {
        return toUserImage(loadImage(pathText(path, "path")), bgr);
      }, py::arg("path"), py::arg("bgr") = false,
      "an image file (PNG/JPEG/...; palette images decoded) as HxWx3 uint8 RGB (bgr=True: BGR)");
  module.def("read_pfm", [](const py::object& path) { return toArray(readPfm(pathText(path, "path"))); },
             py::arg("path"), "a PFM file (disparity: float32 HxW, NaN = unknown)");
  module.def("write_pfm", [](const py::object& path, const py::array& image) {
        writePfm(pathText(path, "path"), floatView(image, "image"));
      }, py::arg("path"), py::arg("image"), "writes an HxW float32 array as PFM (NaN = unknown)");
  module.def("score_disparity", &score, py::arg("disparity"), py::arg("truth"), py::arg("mask") = py::none(),
             R"(Scores a disparity against ground truth as ``tissuemosaic stereo --ground-truth`` does: dict(density,
bad1, bad2 (shares of estimated pixels off by more than 1 or 2 px), mean_abs_error_px, evaluated, estimated). NaN
in truth = unknown; mask: HxW uint8, nonzero = evaluate.)");
}

}  // namespace tissuemosaic::python
