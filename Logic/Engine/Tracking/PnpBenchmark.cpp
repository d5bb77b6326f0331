#include "Tracking/PnpBenchmark.h"

#include "Core/Error.h"
#include "Core/ParameterError.h"
#include "Core/Statistics.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <numeric>
#include <random>
#include <sstream>

namespace tissuemosaic {

namespace {

std::string cpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown cpu";
}

std::string jsonEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}


struct Outcome {
  bool success = false;
  Eigen::Matrix4d T_camera_world = Eigen::Matrix4d::Identity();
};

Outcome runOpenCv(const SyntheticPnpCase& scene, int iterations) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (std::size_t i = 0; i < scene.pointsMm.size(); ++i) {
    object.emplace_back(scene.pointsMm[i].x(), scene.pointsMm[i].y(), scene.pointsMm[i].z());
    image.emplace_back(scene.pixelsPx[i].x(), scene.pixelsPx[i].y());
  }
  const cv::Matx33d K(scene.intrinsics.fxPx, 0, scene.intrinsics.cxPx, 0, scene.intrinsics.fyPx,
                      scene.intrinsics.cyPx, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  Outcome outcome;
  outcome.success = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false, iterations, 5.0f, 0.99,
                                       inliers, cv::SOLVEPNP_AP3P);
  if (outcome.success && !rvec.empty()) {
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d Re;
    Eigen::Vector3d te;
    cv::cv2eigen(R, Re);
    cv::cv2eigen(tvec, te);
    outcome.T_camera_world.block<3, 3>(0, 0) = Re;
    outcome.T_camera_world.block<3, 1>(0, 3) = te;
  }
  return outcome;
}

}  // namespace

SyntheticPnpCase makeSyntheticPnpCase(std::uint64_t seed, int n, double outlierRatio, double noisePx) {
  require(n >= 1, "synthetic PnP case needs at least one point");
  require(outlierRatio >= 0 && outlierRatio < 1, "synthetic PnP outlier ratio must be in [0, 1)");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  SyntheticPnpCase scene;
  scene.intrinsics = {1000.0, 1000.0, 480.0, 270.0};
  const double W = scene.widthPx, H = scene.heightPx;
  const PinholeIntrinsics& k = scene.intrinsics;

  // Surface in the camera frame: depth over normalised image coordinates, smooth, tilted, 60-110 mm away.
  const double distanceMm = 60.0 + 50.0 * unit(rng);
  const double tiltX = 20.0 * (unit(rng) - 0.5), tiltY = 20.0 * (unit(rng) - 0.5);
  const double bumpMm = 3.0 + 5.0 * unit(rng), phaseX = 6.3 * unit(rng), phaseY = 6.3 * unit(rng);
  auto depthMm = [&](double xn, double yn) {
    return distanceMm + tiltX * xn + tiltY * yn + bumpMm * std::sin(4.0 * xn + phaseX) * std::cos(5.0 * yn + phaseY);
  };
  // Random camera pose in the world.
  const Eigen::Quaterniond q(Eigen::Vector4d(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized());
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();
  T_world_camera.block<3, 3>(0, 0) = q.toRotationMatrix();
  T_world_camera.block<3, 1>(0, 3) = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5) * 100.0;
  scene.T_camera_world = T_world_camera.inverse();

  const int outliers = static_cast<int>(std::lround(n * outlierRatio));
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  scene.isInlier.assign(n, 1);
  for (int i = 0; i < outliers; ++i) scene.isInlier[order[i]] = 0;

  auto randomPixel = [&]() { return Eigen::Vector2d(W * unit(rng), H * unit(rng)); };
  auto noisy = [&](const Eigen::Vector2d& p) { return Eigen::Vector2d(p + noisePx * Eigen::Vector2d(gauss(rng), gauss(rng))); };
  scene.candidates.resize(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d truePx(W * unit(rng), H * unit(rng));
    const double xn = k.normalisedX(truePx.x()), yn = k.normalisedY(truePx.y());
    const Eigen::Vector3d cameraPoint = depthMm(xn, yn) * Eigen::Vector3d(xn, yn, 1.0);
    scene.pointsMm.push_back((T_world_camera * cameraPoint.homogeneous()).head<3>());
    scene.pixelsPx.push_back(scene.isInlier[i] ? noisy(truePx) : randomPixel());
    for (int c = 0; c < 2; ++c) {
      CandidateMatch candidate;
      if (c == 0 && !scene.isInlier[i] && unit(rng) < 0.5) {
        candidate.pixelPx = noisy(truePx);
      } else if (unit(rng) < 0.5) {
        const double angle = 6.283185307 * unit(rng), radius = 40.0 * std::sqrt(unit(rng));
        candidate.pixelPx = truePx + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      } else {
        candidate.pixelPx = randomPixel();
      }
      scene.candidates[i].push_back(candidate);
    }
  }
  return scene;
}

