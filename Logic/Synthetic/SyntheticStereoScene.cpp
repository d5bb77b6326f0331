#include "SyntheticStereoScene.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "SyntheticCamera.h"
#include "SyntheticRenderer.h"
#include "TissueSurface.h"
#include "TissueTexture.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace tissuemosaic::synthetic {

namespace {

constexpr double degree = 3.141592653589793 / 180.0;

constexpr parameters::Group kSyntheticStereo{"synthetic stereo"};

/// The raw rig: slightly different lenses, a small relative rotation, the right eye baselineMm to the right.
StereoCalibration makeCalibration(const SyntheticStereoOptions& o) {
  const double f = o.focalPx > 0 ? o.focalPx : 1000.0 * o.width / 960.0;
  const double s = f / 1000.0;  // intrinsic offsets scale with the image
  StereoCalibration c;
  c.imageSize = cv::Size(o.width, o.height);
  c.K1 = (cv::Mat_<double>(3, 3) << f, 0, 0.5 * o.width + 3.2 * s, 0, f * 1.0012, 0.5 * o.height - 2.1 * s, 0, 0, 1);
  c.K2 = (cv::Mat_<double>(3, 3) << f * 1.0021, 0, 0.5 * o.width - 4.3 * s, 0, f * 1.0030, 0.5 * o.height + 1.7 * s,
          0, 0, 1);
  c.D1 = (cv::Mat_<double>(1, 5) << -0.060, 0.085, 0.0004, -0.0003, 0) * o.distortion;
  c.D2 = (cv::Mat_<double>(1, 5) << -0.052, 0.070, -0.0002, 0.0005, 0) * o.distortion;
  // A slight toe-in plus small roll and pitch, scaled to eyeRotationDeg.
  const cv::Vec3d axis = cv::normalize(cv::Vec3d(0.35, -0.85, 0.4));
  cv::Mat rotationVector = cv::Mat(axis * (o.eyeRotationDeg * degree));
  cv::Rodrigues(rotationVector, c.R);
  c.T = (cv::Mat_<double>(3, 1) << -o.baselineMm, 0.012 * o.baselineMm, -0.02 * o.baselineMm);
  return c;
}

SyntheticCamera makeCamera(const cv::Mat& K, const cv::Mat& D, const cv::Matx33d& R_world_camera,
                           const cv::Vec3d& centre, cv::Size size) {
  SyntheticCamera camera;
  camera.K = cv::Matx33d(K(cv::Rect(0, 0, 3, 3)));
  for (int i = 0; i < 5 && !D.empty(); ++i) camera.distortion[i] = D.at<double>(i);
  camera.R_world_camera = R_world_camera;
  camera.centreWorldMm = centre;
  camera.imageSize = size;
  return camera;
}

/// World XY rectangle seen by the cameras (rays along the image borders cast onto the surface), with a margin.
cv::Rect2d visibleDomain(const std::vector<SyntheticCamera>& cameras, const TissueSurface& surface,
                         double* nearestDepthMm) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  *nearestDepthMm = 1e300;
  for (const SyntheticCamera& camera : cameras) {
    const int w = camera.imageSize.width, h = camera.imageSize.height;
    for (int i = 0; i <= 64; ++i) {
      const double a = i / 64.0;
      const cv::Vec2d border[4] = {{a * w - 0.5, -0.5}, {a * w - 0.5, h - 0.5}, {-0.5, a * h - 0.5}, {w - 0.5, a * h - 0.5}};
      for (const cv::Vec2d& pixel : border) {
        const cv::Vec3d ray = camera.rayWorld(pixel[0], pixel[1]);
        const double t = surface.intersect(camera.centreWorldMm, ray);
        require(std::isfinite(t), "synthetic scene: a camera looks past the tissue; lower --tilt");
        const cv::Vec3d p = camera.centreWorldMm + t * ray;
        x0 = std::min(x0, p[0]); x1 = std::max(x1, p[0]);
        y0 = std::min(y0, p[1]); y1 = std::max(y1, p[1]);
        double depth = 0;
        camera.project(p, &depth);
        *nearestDepthMm = std::min(*nearestDepthMm, depth);
      }
    }
  }
  const double margin = 3.0;
  return {x0 - margin, y0 - margin, x1 - x0 + 2 * margin, y1 - y0 + 2 * margin};
}

