// Loading the Middlebury v2 scenes (kept apart: it is the only test utility that needs OpenCV's image codecs).
#include "StereoTestUtilities.h"

#include <opencv2/imgcodecs.hpp>

#include <cstdlib>
#include <fstream>

namespace tissuemosaic::test {

std::string middleburyDirectory() {
  const char* overridden = std::getenv("TM_MIDDLEBURY_DIR");
  return overridden && *overridden ? overridden : TM_MIDDLEBURY_DIR;
}

bool testDataRequired() {
  const char* required = std::getenv("TM_REQUIRE_TEST_DATA");
  return required && std::string(required) == "1";
}

bool loadMiddlebury(const std::string& name, MiddleburyScene& scene) {
  const std::string directory = middleburyDirectory() + "/" + name + "/";
  scene.left = cv::imread(directory + "imL.png", cv::IMREAD_COLOR);
  scene.right = cv::imread(directory + "imR.png", cv::IMREAD_COLOR);
  const cv::Mat truth = cv::imread(directory + "groundtruth.png", cv::IMREAD_GRAYSCALE);
  scene.nonOccluded = cv::imread(directory + "nonocc.png", cv::IMREAD_GRAYSCALE);
  if (scene.left.empty() || scene.right.empty() || truth.empty() || scene.nonOccluded.empty()) return false;
  std::ifstream info(directory + "info.txt");
  double scale = 4;
  info >> scale >> scene.maxDisparity;
  truth.convertTo(scene.groundTruth, CV_32F, 1.0 / scale);
  scene.groundTruth.setTo(NAN, truth == 0);
  return true;
}

}  // namespace tissuemosaic::test
