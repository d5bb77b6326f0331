// cv::stereoCalibrate's names, as TissueMosaic writes them (writeStereoCalibration) and most OpenCV scripts do.
#include "IO/Calibration/CalibrationLayout.h"

#include "Core/Error.h"

#include <cmath>

namespace tissuemosaic {

cv::Mat distortionRow(const cv::Mat& D) { return D.cols == 1 ? cv::Mat(D.t()) : D; }

cv::Mat translationColumn(const cv::Mat& T, const std::string& key) {
  require(T.total() == 3, key + " must be a 3x1 translation, not " + std::to_string(T.rows) + "x" +
                              std::to_string(T.cols));
  return T.reshape(1, 3).clone();
}

int imageSidePx(double value, const std::string& key) {
  constexpr double kLargestSidePx = 100000;
  require(value == std::floor(value) && value > 0 && value <= kLargestSidePx,
          "key '" + key + "' must hold positive whole pixels (at most 100000)");
  return static_cast<int>(value);
}

cv::Size optionalImageSize(const YAML::Node& node) {
  if (node["imageSize"]) {
    const cv::Mat size = readMatrix(node["imageSize"], "imageSize");
    require(size.total() == 2, "key 'imageSize' must be [width, height]");
    return {imageSidePx(size.at<double>(0), "imageSize"), imageSidePx(size.at<double>(1), "imageSize")};
  }
  if (node["image_width"] || node["image_height"]) {
    return {imageSidePx(readNumber(node, "image_width"), "image_width"),
            imageSidePx(readNumber(node, "image_height"), "image_height")};
  }
  return {};
}

CalibrationLayout openCvStereoCalibrateLayout() {
  CalibrationLayout layout;
  layout.name = "OpenCV stereoCalibrate";
  layout.keys = "K1 D1 K2 D2 R T, optional imageSize [w, h] or image_width + image_height";
  layout.matches = [](const CalibrationInput& input) { return hasKeys(input.main.root, {"K1"}) && !input.right; };
  layout.read = [](const CalibrationInput& input) {
    const YAML::Node& root = input.main.root;
    StereoCalibration c;
    c.K1 = readMatrix(requireKey(root, "K1"), "K1");
    c.D1 = distortionRow(readMatrix(requireKey(root, "D1"), "D1"));
    c.K2 = readMatrix(requireKey(root, "K2"), "K2");
    c.D2 = distortionRow(readMatrix(requireKey(root, "D2"), "D2"));
    c.R = readMatrix(requireKey(root, "R"), "R");
    c.T = readMatrix(requireKey(root, "T"), "T");
    if (c.T.total() == 3) c.T = translationColumn(c.T, "T");
    c.imageSize = optionalImageSize(root);
    return c;
  };
  return layout;
}

}  // namespace tissuemosaic
