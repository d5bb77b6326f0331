#include "SyntheticScan.h"

#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "Core/ParameterChecks.h"
#include "SyntheticBreathing.h"
#include "SyntheticCamera.h"
#include "SyntheticCameraOut.h"
#include "SyntheticCapture.h"
#include "SyntheticHaze.h"
#include "SyntheticInstruments.h"
#include "SyntheticPulse.h"
#include "SyntheticPush.h"
#include "SyntheticRandom.h"
#include "SyntheticRenderer.h"
#include "SyntheticStereoScene.h"
#include "TissueSurface.h"
#include "TissueTexture.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace tissuemosaic::synthetic {

namespace {

constexpr double pi = 3.141592653589793;
constexpr double degree = pi / 180.0;
/// Smoke (--smoke): the most a pixel moves toward the smoke's colour where the haze is densest.
constexpr double kSmokeStrength = 0.45;
/// In-vivo instruments at the border (SyntheticInVivoOptions::instrumentsAtBorder): their tips work this share of the
/// way from the view's centre to its edge.
constexpr double kInstrumentBorderShare = 0.6;
/// The pulsing patch lies within this share of the view's half extent from its centre.
constexpr double kPulseOffsetShare = 0.35;

constexpr parameters::Group kSyntheticScan{"synthetic scan"};

cv::Matx33d rotationX(double a) { return {1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a)}; }
cv::Matx33d rotationY(double a) { return {std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a)}; }
cv::Matx33d rotationZ(double a) { return {std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1}; }

cv::Matx33d matx33(const cv::Mat& m) { return cv::Matx33d(m(cv::Rect(0, 0, 3, 3)).clone().ptr<double>()); }

/// The path: a closed Lissajous raster on the XY plane walked at a smoothly varying speed, plus slow, smooth
/// oscillations of tilt, roll and working distance. Every quantity is a smooth function of time.
struct ScanPath {
  // Lissajous raster sampled densely and parametrised by arc length.
  std::vector<cv::Vec2d> samples;
  std::vector<double> arcLengthMm;
  double startMm = 0;
  double speedOmega = 0, speedPhase = 0;
  double tiltOmega[2] = {0, 0}, tiltPhase[2] = {0, 0};
  double rollOmega = 0, rollPhase = 0, distanceOmega = 0, distancePhase = 0;

  ScanPath(const SyntheticScanOptions& o) {
    std::mt19937 generator(o.seed ^ 0x5ca9u);
    const auto period = [&](double low, double high) { return 2 * pi / uniform(generator, low, high); };
    const double phaseY = uniform(generator, 0, 2 * pi);
    const int count = 40000;
    samples.resize(count + 1);
    arcLengthMm.resize(count + 1);
    for (int i = 0; i <= count; ++i) {
      const double theta = 2 * pi * i / count;
      samples[i] = {0.5 * o.rasterWidthMm * std::sin(theta),
                    0.5 * o.rasterHeightMm * std::sin(2 * o.rasterSweeps * theta + phaseY)};
      arcLengthMm[i] = i == 0 ? 0 : arcLengthMm[i - 1] + cv::norm(samples[i] - samples[i - 1]);
    }
    startMm = uniform(generator, 0, arcLengthMm.back());
    speedOmega = period(5, 9);
    speedPhase = uniform(generator, 0, 2 * pi);
    for (int k = 0; k < 2; ++k) {
      tiltOmega[k] = period(8, 14);
      tiltPhase[k] = uniform(generator, 0, 2 * pi);
    }
    rollOmega = period(10, 16);
    rollPhase = uniform(generator, 0, 2 * pi);
    distanceOmega = period(12, 20);
    distancePhase = uniform(generator, 0, 2 * pi);
  }

  /// Distance walked by time t: the integral of v(t) = vmin + (vmax - vmin) (1 - cos(w t + p)) / 2.
  double walkedMm(const SyntheticScanOptions& o, double t) const {
    const double span = o.maxSpeedMmPerS - o.minSpeedMmPerS;
    return (o.minSpeedMmPerS + 0.5 * span) * t -
           0.5 * span / speedOmega * (std::sin(speedOmega * t + speedPhase) - std::sin(speedPhase));
  }

  cv::Vec2d positionMm(double s) const {
    const double length = arcLengthMm.back();
    s = std::fmod(s, length);
    if (s < 0) s += length;
    const auto upper = std::upper_bound(arcLengthMm.begin(), arcLengthMm.end(), s);
    const std::size_t i = std::min<std::size_t>(std::max<std::ptrdiff_t>(upper - arcLengthMm.begin(), 1),
                                                arcLengthMm.size() - 1);
    const double a = (s - arcLengthMm[i - 1]) / std::max(arcLengthMm[i] - arcLengthMm[i - 1], 1e-12);
    return samples[i - 1] * (1 - a) + samples[i] * a;
  }

  /// Height of the scope tip above the tissue at time t.
  double workingDistanceMm(const SyntheticScanOptions& o, double t) const {
    if (o.distanceProfile == WorkingDistanceProfile::Approaching) {
      const double lastS = o.frames > 1 ? (o.frames - 1) / o.fps : 1.0;
      return o.maxWorkingDistanceMm - (o.maxWorkingDistanceMm - o.minWorkingDistanceMm) * std::min(t / lastS, 1.0);
    }
    const double mid = 0.5 * (o.minWorkingDistanceMm + o.maxWorkingDistanceMm);
    const double amplitude = 0.5 * (o.maxWorkingDistanceMm - o.minWorkingDistanceMm);
    return mid + amplitude * std::sin(distanceOmega * t + distancePhase);
  }

