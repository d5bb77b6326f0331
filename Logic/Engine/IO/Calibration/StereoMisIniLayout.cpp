// StereoMIS (Hayoz et al. 2023, da Vinci Xi sequences): StereoCalibration.ini, one [StereoLeft] and one [StereoRight]
// section, each with fc_x fc_y cc_x cc_y (pixels), kc_0..kc_4 (OpenCV's k1 k2 p1 p2 k3) and res_x res_y; the
// extrinsics R_0..R_8 (row-major) and T_0..T_2 (mm), taken from whichever section holds them, the right section
// first, as cv::stereoCalibrate's R and T (left camera to right camera).
#include "IO/Calibration/CalibrationLayout.h"

#include "Core/Error.h"

namespace tissuemosaic {
namespace {

double iniNumber(const YAML::Node& section, const std::string& sectionName, const std::string& key) {
  if (!section.IsMap() || !section[key]) throw Error("key '" + key + "' is missing from [" + sectionName + "]");
  return readNumber(section, key);
}

/// The section among [StereoRight], [StereoLeft] that holds `key`; Error when neither does.
YAML::Node sectionWith(const YAML::Node& root, const std::string& key, std::string& name) {
  for (const char* candidate : {"StereoRight", "StereoLeft"}) {
    if (root[candidate][key]) {
      name = candidate;
      return root[candidate];
    }
  }
  throw Error("key '" + key + "' is in neither [StereoRight] nor [StereoLeft]");
}

}  // namespace

CalibrationLayout stereoMisIniLayout() {
  CalibrationLayout layout;
  layout.name = "StereoMIS StereoCalibration.ini";
  layout.keys = "[StereoLeft] and [StereoRight] with fc_x fc_y cc_x cc_y kc_0..kc_4 res_x res_y; R_0..R_8 T_0..T_2";
  layout.matches = [](const CalibrationInput& input) {
    return hasKeys(input.main.root, {"StereoLeft", "StereoRight"}) && !input.right;
  };
  layout.read = [](const CalibrationInput& input) {
    const YAML::Node& root = input.main.root;
    StereoCalibration c;
    cv::Size sizes[2];
    int eye = 0;
    for (const char* name : {"StereoLeft", "StereoRight"}) {
      const YAML::Node section = root[name];
      const cv::Mat K = (cv::Mat_<double>(3, 3) << iniNumber(section, name, "fc_x"), 0, iniNumber(section, name, "cc_x"),
                         0, iniNumber(section, name, "fc_y"), iniNumber(section, name, "cc_y"), 0, 0, 1);
      cv::Mat D(1, 5, CV_64F);
      for (int i = 0; i < 5; ++i) D.at<double>(i) = iniNumber(section, name, "kc_" + std::to_string(i));
      (eye == 0 ? c.K1 : c.K2) = K;
      (eye == 0 ? c.D1 : c.D2) = D;
      sizes[eye] = cv::Size(imageSidePx(iniNumber(section, name, "res_x"), std::string(name) + ".res_x"),
                            imageSidePx(iniNumber(section, name, "res_y"), std::string(name) + ".res_y"));
      ++eye;
    }
    require(sizes[0] == sizes[1], "[StereoLeft] and [StereoRight] give different image sizes (res_x, res_y)");
    c.imageSize = sizes[0];
    std::string rName, tName;
    const YAML::Node rSection = sectionWith(root, "R_0", rName);
    const YAML::Node tSection = sectionWith(root, "T_0", tName);
    c.R = cv::Mat(3, 3, CV_64F);
    for (int i = 0; i < 9; ++i) c.R.at<double>(i) = iniNumber(rSection, rName, "R_" + std::to_string(i));
    c.T = cv::Mat(3, 1, CV_64F);
    for (int i = 0; i < 3; ++i) c.T.at<double>(i) = iniNumber(tSection, tName, "T_" + std::to_string(i));
    return c;
  };
  return layout;
}

}  // namespace tissuemosaic
