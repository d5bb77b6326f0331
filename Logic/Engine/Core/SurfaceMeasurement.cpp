// measureSurface on either backend, and its CPU instantiation (the CUDA one is SurfaceMeasurementCuda.cu).
#include "SurfaceMeasurement.h"

#include "Error.h"
#include "SurfaceKernels.h"

#include <opencv2/imgproc.hpp>

#include <string>

namespace tissuemosaic {

namespace surface {

void measureSurfaceCpu(ImageView<const float> disparityPx, ImageView<Float3> pointsMm, ImageView<Float3> normals,
                       const Reprojection& reprojection, int normalRadiusPx, float maxDepthJumpMm) {
  measureSurfaceOn<CpuBackend>(disparityPx, pointsMm, normals, reprojection, normalRadiusPx, maxDepthJumpMm);
}

}  // namespace surface

SurfaceMeasurement measureSurface(const cv::Mat& disparityPx, const cv::Mat& leftRectified,
                                  const RectifiedGeometry& geometry, Device device, int normalRadiusPx,
                                  double maxDepthJumpMm) {
  require(!disparityPx.empty() && disparityPx.type() == CV_32FC1, "measureSurface: the disparity map must be a non-empty CV_32FC1 image");
  require(disparityPx.size() == geometry.imageSize,
          "measureSurface: the disparity map is " + std::to_string(disparityPx.cols) + "x" +
              std::to_string(disparityPx.rows) + " but the rectified images are " +
              std::to_string(geometry.imageSize.width) + "x" + std::to_string(geometry.imageSize.height));
  require(leftRectified.size() == disparityPx.size(),
          "measureSurface: the rectified left image and the disparity map must have the same size");
  require(leftRectified.depth() == CV_8U &&
              (leftRectified.channels() == 1 || leftRectified.channels() == 3 || leftRectified.channels() == 4),
          "measureSurface: the rectified left image must be 8-bit grey, BGR or BGRA");
  require(geometry.Q.rows == 4 && geometry.Q.cols == 4 && geometry.Q.type() == CV_64F,
          "measureSurface: the rectified geometry has no 4x4 CV_64F Q matrix");
  require(normalRadiusPx >= 1, "measureSurface: normalRadiusPx must be at least 1");
  require(maxDepthJumpMm > 0, "measureSurface: maxDepthJumpMm must be positive");
  requireUsableDevice(device, "measureSurface on CUDA");

  const int width = disparityPx.cols, height = disparityPx.rows;
  surface::Reprojection reprojection{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) reprojection.q[r][c] = geometry.Q.at<double>(r, c);

  const cv::Mat disparity = disparityPx.isContinuous() ? disparityPx : disparityPx.clone();
  Image<float> disparityImage(device, width, height);
  Image<Float3> points(device, width, height), normals(device, width, height);
  disparityImage.buffer().upload(disparity.ptr<float>());
  if (device == Device::Cuda) {
    surface::measureSurfaceCuda(disparityImage.view(), points.view(), normals.view(), reprojection, normalRadiusPx,
                                static_cast<float>(maxDepthJumpMm));
  } else {
    surface::measureSurfaceCpu(disparityImage.view(), points.view(), normals.view(), reprojection, normalRadiusPx,
                               static_cast<float>(maxDepthJumpMm));
  }

  SurfaceMeasurement measurement;
  measurement.pointsCameraMm.create(height, width, CV_32FC3);
  measurement.normalsCamera.create(height, width, CV_32FC3);
  points.buffer().download(measurement.pointsCameraMm.ptr<Float3>());
  normals.buffer().download(measurement.normalsCamera.ptr<Float3>());
  if (leftRectified.channels() == 3) measurement.colourBgr = leftRectified.clone();
  else cv::cvtColor(leftRectified, measurement.colourBgr, leftRectified.channels() == 1 ? cv::COLOR_GRAY2BGR : cv::COLOR_BGRA2BGR);
  // A normal exists only where its point does, so valid normals count the pixels with both.
  cv::Mat normalX;
  cv::extractChannel(measurement.normalsCamera, normalX, 0);
  measurement.validPixels = cv::countNonZero(normalX == normalX);
  return measurement;
}

}  // namespace tissuemosaic
