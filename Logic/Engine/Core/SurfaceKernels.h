#pragma once
/// @file SurfaceKernels.h
/// @brief measureSurface's per-pixel steps, written once for both backends, and the template that runs them
/// (instantiated in SurfaceMeasurement.cpp for the CPU and SurfaceMeasurementCuda.cu for CUDA).
#include "Float3.h"
#include "Image.h"
#include "ParallelFor.h"

namespace tissuemosaic::surface {

/// cv::stereoRectify's Q, in doubles as the host's disparityToPointCloud uses it.
struct Reprojection {
  double q[4][4];
};

/// Pixel (x, y) with disparity d -> 3D point in the left rectified camera frame: Q * [x y d 1], the same double
/// operations as disparityToPointCloud (so the same floats); NaN where it skips the pixel (no disparity, a
/// disparity outside [keptLowestPx, keptHighestPx], at or behind the camera). The one rule by which a measurement
/// turns into points (measureSurface) and into depths (the model agreement, Fusion/AgreementKernels.h).
TM_HOST_DEVICE TM_FORCE_INLINE Float3 reprojectPixel(const Reprojection& reprojection, int x, int y, float disparityPx,
                                                    float keptLowestPx, float keptHighestPx) {
  if (!(disparityPx >= keptLowestPx && disparityPx <= keptHighestPx)) return nanFloat3();
  const double d = disparityPx;
  if (!(fabs(d) <= 1.7976931348623157e308)) return nanFloat3();
  const double(&q)[4][4] = reprojection.q;
  double h[4];
  for (int r = 0; r < 4; ++r) h[r] = q[r][0] * x + q[r][1] * y + q[r][2] * d + q[r][3];
  if (!(h[3] != 0)) return nanFloat3();
  const double px = h[0] / h[3], py = h[1] / h[3], pz = h[2] / h[3];
  const double big = 1.7976931348623157e308;
  if (!(pz > 0 && pz <= big && fabs(px) <= big && fabs(py) <= big)) return nanFloat3();
  return {static_cast<float>(px), static_cast<float>(py), static_cast<float>(pz)};
}

/// Pixel -> 3D point in the left rectified camera frame (reprojectPixel) for every pixel.
struct DisparityToPoints {
  ImageView<const float> disparityPx;
  ImageView<Float3> pointsMm;
  Reprojection reprojection;
  float keptLowestPx, keptHighestPx;  ///< a disparity outside counts as missing

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int i = static_cast<int>(index);
    const int y = i / disparityPx.width, x = i - y * disparityPx.width;
    pointsMm[index] = reprojectPixel(reprojection, x, y, disparityPx[index], keptLowestPx, keptHighestPx);
  }
};

/// The surface normal at point p from its neighbours radiusPx away in x and y (camera frame): the cross product of
/// the central differences, turned toward the camera (n . p < 0). False where p or a neighbour is missing, or a
/// neighbour's depth differs from p's by more than maxDepthJumpMm (a depth edge, not a surface).
TM_HOST_DEVICE TM_FORCE_INLINE bool normalFromNeighbours(Float3 p, Float3 left, Float3 right, Float3 up, Float3 down,
                                                         float maxDepthJumpMm, Float3& normal) {
  if (!isFinite(p) || !isFinite(left) || !isFinite(right) || !isFinite(up) || !isFinite(down)) return false;
  if (fabsf(left.z - p.z) > maxDepthJumpMm || fabsf(right.z - p.z) > maxDepthJumpMm ||
      fabsf(up.z - p.z) > maxDepthJumpMm || fabsf(down.z - p.z) > maxDepthJumpMm)
    return false;
  const Float3 n = cross(right - left, down - up);
  const float norm = length(n);
  if (!(norm > 0)) return false;
  normal = ((dot(n, p) > 0 ? -1.0f : 1.0f) / norm) * n;
  return true;
}

/// Per pixel: normalFromNeighbours of the points radiusPx away; NaN also where a neighbour is outside the image.
/// valid: 255 where the pixel has a normal (and so a point), else 0.
struct PointNormals {
  ImageView<const Float3> pointsMm;
  ImageView<Float3> normals;
  ImageView<uint8_t> valid;
  int radiusPx;
  float maxDepthJumpMm;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const int i = static_cast<int>(index);
    const int y = i / pointsMm.width, x = i - y * pointsMm.width;
    normals[index] = nanFloat3();
    valid[index] = 0;
    const int r = radiusPx;
    if (x < r || y < r || x + r >= pointsMm.width || y + r >= pointsMm.height) return;
    Float3 n;
    if (!normalFromNeighbours(pointsMm[index], pointsMm.at(x - r, y), pointsMm.at(x + r, y), pointsMm.at(x, y - r),
                              pointsMm.at(x, y + r), maxDepthJumpMm, n))
      return;
    normals[index] = n;
    valid[index] = 255;
  }
};

/// Points, then normals, on the backend that owns the images (all of one device).
template <class Backend>
void measureSurfaceOn(ImageView<const float> disparityPx, ImageView<Float3> pointsMm, ImageView<Float3> normals,
                      ImageView<uint8_t> valid, const Reprojection& reprojection, int normalRadiusPx,
                      float maxDepthJumpMm, float keptLowestPx, float keptHighestPx) {
  parallelFor<Backend>(disparityPx.pixelCount(),
                       DisparityToPoints{disparityPx, pointsMm, reprojection, keptLowestPx, keptHighestPx});
  parallelFor<Backend>(pointsMm.pixelCount(),
                       PointNormals{pointsMm, normals, valid, normalRadiusPx, maxDepthJumpMm});
}

/// The backend entry points (SurfaceMeasurement.cpp, SurfaceMeasurementCuda.cu; SurfaceMeasurementCudaAbsent.cpp
/// throws Error without CUDA).
void measureSurfaceCpu(ImageView<const float> disparityPx, ImageView<Float3> pointsMm, ImageView<Float3> normals,
                       ImageView<uint8_t> valid, const Reprojection& reprojection, int normalRadiusPx,
                       float maxDepthJumpMm, float keptLowestPx, float keptHighestPx);
void measureSurfaceCuda(ImageView<const float> disparityPx, ImageView<Float3> pointsMm, ImageView<Float3> normals,
                        ImageView<uint8_t> valid, const Reprojection& reprojection, int normalRadiusPx,
                        float maxDepthJumpMm, float keptLowestPx, float keptHighestPx);

}  // namespace tissuemosaic::surface