/// Largest tan(angle between a camera ray and the world +Z axis) over the image borders (the extreme rays).
double maxRayTangent(const std::vector<SyntheticCamera>& cameras) {
  double result = 0;
  for (const SyntheticCamera& camera : cameras) {
    const int w = camera.imageSize.width, h = camera.imageSize.height;
    for (int i = 0; i <= 64; ++i) {
      const double a = i / 64.0;
      const cv::Vec2d border[4] = {{a * w - 0.5, -0.5}, {a * w - 0.5, h - 0.5}, {-0.5, a * h - 0.5}, {w - 0.5, a * h - 0.5}};
      for (const cv::Vec2d& pixel : border) {
        const cv::Vec3d ray = camera.rayWorld(pixel[0], pixel[1]);
        result = std::max(result, ray[2] > 0 ? std::hypot(ray[0], ray[1]) / ray[2] : 1e300);
      }
    }
  }
  return result;
}

}  // namespace

SyntheticStereoOptions SyntheticStereoOptions::wideDisparity(int width, int height) {
  SyntheticStereoOptions options;
  options.width = width;
  options.height = height;
  options.workingDistanceMm = 42.0;
  // tan(half vertical field of view) = (height / 2) / (1000 px * width / 960), 0.27 at 16:9.
  const auto halfVerticalFovDeg = [](double w, double h) { return std::atan(0.48 * h / w) / degree; };
  options.tiltDeg = 38.0 - std::max(0.0, halfVerticalFovDeg(width, height) - halfVerticalFovDeg(16, 9));
  options.reliefMm = 2.5;
  options.baselineMm = 8.0;
  return options;
}

void SyntheticStereoOptions::validate() const {
  kSyntheticStereo.requireRange("width", width, 64, 8192);
  kSyntheticStereo.requireRange("height", height, 64, 8192);
  kSyntheticStereo.requireRange("focal length (px, 0 = default)", focalPx, 0, 1e5);
  kSyntheticStereo.requireRange("baseline (mm)", baselineMm, 0.5, 100);
  kSyntheticStereo.requireRange("working distance (mm)", workingDistanceMm, 15, 500);
  kSyntheticStereo.requireRange("tilt (degrees)", tiltDeg, 0, 60);
  kSyntheticStereo.requireRange("relief (mm)", reliefMm, 0, 20);
  kSyntheticStereo.requireRange("distortion scale", distortion, 0, 3);
  kSyntheticStereo.requireRange("eye rotation (degrees)", eyeRotationDeg, 0, 5);
  kSyntheticStereo.requireRange("noise (grey levels)", noiseStdGrey, 0, 50);
  kSyntheticStereo.requireRange("supersampling", supersampling, 1, 4);
  kSyntheticStereo.requireRange("right view's rows below the left's (px)", rightRowsBelowPx, -100, 100);
}

StereoCalibration syntheticStereoCalibration(const SyntheticStereoOptions& options) {
  options.validate();
  return makeCalibration(options);
}

