// ROS camera_info YAML (camera_calibration_parsers), one file per eye. The stereo calibrator's own rectification
// is kept: each eye's rectification_matrix R and projection_matrix P define the rectified pair, so frames rectified
// by ROS (image_rect) match the geometry exactly. P's Tx = -fx' * baseline is in metres (REP 103).
#include "IO/Calibration/CalibrationLayout.h"

#include "Core/Error.h"
#include "Core/ParameterError.h"

namespace tissuemosaic {
namespace {

constexpr double kMillimetresPerMetre = 1000.0;

struct RosCamera {
  cv::Mat K, D, R, P;
  cv::Size imageSize;
};

RosCamera readCamera(const CalibrationDocument& document, const std::string& eye) {
  const YAML::Node& root = document.root;
  const std::string where = eye + " eye ('" + document.path + "'): ";
  try {
    RosCamera camera;
    camera.K = readMatrix(root, "camera_matrix", 3, 3);
    camera.R = readMatrix(root, "rectification_matrix", 3, 3);
    camera.P = readMatrix(root, "projection_matrix", 3, 4);
    const std::string model = root["distortion_model"] ? readText(root, "distortion_model") : "plumb_bob";
    require(model == "plumb_bob" || model == "rational_polynomial",
            "distortion_model '" + model + "' is not supported (plumb_bob or rational_polynomial; fisheye / "
            "equidistant lenses are not)");
    camera.D = root["distortion_coefficients"] ? distortionRow(readMatrix(root["distortion_coefficients"],
                                                                          "distortion_coefficients"))
                                               : cv::Mat();
    if (camera.D.empty() || cv::countNonZero(camera.D) == 0) camera.D = cv::Mat::zeros(1, 5, CV_64F);
    camera.imageSize = optionalImageSize(root);
    return camera;
  } catch (const Error& e) {
    throw Error(where + e.what());
  }
}

}  // namespace

CalibrationLayout rosCameraInfoLayout() {
  CalibrationLayout layout;
  layout.name = "ROS camera_info (one file per eye)";
  layout.keys = "camera_matrix distortion_coefficients rectification_matrix projection_matrix image_width "
                "image_height, one file per eye: the left eye's and the right eye's";
  layout.matches = [](const CalibrationInput& input) {
    return hasKeys(input.main.root, {"camera_matrix", "projection_matrix"});
  };
  layout.read = [](const CalibrationInput& input) {
    requireParameter(input.right.has_value(), "rightCalibration",
                     "a ROS camera_info file describes one eye: give the right eye's file too");
    const RosCamera left = readCamera(input.main, "left");
    const RosCamera right = readCamera(*input.right, "right");
    require(left.imageSize == right.imageSize, "the left and right camera_info files give different image sizes");
    // ROS: the left (first) camera's P has Tx = 0, the right one's Tx = -fx' * baseline.
    const double leftTx = left.P.at<double>(0, 3), rightTx = right.P.at<double>(0, 3);
    require(leftTx == 0 && rightTx != 0,
            rightTx == 0 && leftTx != 0
                ? "the left and right camera_info files look swapped: the left eye's projection_matrix has Tx = 0"
                : "projection_matrix Tx must be 0 for the left eye and -fx * baseline for the right eye");
    require(right.P.at<double>(1, 3) == 0, "the camera_info files describe a vertical rig (P(1,3) != 0); only "
                                           "side-by-side rigs are supported");
    StereoCalibration c;
    c.K1 = left.K;
    c.D1 = left.D;
    c.K2 = right.K;
    c.D2 = right.D;
    c.imageSize = left.imageSize;
    c.rectification.R1 = left.R;
    c.rectification.R2 = right.R;
    c.rectification.P1 = left.P.clone();
    c.rectification.P2 = right.P.clone();
    c.rectification.P2.at<double>(0, 3) *= kMillimetresPerMetre;
    // X_right = R2^T (R1 X_left + t): the rectified right camera sits at -t in the rectified left frame.
    const cv::Mat t = (cv::Mat_<double>(3, 1) << c.rectification.P2.at<double>(0, 3) / right.P.at<double>(0, 0), 0, 0);
    c.R = right.R.t() * left.R;
    c.T = right.R.t() * t;
    return c;
  };
  return layout;
}

}  // namespace tissuemosaic
