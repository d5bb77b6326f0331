#include "StereoRig.h"

#include "Error.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

namespace tissuemosaic {
namespace {

std::string shapeText(const cv::Mat& m) {
  std::ostringstream text;
  text << m.rows << "x" << m.cols;
  if (m.channels() != 1) text << " with " << m.channels() << " channels";
  return text.str();
}

bool allFinite(const cv::Mat& m) { return cv::checkRange(m, true, nullptr, -1e300, 1e300); }

void validateCameraMatrix(const cv::Mat& K, const std::string& name) {
  require(K.rows == 3 && K.cols == 3 && K.channels() == 1, name + " must be a 3x3 camera matrix, not " + shapeText(K));
  require(K.type() == CV_64F, name + " must be CV_64F");
  require(allFinite(K), name + " holds NaN or infinite values");
  require(K.at<double>(0, 0) > 0 && K.at<double>(1, 1) > 0,
          name + " must have positive focal lengths fx, fy (K(0,0), K(1,1))");
  require(K.at<double>(1, 0) == 0 && K.at<double>(2, 0) == 0 && K.at<double>(2, 1) == 0 &&
              std::abs(K.at<double>(2, 2) - 1) < 1e-12,
          name + " is not a camera matrix: its last row must be [0 0 1] and K(1,0) must be 0");
}

void validateGivenRectification(const GivenRectification& given) {
  for (const auto& [m, name] : {std::pair{given.R1, "R1"}, {given.R2, "R2"}}) {
    require(m.rows == 3 && m.cols == 3 && m.type() == CV_64F && allFinite(m),
            std::string("the rectification rotation ") + name + " must be a finite 3x3 CV_64F matrix");
    require(cv::norm(m.t() * m, cv::Mat::eye(3, 3, CV_64F), cv::NORM_INF) < 1e-4 && cv::determinant(m) > 0,
            std::string("the rectification matrix ") + name + " is not a rotation");
  }
  for (const auto& [m, name] : {std::pair{given.P1, "P1"}, {given.P2, "P2"}}) {
    require(m.rows == 3 && m.cols == 4 && m.type() == CV_64F && allFinite(m),
            std::string("the rectified projection ") + name + " must be a finite 3x4 CV_64F matrix");
    require(m.at<double>(0, 0) > 0 && m.at<double>(2, 2) == 1,
            std::string("the rectified projection ") + name + " is not [f 0 cx Tx; 0 f cy 0; 0 0 1 0]");
  }
  require(given.P1.at<double>(0, 0) == given.P2.at<double>(0, 0) && given.P1.at<double>(1, 2) == given.P2.at<double>(1, 2),
          "the rectified projections P1 and P2 must share the focal length and cy");
  require(given.P1.at<double>(0, 3) == 0 && given.P2.at<double>(1, 3) == 0,
          "the rectified projections describe no side-by-side pair (P1 needs Tx = 0, P2 Ty = 0)");
}

void validateDistortion(const cv::Mat& D, const std::string& name) {
  int n = static_cast<int>(D.total());
  require(D.channels() == 1 && (D.rows == 1 || D.cols == 1) && (n == 4 || n == 5 || n == 8 || n == 12 || n == 14),
          name + " must be 1xN with N in 4, 5, 8, 12, 14 distortion coefficients, not " + shapeText(D));
  require(D.type() == CV_64F, name + " must be CV_64F");
  require(allFinite(D), name + " holds NaN or infinite values");
}

}  // namespace

void StereoCalibration::adoptFrameSize(const cv::Size& frameSize, const std::string& framesDescription) {
  if (imageSize.empty()) {
    imageSize = frameSize;
    return;
  }
  require(imageSize == frameSize, "the calibration is for " + std::to_string(imageSize.width) + "x" +
                                      std::to_string(imageSize.height) + " but the frames of " + framesDescription +
                                      " are " + std::to_string(frameSize.width) + "x" +
                                      std::to_string(frameSize.height));
}

void StereoCalibration::validate() const {
  validateCameraMatrix(K1, "K1");
  validateCameraMatrix(K2, "K2");
  validateDistortion(D1, "D1");
  validateDistortion(D2, "D2");
  require(R.rows == 3 && R.cols == 3 && R.channels() == 1, "R must be a 3x3 rotation, not " + shapeText(R));
  require(R.type() == CV_64F && allFinite(R), "R must be CV_64F with finite values");
  // Files written with few digits are slightly off; 1e-4 still rejects anything that is not a rotation.
  double orthogonalityError = cv::norm(R.t() * R, cv::Mat::eye(3, 3, CV_64F), cv::NORM_INF);
  require(orthogonalityError < 1e-4 && cv::determinant(R) > 0,
          "R is not a rotation matrix (R^T R must be the identity and det R = +1)");
  require(T.rows == 3 && T.cols == 1 && T.channels() == 1, "T must be a 3x1 translation, not " + shapeText(T));
  require(T.type() == CV_64F && allFinite(T), "T must be CV_64F with finite values");
  require(cv::norm(T) > 1e-9, "T is zero: the baseline between the cameras must be positive");
  require(imageSize.empty() || (imageSize.width > 0 && imageSize.height > 0), "the image size must be positive");
  if (!rectification.empty()) validateGivenRectification(rectification);
}

StereoRectifier::StereoRectifier(const StereoCalibration& calibration, RectificationMode mode)
    : calibration_(calibration) {
  calibration.validate();
  require(!calibration.imageSize.empty(),
          "the calibration file gives no image size: it is taken from the frames (open the frames first)");
  const GivenRectification& given = calibration.rectification;
  if (given.empty()) {
    int flags = mode == RectificationMode::ZeroDisparityAtInfinity ? cv::CALIB_ZERO_DISPARITY : 0;
    cv::stereoRectify(calibration.K1, calibration.D1, calibration.K2, calibration.D2, calibration.imageSize,
                      calibration.R, calibration.T, R1_, R2_, P1_, P2_, geometry_.Q, flags, 0.0,
                      calibration.imageSize);
  } else {  // the tool's own rectification; Q as cv::stereoRectify makes it (Tx = P2(0,3) / f = -baseline)
    R1_ = given.R1.clone();
    R2_ = given.R2.clone();
    P1_ = given.P1.clone();
    P2_ = given.P2.clone();
    const double f = P1_.at<double>(0, 0), tx = P2_.at<double>(0, 3) / f;
    const double cx1 = P1_.at<double>(0, 2), cx2 = P2_.at<double>(0, 2);
    geometry_.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -cx1, 0, 1, 0, -P1_.at<double>(1, 2), 0, 0, 0, f, 0, 0,
                   -1.0 / tx, (cx1 - cx2) / tx);
  }
  // stereoRectify makes a vertical pair when |T_y| > |T_x|; the matchers search along rows only.
  require(P2_.at<double>(1, 3) == 0,
          "the stereo calibration describes a vertical (top-bottom) rig; only side-by-side rigs are supported");
  const double focalPx = P1_.at<double>(0, 0);
  // P2 = [f 0 cx2 Tx*f; ...] with Tx the right camera's x in the rectified left frame: negative when it is right.
  const double baselineMm = -P2_.at<double>(0, 3) / P2_.at<double>(0, 0);
  require(baselineMm > 0,
          "the right camera lies to the left of the left camera: the left and right images (K1/K2, D1/D2) look "
          "swapped, or R and T do not map left-camera points into the right camera");
  geometry_.imageSize = calibration.imageSize;
  geometry_.focalPx = focalPx;
  geometry_.cxLeftPx = P1_.at<double>(0, 2);
  geometry_.cyPx = P1_.at<double>(1, 2);
  geometry_.doffsPx = P2_.at<double>(0, 2) - P1_.at<double>(0, 2);
  geometry_.baselineMm = baselineMm;
  // Fixed-point maps (CV_16SC2 + CV_16UC1): remap quantises float maps to 1/32 px anyway, and these are faster.
  cv::initUndistortRectifyMap(calibration.K1, calibration.D1, R1_, P1_, calibration.imageSize, CV_16SC2, leftMapX_,
                              leftMapY_);
  cv::initUndistortRectifyMap(calibration.K2, calibration.D2, R2_, P2_, calibration.imageSize, CV_16SC2, rightMapX_,
                              rightMapY_);
}

