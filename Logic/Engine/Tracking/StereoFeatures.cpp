#include "Tracking/StereoFeatures.h"

#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParameterChecks.h"
#include "Core/PixelFormat.h"

#include <cmath>
#include <limits>

namespace tissuemosaic {

namespace {

void requireRange(double value, double low, double high, const char* name) {
  parameters::requireRange("feature", name, value, low, high);
}

/// Disparity at a sub-pixel position: bilinear where the 4 neighbours are estimates, else the nearest pixel's.
float sampleDisparity(const cv::Mat& disparity, const cv::Point2f& p) {
  const int x0 = static_cast<int>(std::floor(p.x)), y0 = static_cast<int>(std::floor(p.y));
  if (x0 >= 0 && y0 >= 0 && x0 + 1 < disparity.cols && y0 + 1 < disparity.rows) {
    const float a = p.x - x0, b = p.y - y0;
    const float d00 = disparity.at<float>(y0, x0), d01 = disparity.at<float>(y0, x0 + 1);
    const float d10 = disparity.at<float>(y0 + 1, x0), d11 = disparity.at<float>(y0 + 1, x0 + 1);
    const float d = (d00 * (1 - a) + d01 * a) * (1 - b) + (d10 * (1 - a) + d11 * a) * b;
    if (std::isfinite(d)) return d;
  }
  const int x = cvRound(p.x), y = cvRound(p.y);
  if (x < 0 || y < 0 || x >= disparity.cols || y >= disparity.rows) return std::numeric_limits<float>::quiet_NaN();
  return disparity.at<float>(y, x);
}

FeatureDetector orbDetector(cv::ORB& orb) {
  return [&orb](const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) {
    orb.detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
  };
}

}  // namespace

void FeatureParameters::validate() const {
  requireRange(maxFeatures, 10, 100000, "maxFeatures");
  requireRange(scaleFactor, 1.01, 2.0, "scaleFactor");
  requireRange(levels, 1, 16, "levels");
  requireRange(fastThreshold, 1, 255, "fastThreshold");
  requireRange(edgeThresholdPx, 3, 100, "edgeThresholdPx");
  requireRange(maxHammingDistance, 1, 256, "maxHammingDistance");
  requireRange(candidatesPerFeature, 0, 8, "candidatesPerFeature");
  requireRange(voteBinPx, 0.5, 1000, "voteBinPx");
  requireRange(maxRefinementShiftPx, 0.1, 100, "maxRefinementShiftPx");
}

void FeatureParameters::write(cv::FileStorage& storage) const {
  storage << "features" << "{";
  storage << "maxFeatures" << maxFeatures << "scaleFactor" << scaleFactor << "levels" << levels;
  storage << "fastThreshold" << fastThreshold << "edgeThresholdPx" << edgeThresholdPx;
  storage << "maxHammingDistance" << maxHammingDistance << "candidatesPerFeature" << candidatesPerFeature;
  storage << "voteBinPx" << voteBinPx << "subPixelRefinement" << static_cast<int>(subPixelRefinement);
  storage << "maxRefinementShiftPx" << maxRefinementShiftPx;
  storage << "}";
}

FeatureParameters FeatureParameters::read(const cv::FileNode& node) {
  FeatureParameters p;
  if (node.empty()) return p;
  if (!node.isMap()) throw Error("the 'features' parameter node must be a map");
  const auto key = [&node](const char* name, auto& value) { parameters::readKey("feature", node, name, value); };
  key("maxFeatures", p.maxFeatures);
  key("scaleFactor", p.scaleFactor);
  key("levels", p.levels);
  key("fastThreshold", p.fastThreshold);
  key("edgeThresholdPx", p.edgeThresholdPx);
  key("maxHammingDistance", p.maxHammingDistance);
  key("candidatesPerFeature", p.candidatesPerFeature);
  key("voteBinPx", p.voteBinPx);
  int subPixel = p.subPixelRefinement ? 1 : 0;
  key("subPixelRefinement", subPixel);
  if (subPixel != 0 && subPixel != 1) throw Error("feature parameter subPixelRefinement must be 0 or 1");
  p.subPixelRefinement = subPixel == 1;
  key("maxRefinementShiftPx", p.maxRefinementShiftPx);
  p.validate();
  return p;
}

StereoFeatures detectFeatures(const FeatureDetector& detect, const cv::Mat& leftRectified) {
  StereoFeatures features;
  cv::Mat& grey = features.grey;
  {
    profiling::ScopedTimer timer("host: features grey");
    grey = toGrey8(leftRectified, "tracking: the left image");
    // The features keep their image (the sub-pixel reference of the next frames): never the caller's buffer.
    if (grey.data == leftRectified.data) grey = grey.clone();
  }
  profiling::ScopedTimer timer("host: features detect");
  detect(grey, features.keypoints, features.descriptors);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  features.pointsCameraMm.assign(features.keypoints.size(), Eigen::Vector3d(nan, nan, nan));
  return features;
}

StereoFeatures detectFeatures(cv::ORB& orb, const cv::Mat& leftRectified) {
  return detectFeatures(orbDetector(orb), leftRectified);
}

void liftFeatures(StereoFeatures& features, const cv::Mat& disparityPx, const RectifiedGeometry& geometry) {
  require(disparityPx.type() == CV_32FC1 && disparityPx.size() == features.grey.size(),
          "tracking: the disparity map must be CV_32F and of the left image's size");
  profiling::ScopedTimer timer("host: features lift");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  features.pointsCameraMm.assign(features.keypoints.size(), Eigen::Vector3d(nan, nan, nan));
  features.withDepth = 0;
  for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
    const cv::Point2f p = features.keypoints[i].pt;
    const double d = sampleDisparity(disparityPx, p);
    if (!std::isfinite(d) || d + geometry.doffsPx <= 0) continue;
    const double z = geometry.depthMm(d);
    double x, y;
    geometry.leftIntrinsics().backProject(p.x, p.y, z, x, y);
    features.pointsCameraMm[i] = Eigen::Vector3d(x, y, z);
    ++features.withDepth;
  }
}

StereoFeatures extractStereoFeatures(cv::ORB& orb, const cv::Mat& leftRectified, const cv::Mat& disparityPx,
                                     const RectifiedGeometry& geometry) {
  return extractStereoFeatures(orbDetector(orb), leftRectified, disparityPx, geometry);
}

StereoFeatures extractStereoFeatures(const FeatureDetector& detect, const cv::Mat& leftRectified,
                                     const cv::Mat& disparityPx, const RectifiedGeometry& geometry) {
  StereoFeatures features = detectFeatures(detect, leftRectified);  // each half checks its own input
  liftFeatures(features, disparityPx, geometry);
  return features;
}

}  // namespace tissuemosaic
