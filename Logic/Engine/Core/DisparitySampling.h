#pragma once
/// @file DisparitySampling.h
/// @brief The disparity at a sub-pixel position of the left image, the one rule by which features are lifted to 3D:
/// bilinear where the 4 neighbours are estimates, else the nearest pixel's (NaN there: none). Host and device
/// (StereoMatcher::sampleLastDisparityAwayFromHighlights on CUDA) compute the same float. In Core because stereo
/// (which samples its map) and tracking (which lifts its features) both follow it.
#include "Core/Float3.h"
#include "Core/HostDevice.h"
#include "Core/Image.h"

#include <cmath>

namespace tissuemosaic {

TM_HOST_DEVICE inline float sampleDisparityPx(ImageView<const float> disparityPx, float x, float y) {
  const int x0 = static_cast<int>(floorf(x)), y0 = static_cast<int>(floorf(y));
  if (x0 >= 0 && y0 >= 0 && x0 + 1 < disparityPx.width && y0 + 1 < disparityPx.height) {
    const float a = x - x0, b = y - y0;
    const float d00 = disparityPx.at(x0, y0), d01 = disparityPx.at(x0 + 1, y0);
    const float d10 = disparityPx.at(x0, y0 + 1), d11 = disparityPx.at(x0 + 1, y0 + 1);
    const float d = (d00 * (1 - a) + d01 * a) * (1 - b) + (d10 * (1 - a) + d11 * a) * b;
    if (isFinite(d)) return d;
  }
  const int xn = static_cast<int>(rintf(x)), yn = static_cast<int>(rintf(y));  // halves to even, as cvRound
  if (!disparityPx.contains(xn, yn)) return NAN;
  return disparityPx.at(xn, yn);
}

}  // namespace tissuemosaic
