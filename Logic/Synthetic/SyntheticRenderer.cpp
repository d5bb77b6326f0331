#include "SyntheticRenderer.h"

#include "SyntheticRandom.h"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace tissuemosaic::synthetic {

namespace {

/// x^n by repeated squaring (n >= 0): exact and much cheaper than std::pow.
double powInt(double x, int n) {
  double result = 1.0;
  for (; n > 0; n >>= 1, x *= x)
    if (n & 1) result *= x;
  return result;
}

/// Brightness factor of the physical lens at a world ray direction (smooth fall-off toward the corners).
double vignettingFactor(const SyntheticCamera& lens, const cv::Vec3d& rayWorld, double strength) {
  const cv::Vec2d pixel = lens.project(lens.centreWorldMm + rayWorld);
  const double halfW = 0.5 * lens.imageSize.width, halfH = 0.5 * lens.imageSize.height;
  const double dx = pixel[0] - lens.K(0, 2), dy = pixel[1] - lens.K(1, 2);
  const double r2 = (dx * dx + dy * dy) / (halfW * halfW + halfH * halfH);
  return std::max(0.0, 1.0 - strength * r2);
}

/// Linear BGR radiance of the surface point at ray parameter t (Lambert + Blinn-Phong, light at the scope tip, or
/// the realistic lighting), its diffuse and specular parts apart.
SurfaceRadiance shade(const cv::Vec3d& origin, const cv::Vec3d& ray, double t, const cv::Vec2d& gradient,
                      const TissueSurface& surface, const TissueTexture& texture, const ShadingParameters& shading) {
  const cv::Vec3d point = origin + t * ray;
  // The texture moves with the tissue: read where this tissue point rested (its own XY unless it slid).
  const cv::Vec2d material = surface.materialXYMm(point[0], point[1]);
  if (shading.realistic) {
    return shading.realistic->shade(point, gradient, texture.albedo(material[0], material[1]), shading.lightWorldMm,
                                    origin, shading.lightReferenceMm, &material);
  }
  const cv::Vec3d normal = cv::normalize(cv::Vec3d(gradient[0], gradient[1], -1.0));
  cv::Vec3d toLight = shading.lightWorldMm - point;
  const double distance2 = toLight.dot(toLight);
  toLight *= 1.0 / std::sqrt(distance2);
  const cv::Vec3d toEye = cv::normalize(origin - point);
  const double diffuse = std::max(0.0, normal.dot(toLight));
  const double halfway = normal.dot(cv::normalize(toLight + toEye));
  // Below 0.97 the highlight term is < 1e-11 at the shininess used: skip the power.
  const double specular = halfway > 0.97 ? shading.specularStrength * powInt(halfway, shading.shininess) : 0.0;
  const double irradiance = shading.lightReferenceMm * shading.lightReferenceMm / distance2;
  const cv::Vec3f albedo = texture.albedo(material[0], material[1]);
  const double lit = (diffuse + shading.ambient) * irradiance * 1.2;
  return {{albedo[0] * lit, albedo[1] * lit, albedo[2] * lit}, specular * irradiance};
}

/// 8-bit grey level (OpenCV's BGR weights) of gamma-encoded linear BGR, before noise.
double encodedGrey(const cv::Vec3d& linear, const std::vector<float>& gamma, int tableSize) {
  const double weights[3] = {0.114, 0.587, 0.299};
  double grey = 0;
  for (int c = 0; c < 3; ++c) grey += weights[c] * gamma[static_cast<int>(std::min(1.0, std::max(0.0, linear[c])) * tableSize + 0.5)];
  return grey;
}

}  // namespace

