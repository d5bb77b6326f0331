#include "SyntheticLighting.h"

#include "Core/Error.h"
#include "SyntheticRandom.h"
#include "TissueTexture.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace tissuemosaic::synthetic {

namespace {

constexpr double degree = 3.141592653589793 / 180.0;

/// x^n by repeated squaring (n >= 0).
double powInt(double x, int n) {
  double result = 1.0;
  for (; n > 0; n >>= 1, x *= x)
    if (n & 1) result *= x;
  return result;
}

}  // namespace

const char* syntheticLightingName(SyntheticLighting lighting) {
  return lighting == SyntheticLighting::Realistic ? "realistic" : "standard";
}

SyntheticLighting parseSyntheticLighting(const std::string& name) {
  if (name == "standard") return SyntheticLighting::Standard;
  if (name == "realistic") return SyntheticLighting::Realistic;
  throw Error("unknown lighting '" + name + "' (choices: standard, realistic)");
}

RealisticLighting::RealisticLighting(const TissueTexture& texture, uint32_t seed,
                                     const RealisticLightingParameters& parameters)
    : parameters_(parameters), domainMm_(texture.domainMm()) {
  // The finest folds (an eighth of the largest) need a few texels each, not the albedo's resolution.
  texelMm_ = std::max(texture.texelMm(), parameters.microScaleMm / 8.0 / 5.0);
  const cv::Size size(static_cast<int>(std::ceil(domainMm_.width / texelMm_)) + 2,
                      static_cast<int>(std::ceil(domainMm_.height / texelMm_)) + 2);
  require(texelMm_ > 0 && size.width >= 4 && size.height >= 4 && size.area() <= 40'000'000,
          "synthetic lighting: the lit area is empty or too large for its texel size");
  std::mt19937 generator(seed ^ 0x11647u);
  // Glossy where the texture has its smooth capsule patches (same domain; resampled to this grid).
  cv::Mat glossy;
  cv::resize(texture.lowTextureMask(), glossy, size, 0, 0, cv::INTER_AREA);
  // Micro-relief: folds and two finer octaves that ripple their highlights; its gradient by central differences,
  // scaled to the wanted slope, and evened out on glossy tissue.
  const double period = parameters.microScaleMm / texelMm_;
  cv::Mat relief = valueNoise(size, period, generator) + 0.3 * valueNoise(size, period / 2.8, generator) +
                   0.08 * valueNoise(size, period / 8.0, generator);
  cv::Mat gx, gy;
  cv::Sobel(relief, gx, CV_32F, 1, 0, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
  cv::Sobel(relief, gy, CV_32F, 0, 1, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
  const double rms = std::sqrt((cv::mean(gx.mul(gx))[0] + cv::mean(gy.mul(gy))[0]) / 2.0);
  const cv::Mat reliefScale = (rms > 0 ? parameters.microSlope / rms : 0.0) *
                              (1.0 - (1.0 - parameters.glossyRelief) * glossy);
  gx = gx.mul(reliefScale);
  gy = gy.mul(reliefScale);
  // Wetness: patches of film and of drier tissue, a few millimetres across; the glossy patches are wet.
  cv::Mat wet = valueNoise(size, 7.0 / texelMm_, generator) + 0.4 * valueNoise(size, 2.5 / texelMm_, generator) + 0.6;
  cv::min(cv::max(wet, glossy), 1.0, wet);
  cv::max(wet, 0.0, wet);
  wet = parameters.minWetness + (1.0 - parameters.minWetness) * wet;
  const cv::Mat planes[3] = {gx, gy, wet};
  cv::merge(planes, 3, maps_);
}

cv::Vec3f RealisticLighting::sample(double xMm, double yMm) const {
  const float u = static_cast<float>((xMm - domainMm_.x) / texelMm_);
  const float v = static_cast<float>((yMm - domainMm_.y) / texelMm_);
  const float uc = std::min(std::max(u, 0.f), static_cast<float>(maps_.cols - 1) - 1e-3f);
  const float vc = std::min(std::max(v, 0.f), static_cast<float>(maps_.rows - 1) - 1e-3f);
  const int x0 = static_cast<int>(uc), y0 = static_cast<int>(vc);
  const float fx = uc - x0, fy = vc - y0;
  const cv::Vec3f* row0 = maps_.ptr<cv::Vec3f>(y0) + x0;
  const cv::Vec3f* row1 = maps_.ptr<cv::Vec3f>(y0 + 1) + x0;
  return (row0[0] * (1 - fx) + row0[1] * fx) * (1 - fy) + (row1[0] * (1 - fx) + row1[1] * fx) * fy;
}

SurfaceRadiance RealisticLighting::shade(const cv::Vec3d& point, const cv::Vec2d& gradient, const cv::Vec3f& albedo,
                                         const cv::Vec3d& lightMm, const cv::Vec3d& eyeMm,
                                         double lightReferenceMm, const cv::Vec2d* materialXYMm) const {
  const RealisticLightingParameters& p = parameters_;
  const cv::Vec3f micro = materialXYMm ? sample((*materialXYMm)[0], (*materialXYMm)[1]) : sample(point[0], point[1]);
  // The surface is Z = h: its normal toward the scope is (dh/dx, dh/dy, -1), tilted by the micro-relief.
  const cv::Vec3d normal = cv::normalize(cv::Vec3d(gradient[0] + micro[0], gradient[1] + micro[1], -1.0));
  cv::Vec3d toLight = lightMm - point;
  const double distance2 = toLight.dot(toLight);
  toLight *= 1.0 / std::sqrt(distance2);
  const cv::Vec3d toEye = cv::normalize(eyeMm - point);
  const double irradiance = p.exposure * lightReferenceMm * lightReferenceMm / distance2;
  const double cosLight = std::max(0.0, normal.dot(toLight));
  SurfaceRadiance radiance;
  radiance.diffuse = cv::Vec3d(albedo[0], albedo[1], albedo[2]) * ((cosLight + p.ambient) * irradiance);
  const cv::Vec3d halfway = cv::normalize(toLight + toEye);
  const double cosHalf = normal.dot(halfway);
  // The mirror image of the guide's disc: normals within half its angular radius of the bisector reflect it.
  const double plateau = 0.5 * p.lightRadiusMm / std::sqrt(distance2);
  const double rim = p.rimDeg * degree;
  if (cosLight > 0 && cosHalf > std::cos(plateau + rim)) {
    const double offAxis = std::acos(std::min(1.0, cosHalf));
    const double t = std::min(1.0, std::max(0.0, (plateau + rim - offAxis) / (2.0 * rim)));
    const double fresnel = p.filmReflectance + (1.0 - p.filmReflectance) * powInt(1.0 - toLight.dot(halfway), 5);
    radiance.specular = micro[2] * fresnel * p.lightRadiance * p.exposure * t * t * (3.0 - 2.0 * t);
  }
  return radiance;
}

}  // namespace tissuemosaic::synthetic
