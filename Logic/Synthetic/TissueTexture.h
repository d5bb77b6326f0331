#pragma once
/// @file TissueTexture.h
/// @brief Procedural tissue albedo painted on the surface's (X, Y) plane in millimetres: two tissue tones mixed by
/// low-frequency noise, fine mottling for stereo matching to lock onto, smooth low-texture patches where it
/// cannot, and branching vessels. Stored as a texel map (linear reflectance, BGR) and sampled bilinearly.
#include <opencv2/core.hpp>

#include <cstdint>
#include <random>
#include <string>

namespace tissuemosaic::synthetic {

/// The tissue's look. Standard: liver red-brown and pink with a pale glossy capsule, finely mottled, a quarter of it
/// smooth. InVivo: what real in-vivo frames show (SyntheticInVivo.h): darker, blood-red tissue with less fine texture
/// and more and larger smooth patches (the same noise fields, so the same seed gives the same layout).
enum class TissueLook { Standard, InVivo };
/// "standard" or "invivo".
const char* tissueLookName(TissueLook look);
/// Throws Error naming the choices for anything else.
TissueLook parseTissueLook(const std::string& name);

/// Value noise in [-1, 1]-ish over a size.width x size.height grid: random values every periodTexels, interpolated
/// bicubically. Deterministic from the generator's state.
cv::Mat valueNoise(cv::Size size, double periodTexels, std::mt19937& generator);

class TissueTexture {
public:
  /// Paints the rectangle domainMm (x, y, width, height in mm of the world XY plane) at texelMm per texel.
  TissueTexture(const cv::Rect2d& domainMm, double texelMm, uint32_t seed, TissueLook look = TissueLook::Standard);

  /// Linear BGR reflectance in [0, 1] at world (x, y) mm; outside the domain the border texel is repeated.
  cv::Vec3f albedo(double xMm, double yMm) const {
    const float u = static_cast<float>((xMm - domainMm_.x) / texelMm_);
    const float v = static_cast<float>((yMm - domainMm_.y) / texelMm_);
    const float uc = std::min(std::max(u, 0.f), static_cast<float>(albedo_.cols - 1) - 1e-3f);
    const float vc = std::min(std::max(v, 0.f), static_cast<float>(albedo_.rows - 1) - 1e-3f);
    const int x0 = static_cast<int>(uc), y0 = static_cast<int>(vc);
    const float fx = uc - x0, fy = vc - y0;
    const cv::Vec3f* row0 = albedo_.ptr<cv::Vec3f>(y0) + x0;
    const cv::Vec3f* row1 = albedo_.ptr<cv::Vec3f>(y0 + 1) + x0;
    return (row0[0] * (1 - fx) + row0[1] * fx) * (1 - fy) + (row1[0] * (1 - fx) + row1[1] * fx) * fy;
  }
  /// 1 inside the low-texture patches, 0 on textured tissue (same texel grid as the albedo).
  const cv::Mat& lowTextureMask() const { return lowTextureMask_; }
  const cv::Mat& albedoMap() const { return albedo_; }
  const cv::Rect2d& domainMm() const { return domainMm_; }
  double texelMm() const { return texelMm_; }

private:
  cv::Rect2d domainMm_;
  double texelMm_;
  cv::Mat albedo_;          ///< CV_32FC3
  cv::Mat lowTextureMask_;  ///< CV_32F
};

}  // namespace tissuemosaic::synthetic