cv::Mat renderView(const SyntheticCamera& camera, const SyntheticCamera& lensCamera, const TissueSurface& surface,
                   const TissueTexture& texture, const ShadingParameters& shading, uint32_t seed,
                   uint32_t noiseStream, cv::Mat* highlightMask, const RayOccluder* occluder) {
  const int width = camera.imageSize.width, height = camera.imageSize.height;
  const int n = std::max(1, shading.supersampling);
  cv::Mat image = shading.rowParity >= 0 ? cv::Mat::zeros(camera.imageSize, CV_8UC3) : cv::Mat(camera.imageSize, CV_8UC3);
  if (highlightMask) {
    if (shading.rowParity >= 0) *highlightMask = cv::Mat::zeros(camera.imageSize, CV_8U);
    else highlightMask->create(camera.imageSize, CV_8U);
  }
  // 8-bit gamma table (sRGB-like 1/2.2) over linear values in [0, 1].
  constexpr int tableSize = 4096;
  std::vector<float> gamma(tableSize + 1);
  for (int i = 0; i <= tableSize; ++i) gamma[i] = static_cast<float>(255.0 * std::pow(i / double(tableSize), 1 / 2.2));

  cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
    // The last two hits of each sub-row predict the next one (linear extrapolation): one Newton step then suffices.
    std::vector<double> last(n), beforeLast(n);
    for (int y = rows.start; y < rows.end; ++y) {
      if (shading.rowParity >= 0 && (y & 1) != shading.rowParity) continue;
      std::fill(last.begin(), last.end(), 0.0);
      std::fill(beforeLast.begin(), beforeLast.end(), 0.0);
      cv::Vec3b* out = image.ptr<cv::Vec3b>(y);
      for (int x = 0; x < width; ++x) {
        cv::Vec3d sum(0, 0, 0), diffuseSum(0, 0, 0);
        cv::Vec3d dRayDu, dRayDv;
        const cv::Vec3d centreRay = camera.rayWorld(x, y, dRayDu, dRayDv);
        for (int sy = 0; sy < n; ++sy) {
          const double dv = (sy + 0.5) / n - 0.5;
          for (int sx = 0; sx < n; ++sx) {
            const double du = (sx + 0.5) / n - 0.5;
            const cv::Vec3d ray = centreRay + du * dRayDu + dv * dRayDv;
            cv::Vec2d gradient;
            const double guess = beforeLast[sy] > 0 ? 2 * last[sy] - beforeLast[sy] : last[sy];
            // 1 um along the ray is far below a texel: plenty for shading.
            const double t = surface.intersect(camera.centreWorldMm, ray, guess, &gradient, 1e-3);
            if (std::isfinite(t)) {
              beforeLast[sy] = last[sy];
              last[sy] = t;
            }
            cv::Vec3d occluded;
            if (occluder && occluder->shade(camera.centreWorldMm, ray, std::isfinite(t) ? t : HUGE_VAL, shading, occluded)) {
              // An instrument in front of the tissue: its glints are not the tissue's highlights (the mask's subject).
              sum += occluded;
              diffuseSum += occluded;
            } else if (std::isfinite(t)) {  // else looking away from the tissue: black
              const SurfaceRadiance radiance = shade(camera.centreWorldMm, ray, t, gradient, surface, texture, shading);
              const cv::Vec3d specular(radiance.specular, radiance.specular, radiance.specular);
              sum += radiance.diffuse + specular;
              diffuseSum += radiance.diffuse;
            }
          }
        }
        const double vignette = vignettingFactor(lensCamera, centreRay, shading.vignetting);
        const uint64_t pixel = static_cast<uint64_t>(y) * width + x;
        for (int c = 0; c < 3; ++c) {
          const double exposed = sum[c] * vignette / (n * n);
          const double linear = std::min(1.0, std::max(0.0, exposed));
          const double encoded = gamma[static_cast<int>(linear * tableSize + 0.5)];
          // Read noise plus shot noise growing with the signal.
          const double sigma = std::sqrt(shading.noiseStdGrey * shading.noiseStdGrey + 0.012 * encoded);
          const double noisy = encoded + (shading.noiseStdGrey > 0 ? sigma * hashedGaussian(seed, noiseStream, pixel * 3 + c) : 0.0);
          // A realistic sensor clips at full well: a saturated pixel reads 255 exactly, whatever the noise.
          const bool clipped = shading.realistic != nullptr && exposed >= 1.0;
          out[x][c] = clipped ? uchar(255) : cv::saturate_cast<uchar>(noisy);
        }
        if (highlightMask) {
          const double scale = vignette / (n * n);
          const double raised = encodedGrey(sum * scale, gamma, tableSize) - encodedGrey(diffuseSum * scale, gamma, tableSize);
          highlightMask->at<uchar>(y, x) = raised >= kHighlightMinGrey ? 255 : 0;
        }
      }
    }
  });
  return image;
}

void renderRectifiedGroundTruth(const SyntheticCamera& left, const SyntheticCamera& right,
                                const TissueSurface& surface, cv::Mat& disparityPx, cv::Mat& depthMm) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  disparityPx.create(left.imageSize, CV_32F);
  depthMm.create(left.imageSize, CV_32F);
  cv::parallel_for_(cv::Range(0, left.imageSize.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      float* disparity = disparityPx.ptr<float>(y);
      float* depth = depthMm.ptr<float>(y);
      double last = 0, beforeLast = 0;
      for (int x = 0; x < left.imageSize.width; ++x) {
        disparity[x] = depth[x] = nan;
        const cv::Vec3d ray = left.rayWorld(x, y);
        const double t = surface.intersect(left.centreWorldMm, ray, beforeLast > 0 ? 2 * last - beforeLast : last);
        if (!std::isfinite(t)) continue;
        beforeLast = last;
        last = t;
        const cv::Vec3d point = left.centreWorldMm + t * ray;
        double leftDepth = 0, rightDepth = 0;
        left.project(point, &leftDepth);
        const cv::Vec2d inRight = right.project(point, &rightDepth);
        // Surfaces here are never self-occluded (TissueSurface::maxSlope), so in the right image means visible.
        if (rightDepth <= 0 || inRight[0] < -0.5 || inRight[0] > right.imageSize.width - 0.5) continue;
        depth[x] = static_cast<float>(leftDepth);
        disparity[x] = static_cast<float>(x - inRight[0]);
      }
    }
  });
}

}  // namespace tissuemosaic::synthetic
