#pragma once
/// @file Bindings.h
/// @brief One function per part of the Python API, each in its own file, called by the module's entry (Module.cpp).
#include <pybind11/pybind11.h>

namespace tissuemosaic::python {

namespace py = pybind11;

void bindRig(py::module_& module);
void bindStereo(py::module_& module);
void bindReconstruction(py::module_& module);
void bindFrames(py::module_& module);
void bindSynth(py::module_& module);
void bindEvaluate(py::module_& module);
void bindFiles(py::module_& module);

}  // namespace tissuemosaic::python
