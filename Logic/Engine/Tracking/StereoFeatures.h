#pragma once
/// @file StereoFeatures.h
/// @brief ORB features of a rectified left image, each lifted to 3D (left rectified camera frame, mm) from the
/// left-view disparity map where the stereo stage has an estimate.
#include "Core/StereoRig.h"
#include "Tracking/PnpSolver.h"

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <functional>
#include <vector>

namespace tissuemosaic {

struct FeatureParameters {
  /// ORB features kept per frame (the strongest by FAST/Harris response). The paper gives no number. Measured on
  /// the 300-frame synthetic scan (H100, docs/RECONSTRUCTION.md): 1000 / 1500 / 2000 features track a frame in
  /// 2.1 / 3.0 / 3.6 ms with key-frame position errors of 0.29 / 0.25 / 0.23 mm and model RMSE 0.17 / 0.16 / 0.16 mm.
  int maxFeatures = 1000;
  double scaleFactor = 1.2;     ///< ORB pyramid scale between levels
  /// ORB pyramid levels. Adjacent frames of a slow scan barely change scale, and keypoints of coarse levels are
  /// poorly localised: on the synthetic scans 8 levels drift 4x more than 2 (ATE over 30 frames 1.3-1.8 vs 0.3 mm),
  /// and 1 level tracks as well as 2 (FrameTracker test, 16 frames: 0.145 vs 0.134 mm; key-frame refinement test:
  /// 0.23 vs 0.34 mm after refinement) with half the GPU extractor's launches and downloads.
  int levels = 1;
  int fastThreshold = 10;       ///< FAST corner threshold (grey levels); low: tissue has weak texture
  /// A frame with fewer features than this (dark, blood-red, blurred tissue: real in-vivo video) is detected again
  /// with weakFastThreshold and keeps the larger set. The in-vivo generator's 960x540 frames gave 20-30 inliers at
  /// threshold 10, too few for a key frame (keyFrameMinInliers), and tracking starved; at 5, 300-500.
  int weakTextureFeatures = 300;
  int weakFastThreshold = 5;
  int edgeThresholdPx = 19;     ///< border without features (>= the ORB patch radius)
  int maxHammingDistance = 64;  ///< descriptor matches farther than this (of 256 bits) are dropped
  int candidatesPerFeature = 2; ///< further descriptor matches offered to DynamicR1PPnP per feature (k - 1)
  double voteBinPx = 6.0;       ///< histogram-voting bin size
  /// Not in the paper: refine each primary match to sub-pixel accuracy by Lucas-Kanade from the reference
  /// keypoint (ORB positions are only good to about a pixel, and frame-to-frame pose noise accumulates as drift).
  bool subPixelRefinement = true;
  double maxRefinementShiftPx = 2.0;  ///< a refinement moving a match farther than this is ignored

  /// Throws Error naming the first parameter that is out of range.
  void validate() const;
  /// Writes the parameters under the node name "features".
  void write(cv::FileStorage& storage) const;
  /// Reads a "features" node; missing keys keep their defaults, keys of the wrong type are an error. Validates.
  static FeatureParameters read(const cv::FileNode& featuresNode);
};

/// One frame's features. pointsCameraMm[i] is NaN where keypoint i has no depth.
struct StereoFeatures {
  cv::Mat grey;           ///< the 8-bit grey image the features were detected in
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;    ///< CV_8U, one 32-byte row per keypoint
  Points3d pointsCameraMm;
  int withDepth = 0;      ///< keypoints that have a 3D point
  /// Per keypoint, set by FrameTracker: 1 where the feature moved with the scene recently (its 3D point is then
  /// cleared too); empty: nothing known.
  std::vector<uint8_t> moving;
};

/// Finds keypoints and 32-byte binary descriptors (one CV_8U row each) in an 8-bit grey image.
using FeatureDetector = std::function<void(const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors)>;

/// Detects features on the (grey or BGR, 8-bit) rectified left image, without depth yet (pointsCameraMm all NaN):
/// the tracker matches them while the stereo stage is still computing the frame's disparity.
StereoFeatures detectFeatures(const FeatureDetector& detect, const cv::Mat& leftRectified);
/// The same with OpenCV's ORB as the detector.
StereoFeatures detectFeatures(cv::ORB& orb, const cv::Mat& leftRectified);
/// Lifts each feature with the disparity (CV_32F, NaN = none, of the features' image size) sampled bilinearly at
/// the keypoint when its 4 neighbours have estimates, else at the nearest pixel; sets pointsCameraMm and withDepth.
void liftFeatures(StereoFeatures& features, const cv::Mat& disparityPx, const RectifiedGeometry& geometry);
/// The same from the disparity already sampled at each keypoint (DisparitySampling.h; NaN = none), e.g. where the
/// map lies on the GPU. Throws Error unless there is one sample per keypoint.
void liftFeatures(StereoFeatures& features, const std::vector<float>& disparityAtKeypointsPx,
                  const RectifiedGeometry& geometry);
/// The keypoints' positions, in order: the points to sample a disparity at for liftFeatures.
std::vector<cv::Point2f> keypointPositions(const StereoFeatures& features);
/// The disparity (CV_32F, NaN = none) at each point by DisparitySampling.h's rule. Throws Error unless the map is
/// CV_32FC1 of `imageSize`.
std::vector<float> sampleDisparityMap(const cv::Mat& disparityPx, cv::Size imageSize,
                                      const std::vector<cv::Point2f>& pointsPx);

/// detectFeatures, then liftFeatures: detects features on the (grey or BGR, 8-bit) rectified left image and lifts each with the disparity
/// (CV_32F, NaN = none, same size) sampled bilinearly at the keypoint when its 4 neighbours have estimates, else at
/// the nearest pixel. Throws Error on empty or mismatched inputs.
StereoFeatures extractStereoFeatures(const FeatureDetector& detect, const cv::Mat& leftRectified,
                                     const cv::Mat& disparityPx, const RectifiedGeometry& geometry);
/// The same with OpenCV's ORB as the detector.
StereoFeatures extractStereoFeatures(cv::ORB& orb, const cv::Mat& leftRectified, const cv::Mat& disparityPx,
                                     const RectifiedGeometry& geometry);

}  // namespace tissuemosaic