namespace {
std::vector<cv::Point2d> rectifyPoints(const std::vector<cv::Point2d>& pointsPx, const cv::Mat& K, const cv::Mat& D,
                                       const cv::Mat& R, const cv::Mat& P) {
  if (pointsPx.empty()) return {};
  std::vector<cv::Point2d> rectified;
  cv::undistortPoints(pointsPx, rectified, K, D, R, P,
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-14));
  return rectified;
}
}  // namespace

std::vector<cv::Point2d> StereoRectifier::rectifyLeftPoints(const std::vector<cv::Point2d>& pointsPx) const {
  return rectifyPoints(pointsPx, calibration_.K1, calibration_.D1, R1_, P1_);
}

std::vector<cv::Point2d> StereoRectifier::rectifyRightPoints(const std::vector<cv::Point2d>& pointsPx) const {
  return rectifyPoints(pointsPx, calibration_.K2, calibration_.D2, R2_, P2_);
}

void StereoRectifier::rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& leftRectified,
                              cv::Mat& rightRectified) const {
  const cv::Size expected = geometry_.imageSize;
  auto check = [&](const cv::Mat& image, const char* name) {
    require(!image.empty(), std::string("cannot rectify: the ") + name + " image is empty");
    require(image.size() == expected, std::string("cannot rectify: the ") + name + " image is " +
                                          std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                                          " but the calibration is for " + std::to_string(expected.width) + "x" +
                                          std::to_string(expected.height));
  };
  check(left, "left");
  check(right, "right");
  cv::remap(left, leftRectified, leftMapX_, leftMapY_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  cv::remap(right, rightRectified, rightMapX_, rightMapY_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

namespace {

/// Q * [x y d 1] divided by its w, as reconstructScene; false where there is no point in front of the camera.
struct Reprojector {
  double q[4][4];
  explicit Reprojector(const cv::Mat& Q) {
    require(Q.rows == 4 && Q.cols == 4 && Q.type() == CV_64F, "the rectified geometry has no 4x4 CV_64F Q matrix");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) q[r][c] = Q.at<double>(r, c);
  }
  bool operator()(double x, double y, double d, cv::Point3d& point) const {
    if (!std::isfinite(d)) return false;
    double h[4];
    for (int r = 0; r < 4; ++r) h[r] = q[r][0] * x + q[r][1] * y + q[r][2] * d + q[r][3];
    if (!(h[3] != 0)) return false;
    point = {h[0] / h[3], h[1] / h[3], h[2] / h[3]};
    return point.z > 0 && std::isfinite(point.z) && std::isfinite(point.x) && std::isfinite(point.y);
  }
  /// Only Z: the depth map needs two of Q's four rows.
  float depth(double x, double y, double d) const {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    if (!std::isfinite(d)) return nan;
    const double z = q[2][0] * x + q[2][1] * y + q[2][2] * d + q[2][3];
    const double w = q[3][0] * x + q[3][1] * y + q[3][2] * d + q[3][3];
    const double depthMm = z / w;
    return w != 0 && depthMm > 0 && std::isfinite(depthMm) ? static_cast<float>(depthMm) : nan;
  }
};

void checkDisparity(const cv::Mat& disparityPx, const RectifiedGeometry& geometry) {
  require(!disparityPx.empty() && disparityPx.type() == CV_32FC1, "the disparity map must be a non-empty CV_32FC1 image");
  require(disparityPx.size() == geometry.imageSize,
          "the disparity map is " + std::to_string(disparityPx.cols) + "x" + std::to_string(disparityPx.rows) +
              " but the rectified images are " + std::to_string(geometry.imageSize.width) + "x" +
              std::to_string(geometry.imageSize.height));
}

}  // namespace

cv::Mat disparityToDepthMm(const cv::Mat& disparityPx, const RectifiedGeometry& geometry) {
  checkDisparity(disparityPx, geometry);
  const Reprojector reproject(geometry.Q);
  cv::Mat depthMm(disparityPx.size(), CV_32FC1);
  cv::parallel_for_(cv::Range(0, disparityPx.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float* d = disparityPx.ptr<float>(y);
      float* z = depthMm.ptr<float>(y);
      for (int x = 0; x < disparityPx.cols; ++x) z[x] = reproject.depth(x, y, d[x]);
    }
  });
  return depthMm;
}

ColoredPointCloud disparityToPointCloud(const cv::Mat& disparityPx, const cv::Mat& leftRectified,
                                        const RectifiedGeometry& geometry) {
  checkDisparity(disparityPx, geometry);
  require(leftRectified.size() == disparityPx.size(),
          "the rectified left image and the disparity map must have the same size");
  require(leftRectified.depth() == CV_8U &&
              (leftRectified.channels() == 1 || leftRectified.channels() == 3 || leftRectified.channels() == 4),
          "the rectified left image must be 8-bit grey, BGR or BGRA");
  const Reprojector reproject(geometry.Q);
  const int channels = leftRectified.channels();
  ColoredPointCloud cloud;
  const std::size_t estimate = static_cast<std::size_t>(cv::countNonZero(disparityPx == disparityPx));  // non-NaN
  cloud.pointsMm.reserve(estimate);
  cloud.colorsRgb.reserve(estimate);
  for (int y = 0; y < disparityPx.rows; ++y) {
    const float* d = disparityPx.ptr<float>(y);
    const uchar* pixel = leftRectified.ptr<uchar>(y);
    for (int x = 0; x < disparityPx.cols; ++x) {
      cv::Point3d point;
      if (!reproject(x, y, d[x], point)) continue;
      cloud.pointsMm.emplace_back(static_cast<float>(point.x), static_cast<float>(point.y),
                                  static_cast<float>(point.z));
      const uchar* c = pixel + x * channels;
      cloud.colorsRgb.push_back(channels == 1 ? cv::Vec3b(c[0], c[0], c[0]) : cv::Vec3b(c[2], c[1], c[0]));
    }
  }
  return cloud;
}

}  // namespace tissuemosaic
