// The extension module tissuemosaic._tissuemosaic: the engine for Python (docs/PYTHON.md). The package
// tissuemosaic/__init__.py re-exports it.
#include "Bindings.h"
#include "Parameters.h"

#include "Core/Device.h"
#include "Core/Error.h"

PYBIND11_MODULE(_tissuemosaic, module) {
  namespace py = pybind11;
  using namespace tissuemosaic;
  module.doc() = "TissueMosaic: dense 3D reconstruction of tissue surfaces from stereo video (docs/PYTHON.md)";
  // Every engine error is a tissuemosaic.Error, a ValueError, carrying the engine's (the command line's) message.
  py::register_exception<Error>(module, "Error", PyExc_ValueError);
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