  /// Left rectified camera at time t.
  void pose(const SyntheticScanOptions& o, const TissueSurface& surface, double t, cv::Matx33d& R_world_camera,
            cv::Vec3d& centreMm) const {
    const cv::Vec2d xy = positionMm(startMm + walkedMm(o, t));
    const double tilt = o.maxTiltDeg * degree / std::sqrt(2.0);
    const double a = tilt * std::sin(tiltOmega[0] * t + tiltPhase[0]);
    const double b = tilt * std::sin(tiltOmega[1] * t + tiltPhase[1]);
    const double roll = o.maxRollDeg * degree * std::sin(rollOmega * t + rollPhase);
    R_world_camera = rotationX(a) * rotationY(b) * rotationZ(roll);
    const double distance = workingDistanceMm(o, t);
    // The scope hovers at the working distance above the tissue under the path; tilting turns the view about the
    // scope tip, as a hand does, instead of swinging the tip around a point on the tissue.
    centreMm = cv::Vec3d(xy[0], xy[1], surface.heightMm(xy[0], xy[1]) - distance);
  }
};

/// A world point in front of the camera projecting at least borderPx inside its image (pixel centres integers).
bool seenBy(const SyntheticCamera& camera, const cv::Point3f& pointMm, double borderPx) {
  double depthMm = 0;
  const cv::Vec2d pixel = camera.project(cv::Vec3d(pointMm.x, pointMm.y, pointMm.z), &depthMm);
  return depthMm > 0 && pixel[0] >= borderPx && pixel[0] <= camera.imageSize.width - 1 - borderPx &&
         pixel[1] >= borderPx && pixel[1] <= camera.imageSize.height - 1 - borderPx;
}

SyntheticCamera makeCamera(const cv::Mat& K, const cv::Mat& D, const cv::Matx33d& R_world_camera,
                           const cv::Vec3d& centre, cv::Size size) {
  SyntheticCamera camera;
  camera.K = matx33(K);
  for (int i = 0; i < 5 && !D.empty(); ++i) camera.distortion[i] = D.at<double>(i);
  camera.R_world_camera = R_world_camera;
  camera.centreWorldMm = centre;
  camera.imageSize = size;
  return camera;
}

}  // namespace

void SyntheticScanOptions::validate() const {
  kSyntheticScan.requireRange("width", width, 64, 8192);
  kSyntheticScan.requireRange("height", height, 64, 8192);
  kSyntheticScan.requireRange("frames", frames, 1, 100000);
  kSyntheticScan.requireRange("fps", fps, 1, 1000);
  kSyntheticScan.requireRange("minimum working distance (mm)", minWorkingDistanceMm, 20, 500);
  kSyntheticScan.requireRange("maximum working distance (mm)", maxWorkingDistanceMm, minWorkingDistanceMm, 500);
  kSyntheticScan.requireRange("minimum speed (mm/s)", minSpeedMmPerS, 0, 1000);
  kSyntheticScan.requireRange("maximum speed (mm/s)", maxSpeedMmPerS, minSpeedMmPerS, 1000);
  kSyntheticScan.requireRange("raster width (mm)", rasterWidthMm, 1, 200);
  kSyntheticScan.requireRange("raster height (mm)", rasterHeightMm, 1, 200);
  kSyntheticScan.requireRange("raster sweeps", rasterSweeps, 1, 50);
  kSyntheticScan.requireRange("maximum tilt (degrees)", maxTiltDeg, 0, 30);
  kSyntheticScan.requireRange("maximum roll (degrees)", maxRollDeg, 0, 45);
  kSyntheticScan.requireRange("relief (mm)", reliefMm, 0, 20);
  kSyntheticScan.requireRange("baseline (mm)", baselineMm, 0.5, 100);
  kSyntheticScan.requireRange("focal length (px, 0 = default)", focalPx, 0, 1e5);
  kSyntheticScan.requireRange("rectified disparity offset (px)", rectifiedDisparityOffsetPx, -width, width);
  kSyntheticScan.requireRange("noise (grey levels)", noiseStdGrey, 0, 50);
  kSyntheticScan.requireRange("supersampling", supersampling, 1, 4);
  hardMode.validate(frames);
  inVivo.validate(fps, hardMode);
}

struct SyntheticScan::Impl {
  SyntheticScanOptions options;
  StereoCalibration calibration;
  RectifiedGeometry geometry;
  cv::Mat R1, R2, P1, P2;
  std::unique_ptr<ScanPath> path;
  std::unique_ptr<TissueSurface> surface;
  std::unique_ptr<TissueTexture> texture;
  std::unique_ptr<RealisticLighting> realisticLighting;  ///< with SyntheticLighting::Realistic only
  cv::Rect2d domainMm;
  // The hard mode (SyntheticHardMode.h).
  SyntheticCameraOut cameraOut;
  cv::Matx33d R_path_return = cv::Matx33d::eye();  ///< after the camera-out: T_world_camera = T_path * T_path_return
  cv::Vec3d t_path_return{0, 0, 0};
  SyntheticBreathing breathing;
  std::unique_ptr<TissueSurface> highestSurface;  ///< the tissue at the breathing's peak: the instruments' clearance
  SyntheticInstruments instruments;
  // The in-vivo mode (SyntheticInVivo.h).
  SyntheticPulse pulse;

