// MATLAB's Stereo Camera Calibrator: a stereoParameters object exported with its documented fields (for instance
// jsonencode(toStruct(stereoParams))). MATLAB differs from OpenCV in three ways, undone here:
// - pixel centres are 1-based: the principal point is 1 more than OpenCV's;
// - IntrinsicMatrix is the transpose of OpenCV's K ([fx 0 0; s fy 0; cx cy 1]); K (R2022b on) is not transposed;
// - RotationOfCamera2 / TranslationOfCamera2 post-multiply row vectors (x2 = x1 * R + t), so OpenCV's R is its
//   transpose; PoseCamera2 (R2022b on) is the pose of camera 2 in camera 1 (x1 = R x2 + Translation).
// ImageSize is [rows, columns]; WorldUnits (default mm) gives the unit of the translation.
#include "IO/Calibration/CalibrationLayout.h"

#include "Core/Error.h"

#include <map>

namespace tissuemosaic {
namespace {

double millimetresPerUnit(const std::string& units) {
  static const std::map<std::string, double> scale = {
      {"mm", 1.0}, {"millimeters", 1.0}, {"millimetres", 1.0}, {"cm", 10.0}, {"centimeters", 10.0},
      {"m", 1000.0}, {"meters", 1000.0}, {"metres", 1000.0}, {"in", 25.4}, {"inches", 25.4}};
  const auto found = scale.find(units);
  require(found != scale.end(), "WorldUnits '" + units + "' is not known (mm, cm, m or in)");
  return found->second;
}

/// One camera's K (OpenCV form, 0-based principal point), D (k1 k2 p1 p2 [k3]) and image size.
void readCamera(const YAML::Node& camera, const std::string& name, cv::Mat& K, cv::Mat& D, cv::Size& size) {
  const std::string where = name + ": ";
  if (camera["K"]) {
    K = readMatrix(camera, "K", 3, 3, where);
  } else if (camera["IntrinsicMatrix"]) {
    K = readMatrix(camera, "IntrinsicMatrix", 3, 3, where).t();
  } else {
    const cv::Mat focal = readMatrix(camera, "FocalLength", 1, 2, where + "K, IntrinsicMatrix or FocalLength: ");
    const cv::Mat centre = readMatrix(camera, "PrincipalPoint", 1, 2, where);
    K = (cv::Mat_<double>(3, 3) << focal.at<double>(0), 0, centre.at<double>(0), 0, focal.at<double>(1),
         centre.at<double>(1), 0, 0, 1);
  }
  require(K.at<double>(0, 1) == 0, where + "the intrinsics have a skew, which OpenCV's camera model (and "
                                           "MATLAB's stereoParametersToOpenCV) cannot represent");
  K.at<double>(0, 2) -= 1.0;
  K.at<double>(1, 2) -= 1.0;
  cv::Mat radial = camera["RadialDistortion"] ? readMatrix(camera["RadialDistortion"], "RadialDistortion")
                                              : cv::Mat::zeros(1, 2, CV_64F);
  cv::Mat tangential = camera["TangentialDistortion"]
                           ? readMatrix(camera["TangentialDistortion"], "TangentialDistortion")
                           : cv::Mat::zeros(1, 2, CV_64F);
  require(radial.total() == 2 || radial.total() == 3, where + "RadialDistortion must hold 2 or 3 values");
  require(tangential.total() == 2, where + "TangentialDistortion must hold 2 values");
  radial = radial.reshape(1, 1);
  tangential = tangential.reshape(1, 1);
  D = (cv::Mat_<double>(1, 5) << radial.at<double>(0), radial.at<double>(1), tangential.at<double>(0),
       tangential.at<double>(1), radial.total() == 3 ? radial.at<double>(2) : 0.0);
  size = {};
  if (camera["ImageSize"]) {
    const cv::Mat rowsColumns = readMatrix(camera, "ImageSize", 1, 2, where);
    size = {imageSidePx(rowsColumns.at<double>(1), "ImageSize"), imageSidePx(rowsColumns.at<double>(0), "ImageSize")};
  }
}

}  // namespace

CalibrationLayout matlabStereoParametersLayout() {
  CalibrationLayout layout;
  layout.name = "MATLAB stereoParameters (Stereo Camera Calibrator)";
  layout.keys = "CameraParameters1 CameraParameters2 (K or IntrinsicMatrix, RadialDistortion, TangentialDistortion, "
                "ImageSize), RotationOfCamera2 + TranslationOfCamera2 or PoseCamera2, WorldUnits";
  layout.matches = [](const CalibrationInput& input) {
    return hasKeys(input.main.root, {"CameraParameters1"}) && !input.right;
  };
  layout.read = [](const CalibrationInput& input) {
    const YAML::Node& root = input.main.root;
    const YAML::Node camera1 = requireKey(root, "CameraParameters1");
    const YAML::Node camera2 = requireKey(root, "CameraParameters2");
    StereoCalibration c;
    cv::Size size2;
    readCamera(camera1, "CameraParameters1", c.K1, c.D1, c.imageSize);
    readCamera(camera2, "CameraParameters2", c.K2, c.D2, size2);
    require(c.imageSize == size2, "CameraParameters1 and CameraParameters2 have different ImageSize");
    std::string units = "mm";
    if (root["WorldUnits"]) units = readText(root, "WorldUnits");
    else if (camera1["WorldUnits"]) units = readText(camera1, "WorldUnits");
    const double scale = millimetresPerUnit(units);
    if (root["RotationOfCamera2"]) {
      c.R = readMatrix(root, "RotationOfCamera2", 3, 3).t();
      c.T = readMatrix(root, "TranslationOfCamera2", 1, 3).t() * scale;
    } else {
      const YAML::Node pose = requireKey(root, "PoseCamera2", "RotationOfCamera2 or ");
      const cv::Mat R_1_2 = readMatrix(pose, "R", 3, 3, "PoseCamera2: ");
      const cv::Mat t_1_2 = readMatrix(pose, "Translation", 1, 3, "PoseCamera2: ").t() * scale;
      c.R = R_1_2.t();
      c.T = -R_1_2.t() * t_1_2;
    }
    return c;
  };
  return layout;
}

}  // namespace tissuemosaic
