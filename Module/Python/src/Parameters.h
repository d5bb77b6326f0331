#pragma once
/// @file Parameters.h
/// @brief The module's parameters and device arguments, read by the engine's own readers: a dict with the parameter
/// files' nodes and keys (nested: {"stereo": {"znccWindowPx": 11}}), or the path of a parameters file.
#include "Core/Device.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/StereoParameters.h"

#include <pybind11/pybind11.h>

namespace tissuemosaic::python {

namespace py = pybind11;

/// None: the paper's defaults; a dict: its JSON text read by ReconstructionParameters::parse (unknown keys are an
/// Error naming the nearest known one); a str or os.PathLike: readFile. Validated.
ReconstructionParameters readParameters(const py::object& params);
/// "cpu", "cuda" or "auto" (parseDevice: Error for cuda where CUDA cannot be used, saying why).
Device readDevice(const std::string& device);
/// disparity_range: None keeps the parameters' range, "auto" chooses it from the frames, (min_px, max_px) fixes it.
void applyDisparityRange(const py::object& range, StereoParameters& parameters);
/// The parameters as a dict with the parameter files' nodes and keys (what writeFile writes).
py::dict parametersDict(const ReconstructionParameters& parameters);
/// A str or os.PathLike as a path.
std::string pathText(const py::object& path, const char* what);

}  // namespace tissuemosaic::python