  /// The left rectified camera at frame index, offsetS after its time: the path's, offset after a camera-out; a
  /// camera-out frame's is the scope withdrawn 40 mm from where it left (no tissue is rendered for it).
  void pose(int index, double offsetS, cv::Matx33d& R_world_leftRect, cv::Vec3d& leftCentre) const {
    const bool out = cameraOut.contains(index);
    const int at = out ? cameraOut.start() - 1 : index;
    path->pose(options, *surface, at / options.fps + (out ? 0.0 : offsetS), R_world_leftRect, leftCentre);
    if (cameraOut.contains(index)) {
      leftCentre -= 40.0 * R_world_leftRect * cv::Vec3d(0, 0, 1);
    } else if (cameraOut.active() && index >= cameraOut.end()) {
      leftCentre += R_world_leftRect * t_path_return;
      R_world_leftRect = R_world_leftRect * R_path_return;
    }
  }

  bool deformsInVivo() const {
    return breathing.lateralMm() > 0 || pulse.active() || options.inVivo.push();
  }

  /// What moves at one instant: the tissue and the instruments (pressed into it with a push) and their dents.
  struct Scene {
    std::unique_ptr<TissueSurface> surface;
    std::vector<InstrumentPose> instruments;
    std::vector<SurfaceSwell> dents;
  };

  /// The scene at frame index, offsetS after its time: the tissue breathing, pulsing and pushed, the instruments.
  Scene sceneAt(int index, double offsetS) const {
    const double timeS = index / options.fps + offsetS;
    Scene scene;
    scene.instruments = instruments.posesAt(index, offsetS);
    TissueSurface breathed = breathing.active() ? surface->swollen(breathing.swellAt(timeS)) : *surface;
    if (!deformsInVivo()) {
      scene.surface = std::make_unique<TissueSurface>(std::move(breathed));
      return scene;
    }
    SurfaceDeformation deformation;
    deformation.slide = breathing.slideAt(timeS);
    if (pulse.active()) deformation.swells.push_back(pulse.swellAt(timeS));
    if (options.inVivo.push()) {
      const TissueSurface undented = breathed.deformed(deformation);
      for (InstrumentPose& pose : scene.instruments) {
        const double weight = pushWeight(instruments.spanFraction(pose.instrument, index, offsetS));
        const PressedInstrument pressed = pressInstrument(pose, weight, options.inVivo.pushMm, undented);
        pose = pressed.pose;
        if (pressed.dent.amplitudeMm > 0) scene.dents.push_back(pressed.dent);
      }
      deformation.swells.insert(deformation.swells.end(), scene.dents.begin(), scene.dents.end());
    }
    scene.surface = std::make_unique<TissueSurface>(breathed.deformed(deformation));
    return scene;
  }

  /// The tissue point at the centre of the left view at frame index (false for a camera-out frame).
  bool viewCentreMm(int index, cv::Vec3d& pointMm) const {
    if (cameraOut.contains(index)) return false;
    const Cameras c = cameras(index);
    const cv::Vec3d ray = c.leftRect.rayWorld(c.leftRect.K(0, 2), c.leftRect.K(1, 2));
    const double t = surface->intersect(c.leftRect.centreWorldMm, ray);
    if (!std::isfinite(t)) return false;
    pointMm = c.leftRect.centreWorldMm + t * ray;
    return true;
  }

  struct Cameras {
    SyntheticCamera leftRaw, rightRaw, leftRect, rightRect;
    cv::Vec3d lightMm;
  };

  Cameras cameras(int index, double offsetS = 0) const {
    cv::Matx33d R_world_leftRect;
    cv::Vec3d leftCentre;
    pose(index, offsetS, R_world_leftRect, leftCentre);
    const cv::Matx33d R = matx33(calibration.R);
    const cv::Vec3d T(calibration.T.ptr<double>());
    // X_rect = R1 X_raw; X_right = R X_left + T: the right eye's centre in the raw left frame is -R^T T.
    const cv::Matx33d R_world_leftRaw = R_world_leftRect * matx33(R1);
    const cv::Matx33d R_world_rightRaw = R_world_leftRaw * R.t();
    const cv::Vec3d rightCentre = leftCentre + R_world_leftRaw * (-(R.t() * T));
    const cv::Size size = calibration.imageSize;
    Cameras c;
    c.leftRaw = makeCamera(calibration.K1, calibration.D1, R_world_leftRaw, leftCentre, size);
    c.rightRaw = makeCamera(calibration.K2, calibration.D2, R_world_rightRaw, rightCentre, size);
    c.leftRect = makeCamera(P1, {}, R_world_leftRect, leftCentre, size);
    c.rightRect = makeCamera(P2, {}, R_world_rightRaw * matx33(R2).t(), rightCentre, size);
    // The light guide sits at the tip between the eyes, a little below them.
    c.lightMm = 0.5 * (leftCentre + rightCentre) + R_world_leftRect * cv::Vec3d(0, 2.0, 0);
    return c;
  }