std::string runPnpBenchmark(const PnpBenchmarkOptions& options) {
  requireParameter(options.repeats >= 1 && options.repeats <= 100000, "repeats",
                   "bench pnp: the repeat count must be in [1, 100000]");
  cv::setNumThreads(1);  // OpenCV single-threaded, as ours: the comparison is one core against one core
  const std::vector<int> sizes = options.quick ? std::vector<int>{200} : std::vector<int>{200, 500, 1000};
  const std::vector<double> ratios =
      options.quick ? std::vector<double>{0.5, 0.9} : std::vector<double>{0.5, 0.8, 0.9, 0.95};
  const TrackingParameters parameters;
  using Method = std::function<Outcome(const SyntheticPnpCase&)>;
  const std::vector<std::pair<std::string, Method>> methods = {
      {"R1PPnP",
       [&](const SyntheticPnpCase& s) {
         const PnpResult r = solveR1Ppnp(s.pointsMm, s.pixelsPx, s.intrinsics, parameters);
         return Outcome{r.success, r.T_camera_world};
       }},
      {"DynamicR1PPnP",
       [&](const SyntheticPnpCase& s) {
         const PnpResult r = solveDynamicR1Ppnp(s.pointsMm, s.pixelsPx, s.candidates, s.intrinsics, parameters);
         return Outcome{r.success, r.T_camera_world};
       }},
      {"opencv_ap3p_ransac_100", [](const SyntheticPnpCase& s) { return runOpenCv(s, 100); }},
      {"opencv_ap3p_ransac_10000", [](const SyntheticPnpCase& s) { return runOpenCv(s, 10000); }},
  };

  std::ostringstream json;
  json << std::setprecision(6);
  json << "{\"device\": \"" << jsonEscape(cpuModel()) << "\", \"threads\": 1, \"repeats\": " << options.repeats
       << ", \"seed\": " << options.seed
       << ", \"success\": \"rotation error < 1 deg and camera-centre error < 2 mm\", \"cases\": [";
  bool first = true;
  for (int n : sizes) {
    for (double ratio : ratios) {
      std::vector<SyntheticPnpCase> scenes;
      for (int r = 0; r < options.repeats; ++r) {
        const std::uint64_t seed = options.seed * 1000003ULL + static_cast<std::uint64_t>(n) * 7919ULL +
                                   static_cast<std::uint64_t>(ratio * 1000) * 104729ULL + static_cast<std::uint64_t>(r);
        scenes.push_back(makeSyntheticPnpCase(seed, n, ratio, 1.0));
      }
      for (const auto& [name, method] : methods) {
        std::vector<double> milliseconds;
        int successes = 0;
        for (const SyntheticPnpCase& scene : scenes) {
          const auto start = std::chrono::steady_clock::now();
          const Outcome outcome = method(scene);
          const auto stop = std::chrono::steady_clock::now();
          milliseconds.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
          double rotationDeg = 0, centreMm = 0;
          poseDifference(outcome.T_camera_world, scene.T_camera_world, rotationDeg, centreMm);
          if (outcome.success && rotationDeg < 1.0 && centreMm < 2.0) ++successes;
        }
        json << (first ? "" : ", ") << "{\"method\": \"" << name << "\", \"outlier_ratio\": " << ratio
             << ", \"n\": " << n << ", \"success_rate\": " << static_cast<double>(successes) / scenes.size()
             << ", \"median_ms\": " << median(milliseconds) << "}";
        first = false;
      }
    }
  }
  json << "]}";
  return json.str();
}

}  // namespace tissuemosaic
