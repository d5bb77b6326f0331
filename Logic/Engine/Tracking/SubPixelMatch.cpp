#include "Tracking/SubPixelMatch.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

namespace tissuemosaic {

bool refineMatchLucasKanade(const cv::Mat& referenceGrey, const cv::Mat& grey, const cv::Point2f& fromPx,
                            cv::Point2f& toPx, int halfWindowPx, double maxShiftPx) {
  const int n = 2 * halfWindowPx + 1;
  const float margin = static_cast<float>(halfWindowPx + 2 + maxShiftPx);
  const auto inside = [&](const cv::Mat& image, const cv::Point2f& p) {
    return p.x >= margin && p.y >= margin && p.x < image.cols - margin && p.y < image.rows - margin;
  };
  if (!inside(referenceGrey, fromPx) || !inside(grey, toPx)) return false;
  // Template with a one-pixel border for its central-difference gradients.
  cv::Mat templ;
  cv::getRectSubPix(referenceGrey, cv::Size(n + 2, n + 2), fromPx, templ, CV_32F);
  cv::Mat gx(n, n, CV_32F), gy(n, n, CV_32F);
  double hxx = 0, hxy = 0, hyy = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const float dx = 0.5f * (templ.at<float>(y + 1, x + 2) - templ.at<float>(y + 1, x));
      const float dy = 0.5f * (templ.at<float>(y + 2, x + 1) - templ.at<float>(y, x + 1));
      gx.at<float>(y, x) = dx;
      gy.at<float>(y, x) = dy;
      hxx += dx * dx;
      hxy += dx * dy;
      hyy += dy * dy;
    }
  }
  const double det = hxx * hyy - hxy * hxy;
  // Both gradient directions must be present (a corner-like window), else the shift along an edge is free.
  const double trace = hxx + hyy;
  if (!(det > 1e-3 * trace * trace) || trace < n * n * 4.0) return false;
  const cv::Mat centre = templ(cv::Rect(1, 1, n, n));
  cv::Point2f p = toPx;
  cv::Mat warped;
  bool converged = false;
  for (int iteration = 0; iteration < 10; ++iteration) {
    cv::getRectSubPix(grey, cv::Size(n, n), p, warped, CV_32F);
    double bx = 0, by = 0;
    for (int y = 0; y < n; ++y) {
      const float* w = warped.ptr<float>(y);
      const float* t = centre.ptr<float>(y);
      const float* ix = gx.ptr<float>(y);
      const float* iy = gy.ptr<float>(y);
      for (int x = 0; x < n; ++x) {
        const float e = w[x] - t[x];
        bx += ix[x] * e;
        by += iy[x] * e;
      }
    }
    const double dx = (hyy * bx - hxy * by) / det, dy = (hxx * by - hxy * bx) / det;
    p.x -= static_cast<float>(dx);
    p.y -= static_cast<float>(dy);
    if (!inside(grey, p) || std::hypot(p.x - toPx.x, p.y - toPx.y) > maxShiftPx) return false;
    if (dx * dx + dy * dy < 1e-4) {
      converged = true;
      break;
    }
  }
  if (!converged) return false;
  toPx = p;
  return true;
}

}  // namespace tissuemosaic
