#pragma once
// Analytic scenes for the key-frame refinement tests (TestRefinement.cpp, TestRefinementCuda.cpp): feature points
// with exact projections (plus pixel noise) and one random 256-bit descriptor each, and a curved surface measured per
// pixel with exact normals. Deterministic from a seed. Header-only so both test drivers can use it.
#include "Core/StereoRig.h"
#include "Refinement/KeyFrameRefiner.h"
#include "Core/SurfaceMeasurement.h"
#include "Tracking/StereoFeatures.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cmath>
#include <random>
#include <vector>

namespace tissuemosaic::refinement_test {

inline RectifiedGeometry testGeometry() {
  RectifiedGeometry g;
  g.imageSize = cv::Size(640, 480);
  g.focalPx = 500;
  g.cxLeftPx = 320;
  g.cyPx = 240;
  g.baselineMm = 5;
  return g;
}

/// Camera-to-world pose: rotation about `axis` by `degrees`, then translation.
inline Eigen::Matrix4d pose(const Eigen::Vector3d& axis, double degrees, const Eigen::Vector3d& translationMm) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  if (degrees != 0) T.block<3, 3>(0, 0) = Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  T.block<3, 1>(0, 3) = translationMm;
  return T;
}

/// Rotation (degrees) and translation (mm) between two camera-to-world poses.
inline void poseError(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double& degrees, double& mm) {
  degrees = Eigen::AngleAxisd(Eigen::Matrix3d(a.block<3, 3>(0, 0).transpose() * b.block<3, 3>(0, 0))).angle() * 180 / M_PI;
  mm = (a.block<3, 1>(0, 3) - b.block<3, 1>(0, 3)).norm();
}

/// A random rigid perturbation of `degrees` about a random axis and `mm` in a random direction, applied in the
/// world frame on the left: T' = D T.
inline Eigen::Matrix4d perturb(const Eigen::Matrix4d& T, double degrees, double mm, std::mt19937& random) {
  std::normal_distribution<double> normal(0, 1);
  const Eigen::Vector3d axis(normal(random), normal(random), normal(random));
  const Eigen::Vector3d direction(normal(random), normal(random), normal(random));
  Eigen::Matrix4d D = pose(axis, degrees, mm * direction.normalized());
  // Rotate about the camera centre, so that `mm` is the centre's displacement.
  const Eigen::Vector3d centre = T.block<3, 1>(0, 3);
  D.block<3, 1>(0, 3) += centre - D.block<3, 3>(0, 0) * centre;
  return D * T;
}

/// World points on a gently curved surface in front of the world origin, each with a random 32-byte descriptor.
struct FeatureScene {
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> pointsWorldMm;
  cv::Mat descriptors;  ///< one row per point

