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

cv::Mat toGrey8(const cv::Mat& image, const std::string& what) {
  require(!image.empty(), what + " is empty");
  require(image.depth() == CV_8U && (image.channels() == 1 || image.channels() == 3 || image.channels() == 4),
          what + " must be 8-bit grey, BGR or BGRA");
  if (image.channels() == 1) return image.isContinuous() ? image : image.clone();
  cv::Mat grey;  // cv::Mat::create allocates continuous memory
  cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return grey;
}

}  // namespace tissuemosaic