  /// Both rectified views of `scene` seen at frame index, offsetS after its time (rows of one parity, or all: -1).
  void renderViews(int index, double offsetS, const Scene& scene, int rowParity, cv::Mat& left, cv::Mat& right,
                   cv::Mat* highlightMaskLeft) const {
    const Cameras c = cameras(index, offsetS);
    const InstrumentOccluder occluding(scene.instruments);
    const RayOccluder* occluder = occluding.empty() ? nullptr : &occluding;
    ShadingParameters shading;
    shading.lightWorldMm = c.lightMm;
    shading.lightReferenceMm = options.autoExposure
                                   ? path->workingDistanceMm(options, index / options.fps + offsetS)
                                   : 0.5 * (options.minWorkingDistanceMm + options.maxWorkingDistanceMm);
    shading.noiseStdGrey = options.noiseStdGrey;
    shading.supersampling = options.supersampling;
    shading.realistic = realisticLighting.get();
    shading.rowParity = rowParity;
    // Each frame and eye has its own noise stream (the same at every instant of a frame: a still pixel's noise
    // survives the blur's average).
    const auto stream = static_cast<uint32_t>(2 * index);
    left = renderView(c.leftRect, c.leftRaw, *scene.surface, *texture, shading, options.seed, stream + 1,
                      highlightMaskLeft, occluder);
    right = renderView(c.rightRect, c.rightRaw, *scene.surface, *texture, shading, options.seed, stream + 2, nullptr,
                       occluder);
  }

  /// Frame index at one instant, offsetS after its time: views, truth and masks (no smoke).
  SyntheticScanFrame renderInstant(int index, double offsetS) const {
    SyntheticScanFrame frame;
    frame.index = index;
    frame.timeS = index / options.fps;
    const Scene scene = sceneAt(index, offsetS);
    renderViews(index, offsetS, scene, -1, frame.leftRectified, frame.rightRectified, &frame.highlightMaskLeft);
    const Cameras c = cameras(index, offsetS);
    renderRectifiedGroundTruth(c.leftRect, c.rightRect, *scene.surface, frame.disparityPx, frame.depthMm);
    if (instruments.count() > 0) {
      const cv::Size size = calibration.imageSize;
      const InstrumentOccluder occluding(scene.instruments);
      frame.instrumentMask = cv::Mat::zeros(size, CV_8U);
      if (!occluding.empty()) {
        cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
          for (int y = rows.start; y < rows.end; ++y) {
            for (int x = 0; x < size.width; ++x) {
              if (occluding.hits(c.leftRect.centreWorldMm, c.leftRect.rayWorld(x, y))) frame.instrumentMask.at<uint8_t>(y, x) = 255;
            }
          }
        });
      }
    }
    return frame;
  }
};

