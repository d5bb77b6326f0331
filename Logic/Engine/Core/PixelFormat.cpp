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

}  // namespace tissuemosaic
