// The extension module tissuemosaic._tissuemosaic: the engine for Python (docs/PYTHON.md). The package
// tissuemosaic/__init__.py re-exports it.
#include "Bindings.h"
#include "Parameters.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/ParameterError.h"

#include <map>
#include <string>

namespace {

/// The Python argument for each engine parameter a ParameterError names (Core/ParameterError.h); "" for a value
/// Python does not take (e.g. eval's alignment limit), whose message then comes as it is.
std::string pythonArgument(const std::string& parameter) {
  static const std::map<std::string, std::string> names = {
      {"focalPx", "focal_px"},         {"baselineMm", "baseline_mm"},   {"cxPx", "cx_px"},
      {"cyPx", "cy_px"},               {"doffsPx", "doffs_px"},         {"device", "device"},
      {"disparityRange", "disparity_range"}, {"calibration", "path"}, {"rightCalibration", "right"},
      {"extrinsicsCalibration", "extrinsics"}, {"modelPath", "path"}};
  const auto found = names.find(parameter);
  return found != names.end() ? found->second : std::string();
}

}  // namespace

PYBIND11_MODULE(_tissuemosaic, module) {
  namespace py = pybind11;
  using namespace tissuemosaic;
  module.doc() = "TissueMosaic: dense 3D reconstruction of tissue surfaces from stereo video (docs/PYTHON.md)";
  // Every engine error is a tissuemosaic.Error, a ValueError, carrying the engine's (the command line's) message.
  static py::exception<Error> error = py::register_exception<Error>(module, "Error", PyExc_ValueError);
  // An error about one argument names it as Python spells it: "focal_px: the focal length must be ...".
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const ParameterError& e) {
      const std::string argument = pythonArgument(e.parameter());
      error((argument.empty() ? std::string(e.what()) : argument + ": " + e.what()).c_str());
    }
  });
  module.def("cuda_available", &cudaAvailable, "True when this build has CUDA and a GPU is usable");
  module.def("cuda_compiled_in", &cudaCompiledIn, "True when this build has the CUDA backend");
  module.def("device_description", [](const std::string& device) { return deviceDescription(parseDevice(device)); },
             py::arg("device") = "auto", "the CPU model and threads, or the GPU's name");
  python::bindRig(module);
  python::bindStereo(module);
  python::bindReconstruction(module);
  python::bindFrames(module);
  python::bindSynth(module);
  python::bindEvaluate(module);
  python::bindFiles(module);
  module.def("default_params", [] { return python::parametersDict(ReconstructionParameters{}); },
             "the paper's defaults as a dict with the parameter files' nodes and keys");
}