  FeatureScene(int count, unsigned seed) : descriptors(count, 32, CV_8U) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> x(-45, 65), y(-35, 35);
    for (int i = 0; i < count; ++i) {
      const double px = x(random), py = y(random);
      pointsWorldMm.emplace_back(px, py, heightMm(px, py));
    }
    if (count > 0) cv::randu(descriptors, 0, 256);
  }

  /// The surface the points lie on: z = h(x, y) in the world frame.
  static double heightMm(double x, double y) { return 60 + 0.004 * (x * x + y * y) + 3 * std::sin(0.1 * x); }
  static Eigen::Vector3d upNormal(double x, double y) {  // (-dh/dx, -dh/dy, 1), normalised
    return Eigen::Vector3d(-(0.008 * x + 0.3 * std::cos(0.1 * x)), -0.008 * y, 1).normalized();
  }

  /// The surface as the stereo stage of a camera at T_world_camera would measure it: per pixel the ray's first
  /// intersection (Newton's method along the ray) and the normal turned toward the camera, in the camera frame.
  SurfaceMeasurement measure(const Eigen::Matrix4d& T_world_camera, const RectifiedGeometry& g) const {
    SurfaceMeasurement m;
    m.pointsCameraMm.create(g.imageSize, CV_32FC3);
    m.normalsCamera.create(g.imageSize, CV_32FC3);
    const Eigen::Matrix3d R = T_world_camera.block<3, 3>(0, 0);
    const Eigen::Vector3d o = T_world_camera.block<3, 1>(0, 3);
    for (int v = 0; v < g.imageSize.height; ++v) {
      for (int u = 0; u < g.imageSize.width; ++u) {
        const Eigen::Vector3d ray((u - g.cxLeftPx) / g.focalPx, (v - g.cyPx) / g.focalPx, 1);
        const Eigen::Vector3d d = R * ray;
        double s = 60;  // depth along the optical axis
        for (int it = 0; it < 30; ++it) {
          const Eigen::Vector3d p = o + s * d;
          const Eigen::Vector3d n = upNormal(p.x(), p.y());
          // g(s) = p_z - h(p_x, p_y); g'(s) = d . (-h_x, -h_y, 1) = d . n * |(-h_x, -h_y, 1)|
          const double gs = p.z() - heightMm(p.x(), p.y());
          const double slope = d.dot(n) / n.z();
          s -= gs / slope;
          if (std::abs(gs) < 1e-9) break;
        }
        const Eigen::Vector3d p = o + s * d;
        Eigen::Vector3d n = R.transpose() * upNormal(p.x(), p.y());
        const Eigen::Vector3d c = s * ray;
        if (n.dot(c) > 0) n = -n;
        m.pointsCameraMm.at<cv::Vec3f>(v, u) = cv::Vec3f(c.x(), c.y(), c.z());
        m.normalsCamera.at<cv::Vec3f>(v, u) = cv::Vec3f(n.x(), n.y(), n.z());
      }
    }
    m.validPixels = g.imageSize.area();
    return m;
  }

  /// Model points on the surface: a regular grid over the scene.
  static std::vector<Eigen::Vector3f> model(double stepMm) {
    std::vector<Eigen::Vector3f> points;
    for (double y = -35; y <= 35; y += stepMm) {
      for (double x = -45; x <= 65; x += stepMm) points.emplace_back(x, y, heightMm(x, y));
    }
    return points;
  }

  /// The features a camera at T_world_camera sees: exact projections plus Gaussian pixel noise, stereo points (the
  /// true camera-frame point plus depthNoiseMm along the ray), descriptors with `flippedBits` random bits flipped,
  /// and `outliers` extra features at random pixels with random descriptors and depths.
  StereoFeatures observe(const Eigen::Matrix4d& T_world_camera, const RectifiedGeometry& g, double pixelNoisePx,
                         double depthNoiseMm, int flippedBits, int outliers, unsigned seed) const {
    std::mt19937 random(seed);
    std::normal_distribution<double> noise(0, 1);
    std::uniform_real_distribution<double> uniform(0, 1);
    const Eigen::Matrix4d T_camera_world = T_world_camera.inverse();
    StereoFeatures f;
    std::vector<cv::Mat> rows;
    const auto add = [&](const cv::Point2f& px, const Eigen::Vector3d& pointCamera, const cv::Mat& descriptor) {
      f.keypoints.emplace_back(px, 31.f, -1.f, static_cast<float>(uniform(random)));
      f.pointsCameraMm.push_back(pointCamera);
      rows.push_back(descriptor);
    };
    for (std::size_t i = 0; i < pointsWorldMm.size(); ++i) {
      const Eigen::Vector3d c = T_camera_world.block<3, 3>(0, 0) * pointsWorldMm[i] + T_camera_world.block<3, 1>(0, 3);
      if (c.z() <= 1) continue;
      const double u = g.focalPx * c.x() / c.z() + g.cxLeftPx + pixelNoisePx * noise(random);
      const double v = g.focalPx * c.y() / c.z() + g.cyPx + pixelNoisePx * noise(random);
      if (u < 20 || v < 20 || u > g.imageSize.width - 20 || v > g.imageSize.height - 20) continue;
      cv::Mat descriptor = descriptors.row(static_cast<int>(i)).clone();
      for (int b = 0; b < flippedBits; ++b) {
        const int bit = static_cast<int>(uniform(random) * 256) % 256;
        descriptor.at<uint8_t>(0, bit / 8) ^= static_cast<uint8_t>(1u << (bit % 8));
      }
      add(cv::Point2f(static_cast<float>(u), static_cast<float>(v)), c * (1 + depthNoiseMm * noise(random) / c.norm()),
          descriptor);
    }
    for (int k = 0; k < outliers; ++k) {
      cv::Mat descriptor(1, 32, CV_8U);
      cv::randu(descriptor, 0, 256);
      const cv::Point2f px(static_cast<float>(20 + uniform(random) * (g.imageSize.width - 40)),
                           static_cast<float>(20 + uniform(random) * (g.imageSize.height - 40)));
      const double z = 50 + 20 * uniform(random);
      add(px, Eigen::Vector3d((px.x - g.cxLeftPx) / g.focalPx * z, (px.y - g.cyPx) / g.focalPx * z, z), descriptor);
    }
    if (!rows.empty()) cv::vconcat(rows, f.descriptors);
    else f.descriptors.create(0, 32, CV_8U);
    f.withDepth = static_cast<int>(f.keypoints.size());
    return f;
  }
};

/// The elliptic paraboloid z = z0 + ax x^2 + ay y^2 in the frame of a camera at the origin looking down +z (not
/// symmetric about the optical axis, so every pose component is observable by point-to-plane ICP).
struct CurvedSurface {
  double z0Mm = 60;
  double axPerMm = 0.008, ayPerMm = 0.016;

