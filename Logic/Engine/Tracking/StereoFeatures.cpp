#include "Tracking/StereoFeatures.h"

#include "Core/DisparitySampling.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/PixelFormat.h"

#include <cmath>
#include <limits>

namespace tissuemosaic {

namespace {

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

std::vector<cv::Point2f> keypointPositions(const StereoFeatures& features) {
  std::vector<cv::Point2f> positions;
  positions.reserve(features.keypoints.size());
  for (const cv::KeyPoint& k : features.keypoints) positions.push_back(k.pt);
  return positions;
}

std::vector<float> sampleDisparityMap(const cv::Mat& disparityPx, cv::Size imageSize,
                                      const std::vector<cv::Point2f>& pointsPx) {
  require(disparityPx.type() == CV_32FC1 && disparityPx.size() == imageSize,
          "tracking: the disparity map must be CV_32F and of the left image's size");
  const cv::Mat map = disparityPx.isContinuous() ? disparityPx : disparityPx.clone();
  const ImageView<const float> view{map.ptr<float>(), map.cols, map.rows};
  std::vector<float> samples;
  samples.reserve(pointsPx.size());
  for (const cv::Point2f& p : pointsPx) samples.push_back(sampleDisparityPx(view, p.x, p.y));
  return samples;
}

void liftFeatures(StereoFeatures& features, const cv::Mat& disparityPx, const RectifiedGeometry& geometry) {
  liftFeatures(features, sampleDisparityMap(disparityPx, features.grey.size(), keypointPositions(features)), geometry);
}

void liftFeatures(StereoFeatures& features, const std::vector<float>& disparityAtKeypointsPx,
                  const RectifiedGeometry& geometry) {
  require(disparityAtKeypointsPx.size() == features.keypoints.size(),
          "tracking: one disparity sample per keypoint is needed to lift the features");
  profiling::ScopedTimer timer("host: features lift");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  features.pointsCameraMm.assign(features.keypoints.size(), Eigen::Vector3d(nan, nan, nan));
  features.withDepth = 0;
  for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
    const cv::Point2f p = features.keypoints[i].pt;
    const double d = disparityAtKeypointsPx[i];
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
