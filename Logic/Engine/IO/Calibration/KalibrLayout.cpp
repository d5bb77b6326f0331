// Kalibr's camchain.yaml: cam0 (left) and cam1 (right), pinhole intrinsics [fu fv pu pv], radtan distortion
// [k1 k2 r1 r2] (OpenCV's k1 k2 p1 p2), resolution [w h], and cam1's T_cn_cnm1, the 4x4 transform taking cam0
// points into cam1, in metres.
#include "IO/Calibration/CalibrationLayout.h"

#include "Core/Error.h"

namespace tissuemosaic {
namespace {

constexpr double kMillimetresPerMetre = 1000.0;

void readCamera(const YAML::Node& camera, const std::string& name, cv::Mat& K, cv::Mat& D, cv::Size& size) {
  const std::string where = name + ": ";
  const std::string model = camera["camera_model"] ? camera["camera_model"].Scalar() : "pinhole";
  require(model == "pinhole", where + "camera_model '" + model + "' is not supported (pinhole only)");
  const cv::Mat intrinsics = readMatrix(camera, "intrinsics", 1, 4, where);
  K = (cv::Mat_<double>(3, 3) << intrinsics.at<double>(0), 0, intrinsics.at<double>(2), 0, intrinsics.at<double>(1),
       intrinsics.at<double>(3), 0, 0, 1);
  const std::string distortion = camera["distortion_model"] ? camera["distortion_model"].Scalar() : "none";
  if (distortion == "radtan") {
    D = readMatrix(camera, "distortion_coeffs", 1, 4, where);
  } else {
    require(distortion == "none", where + "distortion_model '" + distortion +
                                      "' is not supported (radtan or none; equidistant / fov lenses are not)");
    D = cv::Mat::zeros(1, 4, CV_64F);
  }
  const cv::Mat resolution = readMatrix(camera, "resolution", 1, 2, where);
  size = {imageSidePx(resolution.at<double>(0), "resolution"), imageSidePx(resolution.at<double>(1), "resolution")};
}

}  // namespace

CalibrationLayout kalibrLayout() {
  CalibrationLayout layout;
  layout.name = "Kalibr camchain.yaml";
  layout.keys = "cam0 and cam1, each with intrinsics distortion_model distortion_coeffs resolution; cam1.T_cn_cnm1";
  layout.matches = [](const CalibrationInput& input) {
    return hasKeys(input.main.root, {"cam0"}) && hasKeys(input.main.root["cam0"], {"intrinsics"}) && !input.right;
  };
  layout.read = [](const CalibrationInput& input) {
    const YAML::Node& root = input.main.root;
    const YAML::Node cam1 = requireKey(root, "cam1", "a stereo camchain needs a second camera: ");
    StereoCalibration c;
    cv::Size size1;
    readCamera(root["cam0"], "cam0", c.K1, c.D1, c.imageSize);
    readCamera(cam1, "cam1", c.K2, c.D2, size1);
    require(c.imageSize == size1, "cam0 and cam1 have different resolutions");
    const cv::Mat T_cam1_cam0 = readMatrix(cam1, "T_cn_cnm1", 4, 4, "cam1: ");
    c.R = T_cam1_cam0(cv::Rect(0, 0, 3, 3)).clone();
    c.T = T_cam1_cam0(cv::Rect(3, 0, 1, 3)) * kMillimetresPerMetre;
    return c;
  };
  return layout;
}

}  // namespace tissuemosaic
