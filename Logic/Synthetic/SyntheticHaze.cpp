#include "SyntheticHaze.h"

#include "Core/Error.h"
#include "SyntheticRandom.h"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>

namespace tissuemosaic::synthetic {

namespace {

/// Value noise: hashed lattice values in [0, 1], interpolated with a smoothstep (continuous slope).
double valueNoise(double x, double y, uint64_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto corner = [&](double cx, double cy) {
    const uint64_t key = hash64(salt ^ hash64(static_cast<uint64_t>(static_cast<int64_t>(cx)) * 0x9E3779B1u +
                                              static_cast<uint64_t>(static_cast<int64_t>(cy))));
    return (key >> 11) * (1.0 / 9007199254740992.0);
  };
  const double tx = x - fx, ty = y - fy;
  const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
  const double top = corner(fx, fy) + sx * (corner(fx + 1, fy) - corner(fx, fy));
  const double bottom = corner(fx, fy + 1) + sx * (corner(fx + 1, fy + 1) - corner(fx, fy + 1));
  return top + sy * (bottom - top);
}

}  // namespace

cv::Mat hazeDensity(cv::Size size, double timeS, uint32_t seed) {
  require(size.width > 0 && size.height > 0, "haze: empty image size");
  cv::Mat density(size, CV_32F);
  const double scale = std::max(size.width, size.height) / 4.0;  // the coarsest octave: a quarter of the image
  const uint64_t salt = hash64(static_cast<uint64_t>(seed) << 20 | 0x5a0cu);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      float* out = density.ptr<float>(y);
      for (int x = 0; x < size.width; ++x) {
        double value = 0, weight = 0, amplitude = 1, frequency = 1 / scale;
        for (int octave = 0; octave < 3; ++octave) {
          // Each octave drifts its own way and faster than the one below (turbulence).
          const double drift = (octave + 1) * 0.35 * timeS;
          value += amplitude * valueNoise(x * frequency + drift, y * frequency - 0.6 * drift, salt + octave);
          weight += amplitude;
          amplitude *= 0.5;
          frequency *= 2;
        }
        const double v = value / weight;
        out[x] = static_cast<float>(std::clamp((v - 0.25) / 0.5, 0.0, 1.0));
      }
    }
  });
  return density;
}

void applyHaze(cv::Mat& image, const cv::Mat& density, double strength, const cv::Vec3d& smokeBgr) {
  require(image.type() == CV_8UC3 && density.type() == CV_32F && image.size() == density.size(),
          "haze: the image must be 8-bit BGR and the density of its size");
  for (int y = 0; y < image.rows; ++y) {
    cv::Vec3b* pixel = image.ptr<cv::Vec3b>(y);
    const float* d = density.ptr<float>(y);
    for (int x = 0; x < image.cols; ++x) {
      const double a = std::clamp(strength * d[x], 0.0, 1.0);
      for (int c = 0; c < 3; ++c) pixel[x][c] = cv::saturate_cast<uchar>((1 - a) * pixel[x][c] + a * smokeBgr[c]);
    }
  }
}

}  // namespace tissuemosaic::synthetic
