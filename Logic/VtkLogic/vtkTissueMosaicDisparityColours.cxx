#include "vtkTissueMosaicDisparityColours.h"

#include "Core/StereoRig.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuemosaic {

void colourDisparity(const cv::Mat& disparityPx, double fallbackLowPx, double fallbackHighPx,
                     DisparityColouring& colouring) {
  colouring.valid = false;
  if (disparityPx.empty()) {
    colouring.bgr.release();
    return;
  }
  // NaN compares unequal to itself.
  const cv::Mat valid = disparityPx == disparityPx;
  double low = fallbackLowPx, high = fallbackHighPx;
  if (cv::countNonZero(valid) > 0) {
    cv::minMaxLoc(disparityPx, &low, &high, nullptr, nullptr, valid);
    colouring.valid = true;
  }
  colouring.lowPx = low;
  colouring.highPx = high;
  const double scale = 255.0 / std::max(high - low, 1.0);
  cv::Mat scaled;
  disparityPx.convertTo(scaled, CV_8U, scale, -low * scale);
  cv::applyColorMap(scaled, colouring.bgr, cv::COLORMAP_TURBO);
  colouring.bgr.setTo(cv::Scalar::all(0), ~valid);
}

cv::Vec3b disparityColour(const DisparityColouring& colouring, double disparityPx) {
  // The colour map's 256 entries, made once (applyColorMap builds its table at every call).
  static const cv::Mat table = [] {
    cv::Mat ramp(1, 256, CV_8U), colours;
    for (int i = 0; i < 256; ++i) ramp.at<uchar>(0, i) = static_cast<uchar>(i);
    cv::applyColorMap(ramp, colours, cv::COLORMAP_TURBO);
    return colours;
  }();
  const double scale = 255.0 / std::max(colouring.highPx - colouring.lowPx, 1.0);
  const int index = static_cast<int>(std::lround(std::clamp((disparityPx - colouring.lowPx) * scale, 0.0, 255.0)));
  return table.at<cv::Vec3b>(0, index);
}

double depthOfDisparityMm(const RectifiedGeometry& geometry, double disparityPx) {
  if (disparityPx + geometry.doffsPx <= 0) return std::numeric_limits<double>::infinity();
  return geometry.depthMm(disparityPx);
}

}  // namespace tissuemosaic