SyntheticStereoPair renderSyntheticStereoPair(const SyntheticStereoOptions& options) {
  options.validate();
  SyntheticStereoPair pair;
  pair.calibration = makeCalibration(options);
  const StereoRectifier rectifier(pair.calibration);
  pair.geometry = rectifier.geometry();
  pair.R1 = rectifier.leftRectificationRotation().clone();
  pair.R2 = rectifier.rightRectificationRotation().clone();
  pair.P1 = rectifier.leftProjection().clone();
  pair.P2 = rectifier.rightProjection().clone();

  // World: the tissue is Z = h(X, Y) with +Z into the tissue; the left eye looks at the origin from
  // workingDistanceMm away, its optical axis tilted by tiltDeg about its x axis.
  const double tilt = options.tiltDeg * degree;
  const cv::Matx33d R_world_left(1, 0, 0, 0, std::cos(tilt), std::sin(tilt), 0, -std::sin(tilt), std::cos(tilt));
  const cv::Vec3d leftCentre = -options.workingDistanceMm * (R_world_left * cv::Vec3d(0, 0, 1));
  const cv::Matx33d R(reinterpret_cast<const double*>(pair.calibration.R.data));
  const cv::Vec3d T(reinterpret_cast<const double*>(pair.calibration.T.data));
  // X_right = R X_left + T: the right eye's centre in the left frame is -R^T T, its axes are R^T.
  const cv::Matx33d R_world_right = R_world_left * R.t();
  const cv::Vec3d rightCentre = leftCentre + R_world_left * (-(R.t() * T));
  const cv::Size size = pair.calibration.imageSize;
  const SyntheticCamera leftRaw = makeCamera(pair.calibration.K1, pair.calibration.D1, R_world_left, leftCentre, size);
  const SyntheticCamera rightRaw = makeCamera(pair.calibration.K2, pair.calibration.D2, R_world_right, rightCentre, size);
  // Rectified frames: X_rect = R1 X_raw, so R_world_rect = R_world_raw * R1^T; same centres, no distortion.
  const SyntheticCamera leftRect =
      makeCamera(pair.P1, {}, R_world_left * cv::Matx33d(reinterpret_cast<const double*>(pair.R1.data)).t(), leftCentre, size);
  const SyntheticCamera rightRect =
      makeCamera(pair.P2, {}, R_world_right * cv::Matx33d(reinterpret_cast<const double*>(pair.R2.data)).t(), rightCentre, size);
  const std::vector<SyntheticCamera> cameras{leftRaw, rightRaw, leftRect, rightRect};

  TissueSurfaceParameters surfaceParameters;
  surfaceParameters.reliefMm = options.reliefMm;
  surfaceParameters.extentMm = std::max(40.0, 0.9 * options.workingDistanceMm);
  const TissueSurface surface(surfaceParameters, options.seed);
  double nearestDepthMm = 0;
  const cv::Rect2d domain = visibleDomain(cameras, surface, &nearestDepthMm);
  require(surface.maxSlope(domain) * maxRayTangent(cameras) < 0.98,
          "synthetic scene: the surface is too steep for this view and would hide parts of itself; lower --relief or "
          "--tilt");
  const double focal = pair.geometry.focalPx;
  // About 1.5 texels per pixel where the tissue is nearest; coarser if the map would get huge.
  double texelMm = 0.65 * nearestDepthMm / focal;
  texelMm = std::max(texelMm, std::sqrt(domain.area() / 16e6));
  const TissueTexture texture(domain, texelMm, options.seed);

  ShadingParameters shading;
  // The light guide sits at the tip between the eyes, a little below them.
  shading.lightWorldMm = 0.5 * (leftCentre + rightCentre) + R_world_left * cv::Vec3d(0, 2.0, 0);
  shading.lightReferenceMm = options.workingDistanceMm;
  shading.noiseStdGrey = options.noiseStdGrey;
  shading.supersampling = options.supersampling;
  std::unique_ptr<RealisticLighting> realistic;
  if (options.lighting == SyntheticLighting::Realistic) {
    realistic = std::make_unique<RealisticLighting>(texture, options.seed);
    shading.realistic = realistic.get();
  }
  pair.leftRectified = renderView(leftRect, leftRaw, surface, texture, shading, options.seed, 1, &pair.highlightMaskLeft);
  SyntheticCamera rightRectShown = rightRect;  // a point on left row v shows on right row v + rightRowsBelowPx
  rightRectShown.K(1, 2) += options.rightRowsBelowPx;
  pair.rightRectified = renderView(rightRectShown, rightRaw, surface, texture, shading, options.seed, 2);
  pair.leftRaw = renderView(leftRaw, leftRaw, surface, texture, shading, options.seed, 3);
  pair.rightRaw = renderView(rightRaw, rightRaw, surface, texture, shading, options.seed, 4);
  renderRectifiedGroundTruth(leftRect, rightRect, surface, pair.disparityPx, pair.depthMm);
  return pair;
}

}  // namespace tissuemosaic::synthetic