SyntheticScan::SyntheticScan(const SyntheticScanOptions& options) : impl_(std::make_unique<Impl>()) {
  options.validate();
  Impl& s = *impl_;
  s.options = options;
  SyntheticStereoOptions rig;
  rig.width = options.width;
  rig.height = options.height;
  rig.focalPx = options.focalPx;
  rig.baselineMm = options.baselineMm;
  s.calibration = syntheticStereoCalibration(rig);
  const StereoRectifier rectifier(s.calibration);
  s.geometry = rectifier.geometry();
  s.R1 = rectifier.leftRectificationRotation().clone();
  s.R2 = rectifier.rightRectificationRotation().clone();
  s.P1 = rectifier.leftProjection().clone();
  s.P2 = rectifier.rightProjection().clone();
  if (options.rectifiedDisparityOffsetPx != 0) {
    // The right principal point moves right by doffs: x_right = x_left - (f B / Z - doffs). Q's last entry is doffs / B.
    s.P2.at<double>(0, 2) += options.rectifiedDisparityOffsetPx;
    s.geometry.doffsPx = options.rectifiedDisparityOffsetPx;
    s.geometry.Q = s.geometry.Q.clone();
    s.geometry.Q.at<double>(3, 3) = options.rectifiedDisparityOffsetPx / s.geometry.baselineMm;
  }
  s.path = std::make_unique<ScanPath>(options);

  // Bumps cover the raster plus the widest footprint of the view around it.
  TissueSurfaceParameters surfaceParameters;
  surfaceParameters.reliefMm = options.reliefMm;
  const double footprintMm = options.maxWorkingDistanceMm * 0.5 * options.width / s.geometry.focalPx;
  surfaceParameters.extentMm =
      std::max(70.0, 0.5 * std::max(options.rasterWidthMm, options.rasterHeightMm) + footprintMm + 10.0);
  s.surface = std::make_unique<TissueSurface>(surfaceParameters, options.seed);

  // After a camera-out the camera is back near where it left, then follows its path offset in its own frame:
  // T_path(t) T_path_return with T_path(end) T_path_return = T(start - 1) returnMotion.
  const SyntheticHardModeOptions& hard = options.hardMode;
  if (hard.cameraOut()) {
    s.cameraOut = SyntheticCameraOut(hard.cameraOutStart, hard.cameraOutEnd, options.seed);
    cv::Matx33d R_left, R_back;
    cv::Vec3d c_left, c_back;
    s.path->pose(options, *s.surface, (hard.cameraOutStart - 1) / options.fps, R_left, c_left);
    s.path->pose(options, *s.surface, hard.cameraOutEnd / options.fps, R_back, c_back);
    const Eigen::Matrix4d motion = s.cameraOut.returnMotion();
    cv::Matx33d R_motion;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R_motion(r, c) = motion(r, c);
    const cv::Matx33d R_world_returned = R_left * R_motion;
    const cv::Vec3d c_returned = c_left + R_left * cv::Vec3d(motion(0, 3), motion(1, 3), motion(2, 3));
    s.R_path_return = R_back.t() * R_world_returned;
    s.t_path_return = R_back.t() * (c_returned - c_back);
  }

  // What the frames see: border rays of every rectified view cast onto the surface.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300, nearestMm = 1e300, maxTangent = 0;
  for (int index = 0; index < options.frames; ++index) {
    if (s.cameraOut.contains(index)) continue;
    const Impl::Cameras c = s.cameras(index);
    for (const SyntheticCamera* camera : {&c.leftRect, &c.rightRect}) {
      const int w = camera->imageSize.width, h = camera->imageSize.height;
      for (int i = 0; i <= 32; ++i) {
        const double a = i / 32.0;
        const cv::Vec2d border[4] = {
            {a * w - 0.5, -0.5}, {a * w - 0.5, h - 0.5}, {-0.5, a * h - 0.5}, {w - 0.5, a * h - 0.5}};
        for (const cv::Vec2d& pixel : border) {
          const cv::Vec3d ray = camera->rayWorld(pixel[0], pixel[1]);
          require(ray[2] > 0, "synthetic scan: a view looks away from the tissue; lower the tilt");
          maxTangent = std::max(maxTangent, std::hypot(ray[0], ray[1]) / ray[2]);
          const double t = s.surface->intersect(camera->centreWorldMm, ray);
          require(std::isfinite(t), "synthetic scan: a view looks past the tissue; lower the tilt");
          const cv::Vec3d p = camera->centreWorldMm + t * ray;
          x0 = std::min(x0, p[0]);
          x1 = std::max(x1, p[0]);
          y0 = std::min(y0, p[1]);
          y1 = std::max(y1, p[1]);
          double depth = 0;
          camera->project(p, &depth);
          nearestMm = std::min(nearestMm, depth);
        }
      }
    }
  }
  const double margin = 3.0;
  s.domainMm = cv::Rect2d(x0 - margin, y0 - margin, x1 - x0 + 2 * margin, y1 - y0 + 2 * margin);
  require(s.surface->maxSlope(s.domainMm) * maxTangent < 0.98,
          "synthetic scan: the surface is too steep for these views and would hide parts of itself; lower the "
          "relief or the tilt");
  // About one texel per pixel where the tissue is nearest; coarser if the map would get huge.
  double texelMm = 0.8 * nearestMm / s.geometry.focalPx;
  texelMm = std::max(texelMm, std::sqrt(s.domainMm.area() / 16e6));
  s.texture = std::make_unique<TissueTexture>(s.domainMm, texelMm, options.seed, options.inVivo.tissueLook);
  if (options.lighting == SyntheticLighting::Realistic) {
    s.realisticLighting = std::make_unique<RealisticLighting>(*s.texture, options.seed);
  }

  if (hard.breathing()) {
    // The breathing part: around where the scope looks a little before the middle of the scan.
    int at = static_cast<int>(std::lround(0.45 * (options.frames - 1)));
    if (s.cameraOut.contains(at)) at = s.cameraOut.start() - 1;
    cv::Vec3d centre;
    require(s.viewCentreMm(at, centre), "synthetic scan: no tissue at the centre of the view for the breathing");
    s.breathing = SyntheticBreathing(hard.breathingAmplitudeMm, hard.breathingPeriodS, {centre[0], centre[1]},
                                     SyntheticBreathing::kInnerShare * hard.breathingRadiusMm, hard.breathingRadiusMm);
    if (hard.breathHold()) s.breathing.holdBreath(hard.breathHoldStartS, hard.breathHoldEndS);
    require(s.surface->swollen(s.breathing.peakSwell()).maxSlope(s.domainMm) * maxTangent < 0.98,
            "synthetic scan: the breathing makes the surface too steep for these views; lower --breathing-mm");
  }
  const SyntheticInVivoOptions& inVivo = options.inVivo;
  // The view's half extent on the tissue (mm, world X and Y for a scope without roll) at the middle working distance.
  const double middleDistanceMm = 0.5 * (options.minWorkingDistanceMm + options.maxWorkingDistanceMm);
  const cv::Vec2d viewHalfMm(middleDistanceMm * 0.5 * options.width / s.geometry.focalPx,
                             middleDistanceMm * 0.5 * options.height / s.geometry.focalPx);
  if (inVivo.breathingLateralMm > 0 || inVivo.pulse()) {
    std::mt19937 generator(options.seed ^ 0x9a15eu);
    const double lateralAngle = uniform(generator, 0, 2 * pi);
    if (inVivo.breathingLateralMm > 0) {
      s.breathing.setLateral(inVivo.breathingLateralMm, {std::cos(lateralAngle), std::sin(lateralAngle)});
    }
    if (inVivo.pulse()) {
      // A seeded place near the middle of the view where the scope looks a little before the middle of the scan.
      int at = static_cast<int>(std::lround(0.45 * (options.frames - 1)));
      if (s.cameraOut.contains(at)) at = s.cameraOut.start() - 1;
      cv::Vec3d centre;
      require(s.viewCentreMm(at, centre), "synthetic scan: no tissue at the centre of the view for the pulse");
      const double dx = uniform(generator, -kPulseOffsetShare, kPulseOffsetShare) * viewHalfMm[0];
      const double dy = uniform(generator, -kPulseOffsetShare, kPulseOffsetShare) * viewHalfMm[1];
      s.pulse = SyntheticPulse(inVivo.pulseAmplitudeMm, inVivo.pulsePeriodS, {centre[0] + dx, centre[1] + dy},
                               inVivo.pulseRadiusMm);
    }
  }
  if (s.deformsInVivo()) {
    // The tissue nearest the scope (breath and pulse at their peaks, the slide at its largest) and the steepest a
    // dent can make it must still show every point to every ray once.
    SurfaceDeformation peak;
    peak.slide = s.breathing.slideAt(0.5 * hard.breathingPeriodS);
    if (s.pulse.active()) peak.swells.push_back(s.pulse.peakSwell());
    const TissueSurface highest =
        (s.breathing.active() ? s.surface->swollen(s.breathing.peakSwell()) : *s.surface).deformed(peak);
    SurfaceSwell dent;
    dent.innerRadiusMm = kPushInnerRadiusMm;
    dent.outerRadiusMm = pushDentOuterRadiusMm(inVivo.pushMm);
    const double dentSlope = inVivo.pushMm * dent.maxWeightSlopePerMm();
    require((highest.maxSlope(s.domainMm) + dentSlope) * maxTangent < 0.98,
            "synthetic scan: the breathing, pulse and push make the surface too steep for these views; lower them or "
            "the tilt");
  }
  if (hard.instruments > 0) {
    TissueSurface highest = s.breathing.active() ? s.surface->swollen(s.breathing.peakSwell()) : *s.surface;
    if (s.pulse.active()) highest = highest.deformed({{s.pulse.peakSwell()}, {}});
    s.highestSurface = std::make_unique<TissueSurface>(highest);
    const cv::Vec2d borderReachMm = inVivo.instrumentsAtBorder ? kInstrumentBorderShare * viewHalfMm : cv::Vec2d(0, 0);
    s.instruments = SyntheticInstruments(
        hard.instruments, options.frames, options.fps, options.seed,
        [&s](int index, cv::Vec3d& point) { return s.viewCentreMm(index, point); }, *s.highestSurface,
        borderReachMm);
  }
}

