#include "Core/PixelFormat.h"

#include "Core/Error.h"
#include "Core/ParallelFor.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>

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

cv::Mat toGrey8(const cv::Mat& image, const std::string& what, ChannelOrder order) {
  requireGrey8Convertible(image, what);
  if (image.channels() == 1 && image.isContinuous()) return image;
  cv::Mat grey;  // cv::Mat::create allocates continuous memory
  convertToGrey8(image, grey, what, 1, order);
  return grey;
}

cv::Mat toContinuousBgr8(const cv::Mat& image, const std::string& what, ChannelOrder order) {
  if (image.type() == CV_8UC3 && order == ChannelOrder::Rgb) {
    cv::Mat bgr;
    cv::cvtColor(image, bgr, cv::COLOR_RGB2BGR);
    return bgr;
  }
  // A 4-channel image loses its alpha in either order; the remaining channels are swapped for RGBA.
  if (image.type() == CV_8UC4 && order == ChannelOrder::Rgb) {
    cv::Mat bgr;
    cv::cvtColor(image, bgr, cv::COLOR_RGBA2BGR);
    return bgr;
  }
  const cv::Mat bgr = toBgr8(image, what);
  return bgr.isContinuous() ? bgr : bgr.clone();
}

void convertToGrey8(const cv::Mat& image, cv::Mat& grey, const std::string& what, int bands, ChannelOrder order) {
  requireGrey8Convertible(image, what);
  grey.create(image.size(), CV_8UC1);  // keeps memory of that size and type: each band writes its rows in place
  const auto convertRows = [&](int first, int end) {
    const cv::Mat from = image.rowRange(first, end);
    cv::Mat to = grey.rowRange(first, end);
    if (image.channels() == 1) from.copyTo(to);
    else if (order == ChannelOrder::Rgb) cv::cvtColor(from, to, image.channels() == 4 ? cv::COLOR_RGBA2GRAY : cv::COLOR_RGB2GRAY);
    else cv::cvtColor(from, to, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  };
  bands = std::clamp(bands, 1, image.rows);
  if (bands == 1) return convertRows(0, image.rows);
  parallelFor<CpuBackend>(bands, [&](int64_t band) {
    convertRows(static_cast<int>(band * image.rows / bands), static_cast<int>((band + 1) * image.rows / bands));
  }, 1);
}

}  // namespace tissuemosaic
