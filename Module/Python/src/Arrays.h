#pragma once
/// @file Arrays.h
/// @brief numpy arrays to and from cv::Mat without copies where the layout allows, and the module's image rule:
/// images are HxWx3 uint8 RGB (bgr=True: BGR, as OpenCV gives them) or HxW uint8 grey.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

namespace tissuemosaic::python {

namespace py = pybind11;

/// A cv::Mat header over an image array (no copy): HxWx3 or HxW uint8 with unit channel stride. Raises TypeError for
/// another dtype, ValueError for another shape; `what` names the argument. The array must outlive the header.
cv::Mat imageView(const py::array& image, const std::string& what);
/// The engine's 8-bit BGR (or grey) frame of an image array: the view itself when bgr or grey, else a converted copy.
cv::Mat engineImage(const py::array& image, bool bgr, const std::string& what);
/// An array that owns `mat` (continuous; its data is shared, not copied): HxW or HxWxC.
py::array toArray(const cv::Mat& mat);
/// An 8-bit BGR (or grey) engine image as the user asked for it: RGB unless bgr.
py::array toUserImage(const cv::Mat& bgrOrGrey, bool bgr);
/// A 4x4 pose as a float64 numpy array (a copy: 128 bytes).
py::array_t<double> toArray(const Eigen::Matrix4d& pose);

}  // namespace tissuemosaic::python