SyntheticScan::~SyntheticScan() = default;

const SyntheticScanOptions& SyntheticScan::options() const { return impl_->options; }
int SyntheticScan::frameCount() const { return impl_->options.frames; }
const StereoCalibration& SyntheticScan::calibration() const { return impl_->calibration; }
const RectifiedGeometry& SyntheticScan::geometry() const { return impl_->geometry; }
const TissueSurface& SyntheticScan::surface() const { return *impl_->surface; }
cv::Rect2d SyntheticScan::scannedDomainMm() const { return impl_->domainMm; }
double SyntheticScan::timeS(int index) const { return index / impl_->options.fps; }

Eigen::Matrix4d SyntheticScan::T_world_camera(int index) const {
  require(index >= 0 && index < frameCount(), "synthetic scan: frame " + std::to_string(index) + " is outside [0, " +
                                                  std::to_string(frameCount()) + ")");
  cv::Matx33d R;
  cv::Vec3d centre;
  impl_->pose(index, 0.0, R, centre);
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T(r, c) = R(r, c);
    T(r, 3) = centre[r];
  }
  return T;
}

SyntheticScanFrame SyntheticScan::renderFrame(int index) const {
  const Impl& s = *impl_;
  const cv::Size size = s.calibration.imageSize;
  if (s.cameraOut.contains(index)) {
    SyntheticScanFrame frame;
    frame.index = index;
    frame.timeS = timeS(index);
    frame.T_world_camera = T_world_camera(index);
    frame.tissueInView = false;
    s.cameraOut.render(index, size, s.options.fps, s.options.noiseStdGrey, frame.leftRectified, frame.rightRectified);
    frame.disparityPx = cv::Mat(size, CV_32F, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
    frame.depthMm = frame.disparityPx.clone();
    if (s.instruments.count() > 0) frame.instrumentMask = cv::Mat::zeros(size, CV_8U);
    frame.highlightMaskLeft = cv::Mat::zeros(size, CV_8U);
    return frame;
  }
  // The truth, the masks and the exposure at the frame's time.
  SyntheticScanFrame frame = s.renderInstant(index, 0.0);
  frame.T_world_camera = T_world_camera(index);
  if (s.options.inVivo.timedCapture()) {
    // Each field averages its exposure's instants; the even field's middle instant is the render above.
    const std::vector<double> fields = fieldOffsetsS(s.options.inVivo.interlaced, s.options.fps);
    const std::vector<double> exposure = exposureOffsetsS(s.options.inVivo.motionBlurMs);
    cv::Mat leftSum, rightSum;
    for (std::size_t f = 0; f < fields.size(); ++f) {
      const int parity = fields.size() > 1 ? static_cast<int>(f) : -1;
      for (double offset : exposure) {
        const double at = fields[f] + offset;
        if (at == 0.0) {
          accumulateField(frame.leftRectified, parity, leftSum);
          accumulateField(frame.rightRectified, parity, rightSum);
          continue;
        }
        cv::Mat left, right;
        s.renderViews(index, at, s.sceneAt(index, at), parity, left, right, nullptr);
        accumulateField(left, parity, leftSum);
        accumulateField(right, parity, rightSum);
      }
    }
    const int count = static_cast<int>(exposure.size());
    frame.leftRectified = averagedImage(leftSum, count);
    frame.rightRectified = averagedImage(rightSum, count);
  }
  if (s.options.hardMode.smoke) {
    // Thin smoke over the tissue, drifting; the same density in both eyes (it has no texture to match).
    const cv::Mat density = hazeDensity(size, frame.timeS, s.options.seed);
    for (cv::Mat* image : {&frame.leftRectified, &frame.rightRectified}) {
      applyHaze(*image, density, kSmokeStrength, cv::Vec3d(185, 190, 200));
    }
  }
  return frame;
}

SyntheticScanFrame SyntheticScan::renderFrameAt(int index, double offsetS) const {
  require(index >= 0 && index < frameCount() && tissueInView(index),
          "synthetic scan: frame " + std::to_string(index) + " is not a frame with tissue");
  SyntheticScanFrame frame = impl_->renderInstant(index, offsetS);
  cv::Matx33d R;
  cv::Vec3d centre;
  impl_->pose(index, offsetS, R, centre);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) frame.T_world_camera(r, c) = R(r, c);
    frame.T_world_camera(r, 3) = centre[r];
  }
  if (impl_->options.hardMode.smoke) {
    const cv::Mat density = hazeDensity(impl_->calibration.imageSize, frame.timeS + offsetS, impl_->options.seed);
    for (cv::Mat* image : {&frame.leftRectified, &frame.rightRectified}) {
      applyHaze(*image, density, kSmokeStrength, cv::Vec3d(185, 190, 200));
    }
  }
  return frame;
}

