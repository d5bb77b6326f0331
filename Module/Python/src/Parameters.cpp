#include "Parameters.h"

#include "Core/Error.h"

#include <opencv2/core.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace tissuemosaic::python {

std::string pathText(const py::object& path, const char* what) {
  const py::module_ os = py::module_::import("os");
  if (!py::isinstance<py::str>(path) && !py::hasattr(path, "__fspath__")) {
    throw py::type_error(std::string(what) + ": expected a path (str or os.PathLike), got " +
                         py::str(path.get_type().attr("__name__")).cast<std::string>());
  }
  return py::str(os.attr("fspath")(path)).cast<std::string>();
}

ReconstructionParameters readParameters(const py::object& params) {
  if (params.is_none()) return ReconstructionParameters{};
  if (py::isinstance<py::dict>(params)) {
    // JSON is a text the parameter files' reader takes (OpenCV's JSON, after yaml-cpp's guard).
    const std::string text = py::module_::import("json").attr("dumps")(params).cast<std::string>();
    return ReconstructionParameters::parse(text);
  }
  return ReconstructionParameters::readFile(pathText(params, "params"));
}

Device readDevice(const std::string& device) { return parseDevice(device); }

void applyDisparityRange(const py::object& range, StereoParameters& parameters) {
  if (range.is_none()) return;
  if (py::isinstance<py::str>(range)) {
    const std::string text = range.cast<std::string>();
    if (text != "auto") {
      throw py::value_error("disparity_range: expected \"auto\", None or (min_px, max_px), got '" + text + "'");
    }
    parameters.disparityRangeMode = DisparityRangeMode::Automatic;
    return;
  }
  const py::tuple pair = py::tuple(py::sequence(range));
  if (pair.size() != 2) throw py::value_error("disparity_range: expected (min_px, max_px)");
  const int minPx = pair[0].cast<int>(), maxPx = pair[1].cast<int>();
  if (minPx >= maxPx) throw py::value_error("disparity_range: expected min_px < max_px");
  parameters.setFixedDisparityRange(minPx, maxPx);
}

py::dict parametersDict(const ReconstructionParameters& parameters) {
  // writeFile is the one writer of every key; OpenCV writes JSON when the name ends in .json.
  char name[] = "/tmp/tissuemosaic-params-XXXXXX";
  const int descriptor = mkstemp(name);
  require(descriptor >= 0, "cannot create a temporary file for the parameters");
  close(descriptor);
  const std::string path = std::string(name) + ".json";
  std::rename(name, path.c_str());
  std::string text;
  try {
    parameters.writeFile(path);
    std::ifstream file(path);
    std::stringstream content;
    content << file.rdbuf();
    text = content.str();
  } catch (...) {
    std::filesystem::remove(path);
    throw;
  }
  std::filesystem::remove(path);
  return py::module_::import("json").attr("loads")(text).cast<py::dict>();
}

}  // namespace tissuemosaic::python
