#include "Tracking/StereoFeatures.h"

#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/PixelFormat.h"

#include <cmath>
#include <limits>

namespace tissuemosaic {

namespace {

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
