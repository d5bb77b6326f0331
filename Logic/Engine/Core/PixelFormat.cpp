#include "Core/PixelFormat.h"

#include "Core/Error.h"

#include <opencv2/imgproc.hpp>

namespace tissuemosaic {

cv::Mat toBgr8(const cv::Mat& image, const std::string& what) {
  if (image.type() == CV_8UC3) return image;
  require(image.depth() == CV_8U && (image.channels() == 1 || image.channels() == 4),
          what + " must be 8-bit grey, BGR or BGRA");
  cv::Mat bgr;
  cv::cvtColor(image, bgr, image.channels() == 4 ? cv::COLOR_BGRA2BGR : cv::COLOR_GRAY2BGR);
  return bgr;
}

void requireGrey8Convertible(const cv::Mat& image, const std::string& what) {
  require(!image.empty(), what + " is empty");
  require(image.depth() == CV_8U && (image.channels() == 1 || image.channels() == 3 || image.channels() == 4),
          what + " must be 8-bit grey, BGR or BGRA");
}

cv::Mat toGrey8(const cv::Mat& image, const std::string& what) {
  requireGrey8Convertible(image, what);
  if (image.channels() == 1 && image.isContinuous()) return image;
  cv::Mat grey;  // cv::Mat::create allocates continuous memory
  convertToGrey8(image, grey, what);
  return grey;
}

void convertToGrey8(const cv::Mat& image, cv::Mat& grey, const std::string& what) {
  requireGrey8Convertible(image, what);
  if (image.channels() == 1) image.copyTo(grey);
  else cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
}

}  // namespace tissuemosaic