bool SyntheticScan::tissueInView(int index) const {
  require(index >= 0 && index < frameCount(), "synthetic scan: frame " + std::to_string(index) + " is outside [0, " +
                                                  std::to_string(frameCount()) + ")");
  return !impl_->cameraOut.contains(index);
}

std::vector<int> SyntheticScan::tissueFrames() const {
  std::vector<int> frames;
  for (int index = 0; index < frameCount(); ++index) {
    if (!impl_->cameraOut.contains(index)) frames.push_back(index);
  }
  return frames;
}

const SyntheticBreathing& SyntheticScan::breathing() const { return impl_->breathing; }
const SyntheticInstruments& SyntheticScan::instruments() const { return impl_->instruments; }
const SyntheticPulse& SyntheticScan::pulse() const { return impl_->pulse; }

bool SyntheticScan::tissueDeforms() const { return impl_->breathing.active() || impl_->deformsInVivo(); }

TissueSurface SyntheticScan::surfaceAt(int index, double offsetS) const {
  require(index >= 0 && index < frameCount(), "synthetic scan: frame " + std::to_string(index) + " is outside [0, " +
                                                  std::to_string(frameCount()) + ")");
  return *impl_->sceneAt(index, offsetS).surface;
}

double SyntheticScan::surfaceHeightMm(double xMm, double yMm, int index) const {
  return surfaceAt(index).heightMm(xMm, yMm);
}

cv::Vec3d SyntheticScan::displacementMm(double restXMm, double restYMm, int index) const {
  return surfaceAt(index).materialPointMm(restXMm, restYMm) -
         cv::Vec3d(restXMm, restYMm, impl_->surface->heightMm(restXMm, restYMm));
}

TriangleMesh SyntheticScan::frameSurfaceMesh(const TriangleMesh& restMesh, int index) const {
  const TissueSurface now = surfaceAt(index);
  TriangleMesh mesh = restMesh;
  parallelFor<CpuBackend>(static_cast<int64_t>(mesh.verticesMm.size()), [&](int64_t v) {
    cv::Point3f& vertex = mesh.verticesMm[static_cast<std::size_t>(v)];
    const cv::Vec3d p = now.materialPointMm(vertex.x, vertex.y);
    vertex = cv::Point3f(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
  }, 4096);
  return mesh;
}

std::vector<SurfaceSwell> SyntheticScan::pushDentsAt(int index, double offsetS) const {
  require(index >= 0 && index < frameCount(), "synthetic scan: frame " + std::to_string(index) + " is outside [0, " +
                                                  std::to_string(frameCount()) + ")");
  return impl_->sceneAt(index, offsetS).dents;
}

TriangleMesh SyntheticScan::surfaceMesh(double spacingMm) const {
  require(spacingMm > 0, "synthetic scan: mesh spacing must be positive");
  const cv::Rect2d d = impl_->domainMm;
  const int nx = static_cast<int>(std::ceil(d.width / spacingMm)) + 1;
  const int ny = static_cast<int>(std::ceil(d.height / spacingMm)) + 1;
  require(static_cast<double>(nx) * ny <= 2e7, "synthetic scan: mesh spacing too fine for the scanned area");
  TriangleMesh mesh;
  mesh.verticesMm.reserve(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = d.x + i * spacingMm, y = d.y + j * spacingMm;
      mesh.verticesMm.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                   static_cast<float>(impl_->surface->heightMm(x, y)));
    }
  }
  mesh.triangles.reserve(2 * static_cast<std::size_t>(nx - 1) * (ny - 1));
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = j * nx + i, b = a + 1, c = a + nx, e = c + 1;
      mesh.triangles.emplace_back(a, c, b);  // both triangles wound the same way (normal toward -Z, the scope)
      mesh.triangles.emplace_back(b, c, e);
    }
  }
  return mesh;
}