  /// Per pixel: the ray's intersection and the unit normal turned toward the camera.
  SurfaceMeasurement measure(const RectifiedGeometry& g) const {
    SurfaceMeasurement m;
    m.pointsCameraMm.create(g.imageSize, CV_32FC3);
    m.normalsCamera.create(g.imageSize, CV_32FC3);
    for (int v = 0; v < g.imageSize.height; ++v) {
      for (int u = 0; u < g.imageSize.width; ++u) {
        const double rx = (u - g.cxLeftPx) / g.focalPx, ry = (v - g.cyPx) / g.focalPx;
        const double a = axPerMm * rx * rx + ayPerMm * ry * ry;
        // a z^2 - z + z0 = 0, the root nearer the camera.
        const double z = a > 0 ? (1 - std::sqrt(1 - 4 * a * z0Mm)) / (2 * a) : z0Mm;
        const Eigen::Vector3d p(rx * z, ry * z, z);
        const Eigen::Vector3d n = Eigen::Vector3d(2 * axPerMm * p.x(), 2 * ayPerMm * p.y(), -1).normalized();
        m.pointsCameraMm.at<cv::Vec3f>(v, u) = cv::Vec3f(p.x(), p.y(), p.z());
        m.normalsCamera.at<cv::Vec3f>(v, u) = cv::Vec3f(n.x(), n.y(), n.z());
      }
    }
    m.validPixels = g.imageSize.area();
    return m;
  }

  /// Points of the surface on a regular grid of (x, y) (camera frame = world frame of the true pose).
  std::vector<Eigen::Vector3f> sample(double halfWidthMm, double halfHeightMm, int perSide) const {
    std::vector<Eigen::Vector3f> points;
    for (int j = 0; j < perSide; ++j) {
      for (int i = 0; i < perSide; ++i) {
        const double x = -halfWidthMm + 2 * halfWidthMm * i / (perSide - 1);
        const double y = -halfHeightMm + 2 * halfHeightMm * j / (perSide - 1);
        points.emplace_back(x, y, z0Mm + axPerMm * x * x + ayPerMm * y * y);
      }
    }
    return points;
  }
};

/// The true camera path: 1 mm and 0.1 degree per frame.
inline Eigen::Matrix4d truePose(int frame) {
  return pose(Eigen::Vector3d(0.3, 1, 0.2), 0.1 * frame, Eigen::Vector3d(1.0 * frame, 0.3 * frame, 0.1 * frame));
}

/// Key frames 0 and 10 at their true poses, then intermediate frames 11..19 and key frame 20 tracked with errors
/// of `errorDeg` and `errorMm` each (random directions); key frame 20 is refined (withIcp: with the scene's surface as
/// the model and its measurement at the true pose; inTwoHalves: in the refiner's parts rather than one call).
struct BundleRun {
  RefinementResult result;
  RefinementResult previous;  ///< key frame 10's refinement (from its true pose)
  Eigen::Matrix4d trackedKey, trueKey;
  std::vector<Eigen::Matrix4d, Eigen::aligned_allocator<Eigen::Matrix4d>> trackedIntermediate, trueIntermediate;
  int storedKeyFrames = 0;
};

inline BundleRun runBundleScenario(Device device, const RefinementParameters& parameters = {}, double errorDeg = 1.5,
                                   double errorMm = 2.0, double pixelNoisePx = 0.5, double depthNoiseMm = 0.1,
                                   int outliers = 100, bool withIcp = false, unsigned seed = 7,
                                   bool inTwoHalves = false) {
  const RectifiedGeometry g = testGeometry();
  const FeatureScene scene(1500, seed);
  KeyFrameRefiner refiner(g, parameters, TrackingParameters{}, FeatureParameters{}, device);
  const SurfaceMeasurement none;
  BundleRun run;
  unsigned view = seed * 1000;
  const auto observe = [&](int frame) { return scene.observe(truePose(frame), g, pixelNoisePx, depthNoiseMm, 4, outliers, ++view); };
  refiner.refineKeyFrame(0, observe(0), truePose(0), none, {}, {});
  for (int f = 1; f < 10; ++f) refiner.addIntermediateFrame(f, observe(f), truePose(f));
  run.previous = refiner.refineKeyFrame(10, observe(10), truePose(10), none, {}, {});
  std::mt19937 random(seed);
  for (int f = 11; f < 20; ++f) {
    run.trueIntermediate.push_back(truePose(f));
    run.trackedIntermediate.push_back(perturb(truePose(f), errorDeg, errorMm, random));
    refiner.addIntermediateFrame(f, observe(f), run.trackedIntermediate.back());
  }
  run.trueKey = truePose(20);
  run.trackedKey = perturb(run.trueKey, errorDeg, errorMm, random);
  const SurfaceMeasurement measurement = withIcp ? scene.measure(run.trueKey, g) : none;
  const std::vector<Eigen::Vector3f> model = withIcp ? FeatureScene::model(0.5) : std::vector<Eigen::Vector3f>{};
  if (inTwoHalves) {  // KeyFrameRefiner::matchKeyFrame, selectIcpModelPoints, then refineMatchedKeyFrame
    const StereoFeatures features = observe(20);
    KeyFrameMatches matches = refiner.matchKeyFrame(20, features, run.trackedKey);
    const IcpModelPoints icp = refiner.selectIcpModelPoints(measurement, model, run.trackedKey);
    run.result = refiner.refineMatchedKeyFrame(std::move(matches), measurement, icp);
  } else {
    run.result = refiner.refineKeyFrame(20, observe(20), run.trackedKey, measurement, model, {});
  }
  run.storedKeyFrames = refiner.keyFrameCount();
  return run;
}

}  // namespace tissuemosaic::refinement_test
