#include "Arrays.h"

#include <opencv2/imgproc.hpp>

namespace tissuemosaic::python {

cv::Mat imageView(const py::array& image, const std::string& what) {
  if (image.dtype().kind() != 'u' || image.itemsize() != 1) {
    throw py::type_error(what + ": expected a uint8 image array, got dtype " +
                         py::str(static_cast<py::object>(image.dtype())).cast<std::string>());
  }
  const bool grey = image.ndim() == 2;
  if (!grey && !(image.ndim() == 3 && image.shape(2) == 3)) {
    std::string shape = "(";
    for (py::ssize_t i = 0; i < image.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(image.shape(i));
    throw py::value_error(what + ": expected an HxWx3 (RGB) or HxW (grey) image, got shape " + shape + ")");
  }
  const int rows = static_cast<int>(image.shape(0)), cols = static_cast<int>(image.shape(1));
  if (rows == 0 || cols == 0) throw py::value_error(what + ": the image is empty");
  const py::ssize_t pixelStride = grey ? 1 : 3;
  if (image.strides(1) != pixelStride || (!grey && image.strides(2) != 1) || image.strides(0) < cols * pixelStride) {
    throw py::value_error(what + ": the image's pixels are not packed (pass numpy.ascontiguousarray(image))");
  }
  // cv::Mat wants a non-const pointer; the engine only reads its input frames.
  return cv::Mat(rows, cols, grey ? CV_8UC1 : CV_8UC3, const_cast<void*>(image.data()),
                 static_cast<std::size_t>(image.strides(0)));
}

cv::Mat engineImage(const py::array& image, bool bgr, const std::string& what) {
  const cv::Mat view = imageView(image, what);
  if (bgr || view.channels() == 1) return view;
  cv::Mat converted;
  cv::cvtColor(view, converted, cv::COLOR_RGB2BGR);
  return converted;
}

py::array toArray(const cv::Mat& mat) {
  const cv::Mat continuous = mat.isContinuous() ? mat : mat.clone();
  auto* owned = new cv::Mat(continuous);
  py::capsule owner(owned, [](void* pointer) { delete static_cast<cv::Mat*>(pointer); });
  py::dtype dtype;
  switch (mat.depth()) {
    case CV_8U: dtype = py::dtype::of<std::uint8_t>(); break;
    case CV_16U: dtype = py::dtype::of<std::uint16_t>(); break;
    case CV_32F: dtype = py::dtype::of<float>(); break;
    case CV_64F: dtype = py::dtype::of<double>(); break;
    default: throw std::logic_error("toArray: unsupported cv::Mat depth");
  }
  const py::ssize_t item = static_cast<py::ssize_t>(owned->elemSize1());
  const py::ssize_t channels = owned->channels();
  if (channels == 1) {
    return py::array(dtype, {static_cast<py::ssize_t>(owned->rows), static_cast<py::ssize_t>(owned->cols)},
                     {static_cast<py::ssize_t>(owned->step[0]), item}, owned->data, owner);
  }
  return py::array(dtype,
                   {static_cast<py::ssize_t>(owned->rows), static_cast<py::ssize_t>(owned->cols), channels},
                   {static_cast<py::ssize_t>(owned->step[0]), item * channels, item}, owned->data, owner);
}

py::array toUserImage(const cv::Mat& bgrOrGrey, bool bgr) {
  if (bgr || bgrOrGrey.channels() == 1) return toArray(bgrOrGrey);
  cv::Mat rgb;
  cv::cvtColor(bgrOrGrey, rgb, cv::COLOR_BGR2RGB);
  return toArray(rgb);
}

py::array_t<double> toArray(const Eigen::Matrix4d& pose) {
  py::array_t<double> out({4, 4});
  auto view = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) view(r, c) = pose(r, c);
  return out;
}

}  // namespace tissuemosaic::python
