#pragma once
/// @file PinholeIntrinsics.h
/// @brief The pinhole camera of rectified (undistorted) images in double precision: the one place where its
/// projection, back-projection and projection derivatives are written, for host and device code alike. (The fusion
/// kernels keep a single-precision camera of their own, FusionKernels.h's PinholeCamera, for the GPU's float path.)
#include "Core/HostDevice.h"

namespace tissuemosaic {

/// u = fx X/Z + cx, v = fy Y/Z + cy for a camera-frame point (X, Y, Z) in mm; pixel centres at integer coordinates.
struct PinholeIntrinsics {
  double fxPx = 0, fyPx = 0, cxPx = 0, cyPx = 0;

  /// Pixel of a camera-frame point with Z > 0.
  TM_HOST_DEVICE void project(double x, double y, double z, double& uPx, double& vPx) const {
    uPx = fxPx * x / z + cxPx;
    vPx = fyPx * y / z + cyPx;
  }

  /// The same projection through 1/Z, with the derivatives of u and v with respect to the camera-frame point c: the
  /// form of the Gauss-Newton residuals (bundle adjustment, PnP polishing), which need 1/Z for the derivatives too.
  TM_HOST_DEVICE void projectWithDerivatives(const double c[3], double& uPx, double& vPx, double dU[3],
                                             double dV[3]) const {
    const double invZ = 1.0 / c[2];
    uPx = fxPx * c[0] * invZ + cxPx;
    vPx = fyPx * c[1] * invZ + cyPx;
    dU[0] = fxPx * invZ;
    dU[1] = 0.0;
    dU[2] = -fxPx * c[0] * invZ * invZ;
    dV[0] = 0.0;
    dV[1] = fyPx * invZ;
    dV[2] = -fyPx * c[1] * invZ * invZ;
  }

  /// The camera-frame point at depth z (mm) that projects to pixel (uPx, vPx).
  TM_HOST_DEVICE void backProject(double uPx, double vPx, double z, double& x, double& y) const {
    x = (uPx - cxPx) * z / fxPx;
    y = (vPx - cyPx) * z / fyPx;
  }

  /// Normalised image coordinates (X/Z, Y/Z) of a pixel.
  TM_HOST_DEVICE double normalisedX(double uPx) const { return (uPx - cxPx) / fxPx; }
  TM_HOST_DEVICE double normalisedY(double vPx) const { return (vPx - cyPx) / fyPx; }
};

}  // namespace tissuemosaic
