#pragma once
/// @file StereoRig.h
/// @brief The calibrated stereo scope: calibration files, rectification, and disparity to depth and to a
/// coloured point cloud (equivalent to MATLAB's reconstructScene). Units: millimetres and pixels.
#include "Core/PinholeIntrinsics.h"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace tissuemosaic {

/// The rectification a calibration tool defined itself (ROS camera_info: each eye's R and P), kept so that frames
/// rectified by that tool match exactly. Empty (the usual case): StereoRectifier computes it with cv::stereoRectify.
struct GivenRectification {
  cv::Mat R1, R2;  ///< CV_64F 3x3: unrectified to rectified left (right) camera frame
  cv::Mat P1, P2;  ///< CV_64F 3x4 rectified projections in the rectified left frame, P2's translation in mm
  bool empty() const { return P1.empty(); }
};

/// What cv::stereoCalibrate produces, plus the image size: K1 D1 (left), K2 D2 (right), and R, T taking points
/// from the left camera frame to the right camera frame (X_right = R * X_left + T), T in millimetres.
struct StereoCalibration {
  cv::Mat K1, D1, K2, D2, R, T;  ///< CV_64F: 3x3, 1xN (N in 4,5,8,12,14), 3x3, 1xN, 3x3, 3x1
  cv::Size imageSize;            ///< width x height in pixels of the unrectified images; empty: not in the file
  GivenRectification rectification;

  // Files: IO/Calibration/CalibrationFile.h reads every layout (readStereoCalibration, readCalibrationFiles) and
  // writes cv::stereoCalibrate's (writeStereoCalibration).
  /// Throws Error when a matrix has the wrong shape, K is not a camera matrix, R is not a rotation, etc. An empty
  /// image size passes (the frames give it); a negative one does not.
  void validate() const;
  /// The frames' size when the file gave none; Error "the calibration is for WxH but the frames of WHAT are WxH"
  /// when it gave another.
  void adoptFrameSize(const cv::Size& frameSize, const std::string& framesDescription);
};

/// The rectified pair's geometry: both rectified cameras share focalPx and cy; doffsPx = cx_right - cx_left.
struct RectifiedGeometry {
  cv::Size imageSize;
  double focalPx = 0;
  double cxLeftPx = 0, cyPx = 0;
  double doffsPx = 0;
  double baselineMm = 0;
  cv::Mat Q;  ///< 4x4 reprojection matrix of cv::stereoRectify (disparity to 3D in the left rectified frame)

  /// Depth in mm of a left-view disparity: focalPx * baselineMm / (d + doffsPx).
  double depthMm(double disparityPx) const { return focalPx * baselineMm / (disparityPx + doffsPx); }
  /// The rectified left camera.
  PinholeIntrinsics leftIntrinsics() const { return {focalPx, focalPx, cxLeftPx, cyPx}; }
};

/// Where the rectified principal points go. ZeroDisparityAtInfinity (cv::CALIB_ZERO_DISPARITY, OpenCV's default,
/// the default here) gives both rectified cameras the same cx, so doffsPx is 0 and a point at infinity has
/// disparity 0. KeepPrincipalPoints lets cx differ (Middlebury style): doffsPx = cx_right - cx_left, and a point at
/// infinity has disparity -doffsPx. Depth, Q and point clouds are consistent in both modes.
enum class RectificationMode { ZeroDisparityAtInfinity, KeepPrincipalPoints };

/// Undistorts and rectifies unrectified left/right images (cv::stereoRectify with alpha 0, or the calibration's
/// given rectification, then remap). The rectified images have the calibration's image size, which must be known
/// (Error otherwise: see StereoCalibration::adoptFrameSize). Only side-by-side rigs with the right camera to the
/// right of the left one are accepted (Error otherwise: swapped or vertical rigs).
class StereoRectifier {
public:
  explicit StereoRectifier(const StereoCalibration& calibration,
                           RectificationMode mode = RectificationMode::ZeroDisparityAtInfinity);
  const RectifiedGeometry& geometry() const { return geometry_; }
  /// R1: rotation from the unrectified to the rectified left camera frame.
  const cv::Mat& leftRectificationRotation() const { return R1_; }
  /// R2: rotation from the unrectified to the rectified right camera frame.
  const cv::Mat& rightRectificationRotation() const { return R2_; }
  /// P1, P2: 3x4 projection matrices of the rectified cameras, both in the rectified left frame (cv::stereoRectify).
  const cv::Mat& leftProjection() const { return P1_; }
  const cv::Mat& rightProjection() const { return P2_; }
  /// Rectified pixel coordinates of unrectified left (or right) image points: undistortion iterated to
  /// convergence, then rectification. For sparse features and tests; images go through rectify().
  std::vector<cv::Point2d> rectifyLeftPoints(const std::vector<cv::Point2d>& pointsPx) const;
  std::vector<cv::Point2d> rectifyRightPoints(const std::vector<cv::Point2d>& pointsPx) const;
  /// Any image type cv::remap takes (bilinear, black border). Throws Error when an image is empty or its size
  /// differs from the calibration's.
  void rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& leftRectified, cv::Mat& rightRectified) const;

private:
  RectifiedGeometry geometry_;
  StereoCalibration calibration_;
  // Maps in cv::remap's fixed-point form: MapX is CV_16SC2 (whole pixels), MapY CV_16UC1 (1/32 px fractions).
  cv::Mat R1_, R2_, P1_, P2_, leftMapX_, leftMapY_, rightMapX_, rightMapY_;
};

/// Per-pixel depth (mm, CV_32F) from a left-view disparity map (CV_32F, NaN = no estimate), the Z of
/// Q * [x y d 1]: focalPx * baselineMm / (d + doffsPx). NaN or infinite disparities give NaN, and so does any
/// disparity that puts the point at or behind the camera (d + doffsPx <= 0). Throws Error for a non-CV_32FC1 map
/// or one whose size differs from geometry.imageSize.
cv::Mat disparityToDepthMm(const cv::Mat& disparityPx, const RectifiedGeometry& geometry);

struct ColoredPointCloud {
  std::vector<cv::Point3f> pointsMm;     ///< in the left rectified camera frame (x right, y down, z forward)
  std::vector<cv::Vec3b> colorsRgb;      ///< red, green, blue: empty (no colour) or one per point
  std::vector<cv::Point3f> normals;      ///< optional: empty or one per point (unit length)
  std::size_t size() const { return pointsMm.size(); }
};

/// Every pixel with a disparity estimate as a 3D point coloured from the rectified left image (8-bit BGR, BGRA
/// or grey, same size as the disparity), as MATLAB's reconstructScene: point = Q * [x y d 1] (x, y 0-based
/// pixel centres), in millimetres in the rectified left camera frame. Pixels skipped as by disparityToDepthMm;
/// points are in row-major pixel order. No normals.
ColoredPointCloud disparityToPointCloud(const cv::Mat& disparityPx, const cv::Mat& leftRectified,
                                        const RectifiedGeometry& geometry);

}  // namespace tissuemosaic
