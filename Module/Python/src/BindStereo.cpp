// stereo(): the left-view disparity of one pair (computePairDisparity, as `tissuemosaic stereo`), its depth in mm
// and the explanation counts.
#include "Arrays.h"
#include "Bindings.h"
#include "Parameters.h"
#include "Rig.h"

#include "Core/Error.h"
#include "Stereo/PairDisparity.h"

#include <pybind11/stl.h>

namespace tissuemosaic::python {

namespace {

struct StereoResult {
  py::array disparity;             ///< float32 HxW px, NaN = none
  py::object depthMm;              ///< float32 HxW mm, or None without a rig
  py::object explanation;          ///< dict, or None unless explain
  std::pair<int, int> rangePx;     ///< the range matched over
  std::string rangeDescription;
  py::dict timesMs;
};

StereoResult stereo(const py::array& left, const py::array& right, const std::shared_ptr<Rig>& rig,
                    const py::object& params, const std::string& device, const py::object& disparityRange,
                    bool explain, bool bgr) {
  StereoParameters parameters = readParameters(params).stereo;
  applyDisparityRange(disparityRange, parameters);
  parameters.validate();
  const Device chosen = readDevice(device);
  cv::Mat leftImage = engineImage(left, bgr, "left"), rightImage = engineImage(right, bgr, "right");
  PairDisparity result;
  cv::Mat depthMm;
  {
    py::gil_scoped_release release;
    require(leftImage.size() == rightImage.size(), cv::format("the left image is %dx%d but the right one %dx%d",
                                                              leftImage.cols, leftImage.rows, rightImage.cols,
                                                              rightImage.rows));
    std::shared_ptr<const StereoGeometry> geometry;
    if (rig) {
      geometry = rig->resolve(leftImage.size(), "the images given");
      if (geometry->rectifier) {
        cv::Mat leftRectified, rightRectified;
        geometry->rectifier->rectify(leftImage, rightImage, leftRectified, rightRectified);
        leftImage = leftRectified;
        rightImage = rightRectified;
      }
    }
    requireDisparityRangeMeetsImage(parameters, leftImage.cols);
    require(parameters.disparityRangeMode != DisparityRangeMode::WorkingDistance || geometry,
            "a working distance (the parameters' disparity range) needs the rig to become disparities: give rig=");
    result = computePairDisparity(leftImage, rightImage, parameters, geometry ? geometry->rectified : RectifiedGeometry{},
                                  chosen, explain);
    if (geometry) depthMm = disparityToDepthMm(result.disparityPx, geometry->rectified);
  }
  StereoResult out;
  out.disparity = toArray(result.disparityPx);
  out.depthMm = depthMm.empty() ? py::object(py::none()) : py::object(toArray(depthMm));
  out.explanation = explain ? py::module_::import("json").attr("loads")(result.explanation.json()) : py::none();
  if (result.range.current) out.rangePx = {result.range.current->minPx, result.range.current->maxPx};
  out.rangeDescription = result.rangeDescription;
  out.timesMs["zncc"] = result.timings.zncc;
  out.timesMs["outliers_holes"] = result.timings.outliersHoles;
  out.timesMs["refinement"] = result.timings.refinement;
  out.timesMs["total"] = result.timings.total();
  return out;
}

}  // namespace

void bindStereo(py::module_& module) {
  py::class_<StereoResult>(module, "StereoResult", "What stereo() returns.")
      .def_readonly("disparity", &StereoResult::disparity,
                    "left-view disparity, float32 HxW px (left x matches right x - d), NaN where none")
      .def_readonly("depth_mm", &StereoResult::depthMm, "depth along the rectified left axis, float32 mm (None without rig)")
      .def_readonly("explanation", &StereoResult::explanation,
                    "with explain=True: how many pixels each step removed and hole filling gave back (docs/STEREO.md)")
      .def_readonly("disparity_range", &StereoResult::rangePx, "(min_px, max_px) matched over")
      .def_readonly("disparity_range_description", &StereoResult::rangeDescription)
      .def_readonly("times_ms", &StereoResult::timesMs);
  module.def("stereo", &stereo, py::arg("left"), py::arg("right"), py::arg("rig") = nullptr,
             py::arg("params") = py::none(), py::arg("device") = "auto", py::arg("disparity_range") = "auto",
             py::arg("explain") = false, py::arg("bgr") = false,
             R"(The left-view disparity of one stereo pair (paper section II, or AD-Census with params
{"stereo": {"method": "ad-census"}}), as ``tissuemosaic stereo``.

left, right: HxWx3 uint8 RGB (bgr=True: BGR, as OpenCV reads them) or HxW uint8 grey, the same size. With a rig
of a calibration the pair is rectified first; the rig also gives depth_mm. params: a dict with the parameter
files' nodes and keys, or a parameters file. disparity_range: "auto" (chosen from the pair's feature matches),
(min_px, max_px), or None for the parameters' range. device: "cpu", "cuda" or "auto". The GIL is released while
the engine works. Raises tissuemosaic.Error (a ValueError) with the engine's message.)");
}

}  // namespace tissuemosaic::python