TriangleMesh SyntheticScan::seenSurfaceMesh(double spacingMm, int frameStep) const {
  require(frameStep >= 1, "synthetic scan: the frame step must be at least 1");
  const TriangleMesh grid = surfaceMesh(spacingMm);
  const auto vertexCount = static_cast<int64_t>(grid.verticesMm.size());
  const auto triangleCount = static_cast<int64_t>(grid.triangles.size());
  std::vector<uint8_t> visible(grid.verticesMm.size()), seen(grid.triangles.size(), 0);
  std::vector<int> frames;
  const std::vector<int> tissue = tissueFrames();
  for (std::size_t k = 0; k < tissue.size(); k += static_cast<std::size_t>(frameStep)) frames.push_back(tissue[k]);
  if (frames.back() != tissue.back()) frames.push_back(tissue.back());
  for (int index : frames) {
    const Impl::Cameras c = impl_->cameras(index);
    parallelFor<CpuBackend>(vertexCount, [&](int64_t v) {
      const cv::Point3f& p = grid.verticesMm[static_cast<std::size_t>(v)];
      visible[static_cast<std::size_t>(v)] =
          seenBy(c.leftRect, p, kSeenBorderPx) && seenBy(c.rightRect, p, kSeenBorderPx);
    }, 4096);
    // All three vertices in the same frame: the whole triangle was in both views at once.
    parallelFor<CpuBackend>(triangleCount, [&](int64_t t) {
      const cv::Vec3i& triangle = grid.triangles[static_cast<std::size_t>(t)];
      if (visible[triangle[0]] && visible[triangle[1]] && visible[triangle[2]]) seen[static_cast<std::size_t>(t)] = 1;
    }, 8192);
  }
  TriangleMesh mesh;
  std::vector<int> newIndex(grid.verticesMm.size(), -1);
  for (std::size_t t = 0; t < grid.triangles.size(); ++t) {
    if (!seen[t]) continue;
    cv::Vec3i triangle;
    for (int k = 0; k < 3; ++k) {
      int& index = newIndex[static_cast<std::size_t>(grid.triangles[t][k])];
      if (index < 0) {
        index = static_cast<int>(mesh.verticesMm.size());
        mesh.verticesMm.push_back(grid.verticesMm[static_cast<std::size_t>(grid.triangles[t][k])]);
      }
      triangle[k] = index;
    }
    mesh.triangles.push_back(triangle);
  }
  require(!mesh.triangles.empty(), "synthetic scan: no triangle of the surface is seen by both eyes");
  return mesh;
}

TriangleMesh SyntheticScan::staticSurfaceMesh(double spacingMm, int frameStep, bool allowEmpty) const {
  const TriangleMesh seen = seenSurfaceMesh(spacingMm, frameStep);
  if (!tissueDeforms()) return seen;
  // Where a dent reached in some frame (its centre's rest XY; the slide moves it by less than the margin).
  std::vector<cv::Vec2d> dentCentres;
  if (impl_->options.inVivo.push()) {
    for (int index = 0; index < frameCount(); ++index) {
      for (const SurfaceSwell& dent : pushDentsAt(index)) dentCentres.emplace_back(dent.centreXMm, dent.centreYMm);
    }
  }
  const double dentReachMm =
      pushDentOuterRadiusMm(impl_->options.inVivo.pushMm) + impl_->options.inVivo.breathingLateralMm + 1.0;
  const auto isStill = [&](const cv::Point3f& p) {
    if (!impl_->breathing.isStatic(p.x, p.y)) return false;
    if (impl_->pulse.peakDisplacementMm(p.x, p.y) > SyntheticBreathing::kStaticToleranceMm) return false;
    for (const cv::Vec2d& centre : dentCentres) {
      if (cv::norm(cv::Vec2d(p.x, p.y) - centre) < dentReachMm) return false;
    }
    return true;
  };
  TriangleMesh mesh;
  std::vector<int> newIndex(seen.verticesMm.size(), -1);
  for (const cv::Vec3i& triangle : seen.triangles) {
    bool still = true;
    for (int k = 0; k < 3 && still; ++k) {
      still = isStill(seen.verticesMm[static_cast<std::size_t>(triangle[k])]);
    }
    if (!still) continue;
    cv::Vec3i kept;
    for (int k = 0; k < 3; ++k) {
      int& index = newIndex[static_cast<std::size_t>(triangle[k])];
      if (index < 0) {
        index = static_cast<int>(mesh.verticesMm.size());
        mesh.verticesMm.push_back(seen.verticesMm[static_cast<std::size_t>(triangle[k])]);
      }
      kept[k] = index;
    }
    mesh.triangles.push_back(kept);
  }
  require(allowEmpty || !mesh.triangles.empty(), "synthetic scan: the breathing moves every triangle the scan saw");
  return mesh;
}

TriangleMesh SyntheticScan::instrumentSurfaceMesh() const { return impl_->instruments.surfaceMesh(tissueFrames()); }

}  // namespace tissuemosaic::synthetic
