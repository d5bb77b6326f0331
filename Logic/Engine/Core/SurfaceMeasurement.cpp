// measureSurface on either backend, and its CPU instantiation (the CUDA one is SurfaceMeasurementCuda.cu).
#include "SurfaceMeasurement.h"

#include "Error.h"
#include "KernelProfiler.h"
#include "SurfaceKernels.h"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <string>

namespace tissuemosaic {

namespace surface {

void measureSurfaceCpu(ImageView<const float> disparityPx, ImageView<Float3> pointsMm, ImageView<Float3> normals,
                       ImageView<uint8_t> valid, const Reprojection& reprojection, int normalRadiusPx,
                       float maxDepthJumpMm, float keptLowestPx, float keptHighestPx) {
  measureSurfaceOn<CpuBackend>(disparityPx, pointsMm, normals, valid, reprojection, normalRadiusPx, maxDepthJumpMm,
                               keptLowestPx, keptHighestPx);
}

}  // namespace surface

surface::Reprojection reprojectionOf(const RectifiedGeometry& geometry) {
  require(geometry.Q.rows == 4 && geometry.Q.cols == 4 && geometry.Q.type() == CV_64F,
          "the rectified geometry has no 4x4 CV_64F Q matrix");
  surface::Reprojection reprojection{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) reprojection.q[r][c] = geometry.Q.at<double>(r, c);
  return reprojection;
}

namespace {

/// The checks both entry points make on everything but the disparity.
void requireSurfaceInputs(cv::Size disparitySize, const cv::Mat& leftRectified, const RectifiedGeometry& geometry,
                          Device device, int normalRadiusPx, double maxDepthJumpMm) {
  require(disparitySize == geometry.imageSize,
          "measureSurface: the disparity map is " + std::to_string(disparitySize.width) + "x" +
              std::to_string(disparitySize.height) + " but the rectified images are " +
              std::to_string(geometry.imageSize.width) + "x" + std::to_string(geometry.imageSize.height));
  require(leftRectified.size() == disparitySize,
          "measureSurface: the rectified left image and the disparity map must have the same size");
  require(leftRectified.depth() == CV_8U &&
              (leftRectified.channels() == 1 || leftRectified.channels() == 3 || leftRectified.channels() == 4),
          "measureSurface: the rectified left image must be 8-bit grey, BGR or BGRA");
  require(geometry.Q.rows == 4 && geometry.Q.cols == 4 && geometry.Q.type() == CV_64F,
          "measureSurface: the rectified geometry has no 4x4 CV_64F Q matrix");
  require(normalRadiusPx >= 1, "measureSurface: normalRadiusPx must be at least 1");
  require(maxDepthJumpMm > 0, "measureSurface: maxDepthJumpMm must be positive");
  requireUsableDevice(device, "measureSurface on CUDA");
}

}  // namespace

SurfaceMeasurement measureSurface(const cv::Mat& disparityPx, const cv::Mat& leftRectified,
                                  const RectifiedGeometry& geometry, Device device, int normalRadiusPx,
                                  double maxDepthJumpMm, SurfaceMapResidence residence, DisparityRangePx kept,
                                  ChannelOrder order) {
  require(!disparityPx.empty() && disparityPx.type() == CV_32FC1, "measureSurface: the disparity map must be a non-empty CV_32FC1 image");
  requireSurfaceInputs(disparityPx.size(), leftRectified, geometry, device, normalRadiusPx, maxDepthJumpMm);  // before any upload
  const cv::Mat disparity = disparityPx.isContinuous() ? disparityPx : disparityPx.clone();
  Image<float> disparityImage;
  {
    profiling::ScopedTimer timer("host: surface measurement, disparity upload");
    disparityImage = Image<float>(device, disparity.cols, disparity.rows);
    disparityImage.buffer().upload(disparity.ptr<float>());
  }
  return measureSurface(disparityImage.view(), leftRectified, geometry, device, normalRadiusPx, maxDepthJumpMm,
                        residence, kept, order);
}

SurfaceMeasurement measureSurface(ImageView<const float> disparityPx, const cv::Mat& leftRectified,
                                  const RectifiedGeometry& geometry, Device device, int normalRadiusPx,
                                  double maxDepthJumpMm, SurfaceMapResidence residence, DisparityRangePx kept,
                                  ChannelOrder order) {
  require(disparityPx.data != nullptr && disparityPx.width > 0 && disparityPx.height > 0,
          "measureSurface: the disparity map is empty");
  requireSurfaceInputs({disparityPx.width, disparityPx.height}, leftRectified, geometry, device, normalRadiusPx,
                       maxDepthJumpMm);
  const int width = disparityPx.width, height = disparityPx.height;
  const surface::Reprojection reprojection = reprojectionOf(geometry);

  auto maps = std::make_shared<SurfaceMapsOnDevice>();
  Image<uint8_t> valid;
  {
    profiling::ScopedTimer timer("host: surface measurement, allocation");
    maps->pointsCameraMm = Image<Float3>(device, width, height);
    maps->normalsCamera = Image<Float3>(device, width, height);
    valid = Image<uint8_t>(device, width, height);
  }
  const auto measure = device == Device::Cuda ? surface::measureSurfaceCuda : surface::measureSurfaceCpu;
  measure(disparityPx, maps->pointsCameraMm.view(), maps->normalsCamera.view(), valid.view(), reprojection,
          normalRadiusPx, static_cast<float>(maxDepthJumpMm), kept.lowestPx, kept.highestPx);

  profiling::ScopedTimer timer("host: surface measurement, download and colour");
  SurfaceMeasurement measurement;
  if (device != Device::Cuda || residence == SurfaceMapResidence::HostAndDevice) {
    measurement.pointsCameraMm.create(height, width, CV_32FC3);
    measurement.normalsCamera.create(height, width, CV_32FC3);
    maps->pointsCameraMm.buffer().download(measurement.pointsCameraMm.ptr<Float3>());
    maps->normalsCamera.buffer().download(measurement.normalsCamera.ptr<Float3>());
  }
  measurement.validMask.create(height, width, CV_8U);
  valid.buffer().download(measurement.validMask.ptr<uint8_t>());
  measurement.validPixels = cv::countNonZero(measurement.validMask);
  // A continuous BGR image is shared, not copied (6 MB a frame at 1920x1080): the measurement reads the caller's
  // pixels. RGB, grey and 4-channel images are converted.
  measurement.colourBgr = toContinuousBgr8(leftRectified, "measureSurface: the left image", order);
  if (device == Device::Cuda) {
    maps->colourBgr = Buffer<uint8_t>(device, measurement.colourBgr.total() * 3);
    maps->colourBgr.upload(measurement.colourBgr.ptr<uint8_t>());  // continuous: shared, cloned or converted above
    measurement.onDevice = std::move(maps);
  }
  return measurement;
}

cv::Size SurfaceMeasurement::size() const {
  if (hasHostMaps()) return pointsCameraMm.size();
  if (onDevice) return {onDevice->pointsCameraMm.width(), onDevice->pointsCameraMm.height()};
  return {};
}

cv::Mat SurfaceMeasurement::validPixelMask() const {
  if (!validMask.empty()) return validMask;
  require(usableHostMaps(pointsCameraMm, normalsCamera),
          "SurfaceMeasurement: no valid-pixel mask and no CV_32FC3 points and normals of one size");
  cv::Mat mask(pointsCameraMm.size(), CV_8U);
  const auto finite = [](const cv::Vec3f& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
  for (int y = 0; y < mask.rows; ++y) {
    for (int x = 0; x < mask.cols; ++x) {
      const bool both = finite(pointsCameraMm.at<cv::Vec3f>(y, x)) && finite(normalsCamera.at<cv::Vec3f>(y, x));
      mask.at<uint8_t>(y, x) = both ? 255 : 0;
    }
  }
  return mask;
}

bool usableHostMaps(const cv::Mat& pointsCameraMm, const cv::Mat& normalsCamera) {
  return !pointsCameraMm.empty() && pointsCameraMm.type() == CV_32FC3 && normalsCamera.type() == CV_32FC3 &&
         pointsCameraMm.size() == normalsCamera.size();
}

void copySurfaceMaps(const cv::Mat& hostPointsCameraMm, const cv::Mat& hostNormalsCamera,
                     const SurfaceMapsOnDevice* onDevice, Image<Float3>& points, Image<Float3>& normals) {
  const bool host = usableHostMaps(hostPointsCameraMm, hostNormalsCamera);
  require(host || onDevice, "surface maps: neither CV_32FC3 host maps of one size nor device maps");
  const cv::Size target(points.width(), points.height());
  require(normals.width() == target.width && normals.height() == target.height,
          "surface maps: the target images differ in size");
  if (onDevice && (points.device() == Device::Cuda || !host)) {
    // On the device already: a device-to-device copy (or one download for the CPU), no upload.
    require(onDevice->pointsCameraMm.width() == target.width && onDevice->pointsCameraMm.height() == target.height,
            "surface maps: the device maps differ in size from the target");
    points.buffer().copyFrom(onDevice->pointsCameraMm.buffer());
    normals.buffer().copyFrom(onDevice->normalsCamera.buffer());
    return;
  }
  require(hostPointsCameraMm.size() == target, "surface maps: the host maps differ in size from the target");
  const cv::Mat continuousPoints = hostPointsCameraMm.isContinuous() ? hostPointsCameraMm : hostPointsCameraMm.clone();
  const cv::Mat continuousNormals = hostNormalsCamera.isContinuous() ? hostNormalsCamera : hostNormalsCamera.clone();
  points.buffer().upload(continuousPoints.ptr<Float3>());
  normals.buffer().upload(continuousNormals.ptr<Float3>());
}

void SurfaceMeasurement::hostMaps(cv::Mat& points, cv::Mat& normals) const {
  if (hasHostMaps() || !onDevice) {
    points = pointsCameraMm;
    normals = normalsCamera;
    return;
  }
  const cv::Size mapSize = size();
  points.create(mapSize, CV_32FC3);
  normals.create(mapSize, CV_32FC3);
  onDevice->pointsCameraMm.buffer().download(points.ptr<Float3>());
  onDevice->normalsCamera.buffer().download(normals.ptr<Float3>());
}

}  // namespace tissuemosaic
