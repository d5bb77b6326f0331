#include "TissueTexture.h"

#include "Core/Error.h"
#include "SyntheticRandom.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace tissuemosaic::synthetic {

cv::Mat valueNoise(cv::Size size, double periodTexels, std::mt19937& generator) {
  const int period = std::max(1, static_cast<int>(std::lround(periodTexels)));
  const int gridW = size.width / period + 4, gridH = size.height / period + 4;
  cv::Mat grid(gridH, gridW, CV_32F);
  for (int y = 0; y < gridH; ++y)
    for (int x = 0; x < gridW; ++x) grid.at<float>(y, x) = static_cast<float>(2.0 * uniform01(generator) - 1.0);
  if (period == 1) return grid(cv::Rect(0, 0, size.width, size.height)).clone();
  cv::Mat fine;
  cv::resize(grid, fine, cv::Size(gridW * period, gridH * period), 0, 0, cv::INTER_CUBIC);
  // Skip the first cell, where cubic interpolation sees the replicated border.
  return fine(cv::Rect(period, period, size.width, size.height)).clone();
}

namespace {

cv::Mat smoothstep(const cv::Mat& x, float edge0, float edge1) {
  cv::Mat t = (x - edge0) / (edge1 - edge0);
  cv::min(cv::max(t, 0.0), 1.0, t);
  cv::Mat t2 = t.mul(t);
  return t2.mul(3.0 - 2.0 * t);
}

/// Branching vessels as anti-aliased polylines of decreasing width on a [0, 1] mask.
void paintVessels(cv::Mat& mask, double texelMm, std::mt19937& generator) {
  struct Branch { double x, y, heading, widthMm; int depth; };
  const double stepMm = 0.4;
  const double areaMm2 = mask.cols * mask.rows * texelMm * texelMm;
  const int trees = std::max(2, static_cast<int>(areaMm2 / 1500.0));
  constexpr int shift = 4;  // sub-texel precision of cv::polylines
  for (int tree = 0; tree < trees; ++tree) {
    std::vector<Branch> pending{{uniform(generator, 0, mask.cols * texelMm), uniform(generator, 0, mask.rows * texelMm),
                                 uniform(generator, 0, 6.283185307179586), uniform(generator, 0.25, 0.6), 0}};
    while (!pending.empty()) {
      Branch b = pending.back();
      pending.pop_back();
      double turn = 0;
      for (int step = 0; step < 120 && b.widthMm > 0.08; ++step) {
        turn = 0.85 * turn + 0.04 * (2.0 * uniform01(generator) - 1.0);
        b.heading += turn;
        const double nx = b.x + stepMm * std::cos(b.heading), ny = b.y + stepMm * std::sin(b.heading);
        const cv::Point p0(static_cast<int>(b.x / texelMm * (1 << shift)), static_cast<int>(b.y / texelMm * (1 << shift)));
        const cv::Point p1(static_cast<int>(nx / texelMm * (1 << shift)), static_cast<int>(ny / texelMm * (1 << shift)));
        const int thickness = std::max(1, static_cast<int>(std::lround(b.widthMm / texelMm)));
        cv::line(mask, p0, p1, cv::Scalar(1.0), thickness, cv::LINE_AA, shift);
        b.x = nx;
        b.y = ny;
        b.widthMm *= 0.992;
        if (b.depth < 3 && uniform01(generator) < 0.04) {
          const double side = uniform01(generator) < 0.5 ? -1.0 : 1.0;
          pending.push_back({b.x, b.y, b.heading + side * uniform(generator, 0.4, 1.1), b.widthMm * 0.65, b.depth + 1});
        }
      }
    }
  }
}

}  // namespace

const char* tissueLookName(TissueLook look) { return look == TissueLook::InVivo ? "invivo" : "standard"; }

TissueLook parseTissueLook(const std::string& name) {
  if (name == "standard") return TissueLook::Standard;
  if (name == "invivo") return TissueLook::InVivo;
  throw Error("unknown tissue look '" + name + "' (choose standard or invivo)");
}

namespace {

/// A look's numbers: where the smooth patches are (thresholds on their noise), how strong the fine mottling is, and
/// the linear BGR reflectances.
struct LookParameters {
  float smoothFrom, smoothTo, mottle;
  cv::Vec3f dark, light, capsule, vessel;
};

LookParameters lookParameters(TissueLook look) {
  if (look == TissueLook::InVivo) {
    // Blood-red and darker under the same light; smooth patches over about half of the tissue, weak mottling.
    return {0.15f, 0.45f, 0.45f, {0.006f, 0.008f, 0.085f}, {0.011f, 0.013f, 0.13f}, {0.016f, 0.018f, 0.12f},
            {0.012f, 0.006f, 0.04f}};
  }
  // Dark liver red-brown, lighter pink tissue, a pale glossy capsule for the smooth patches.
  return {0.40f, 0.65f, 1.0f, {0.045f, 0.06f, 0.30f}, {0.10f, 0.13f, 0.46f}, {0.20f, 0.22f, 0.46f},
          {0.07f, 0.035f, 0.16f}};
}

}  // namespace

TissueTexture::TissueTexture(const cv::Rect2d& domainMm, double texelMm, uint32_t seed, TissueLook look)
    : domainMm_(domainMm), texelMm_(texelMm) {
  const LookParameters parameters = lookParameters(look);
  const cv::Size size(static_cast<int>(std::ceil(domainMm.width / texelMm)) + 2,
                      static_cast<int>(std::ceil(domainMm.height / texelMm)) + 2);
  require(texelMm > 0 && size.width >= 4 && size.height >= 4 && size.area() <= 40'000'000,
          "synthetic texture: the textured area is empty or too large for its texel size");
  std::mt19937 generator(seed ^ 0x7e57u);
  const auto noise = [&](double periodMm) { return valueNoise(size, periodMm / texelMm, generator); };

  // Where the tissue has no fine texture: smooth patches covering roughly a quarter of the surface.
  lowTextureMask_ = smoothstep(noise(14.0) + 0.5 * noise(6.0), parameters.smoothFrom, parameters.smoothTo);

  const cv::Mat tone = smoothstep(noise(18.0) + 0.3 * noise(5.0), -0.6f, 0.6f);
  // Fine mottling, strongest at the scales (0.3 - 3 mm, a few pixels) that stereo windows lock onto.
  cv::Mat mottle = 0.35 * noise(2.4) + 0.35 * noise(1.0) + 0.45 * noise(0.45) + 0.35 * noise(0.25);
  mottle = mottle.mul(1.0 - 0.85 * lowTextureMask_);  // low, not zero: weak texture that stereo must still read
  if (parameters.mottle != 1.0f) mottle *= parameters.mottle;

  cv::Mat vessels(size, CV_32F, cv::Scalar(0));
  paintVessels(vessels, texelMm, generator);
  cv::GaussianBlur(vessels, vessels, cv::Size(0, 0), std::max(0.6, 0.05 / texelMm));
  cv::min(vessels, 1.0, vessels);
  vessels = vessels.mul(1.0 - 0.7 * lowTextureMask_);

  const cv::Vec3f dark = parameters.dark, light = parameters.light, capsule = parameters.capsule;
  const cv::Vec3f vessel = parameters.vessel;
  albedo_.create(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y) {
    const float* t = tone.ptr<float>(y);
    const float* m = mottle.ptr<float>(y);
    const float* l = lowTextureMask_.ptr<float>(y);
    const float* v = vessels.ptr<float>(y);
    cv::Vec3f* out = albedo_.ptr<cv::Vec3f>(y);
    for (int x = 0; x < size.width; ++x) {
      cv::Vec3f c = dark * (1 - t[x]) + light * t[x];
      c = c * (1 - 0.6f * l[x]) + capsule * (0.6f * l[x]);
      c *= std::max(0.15f, 1.0f + 0.7f * m[x]);
      c = c * (1 - 0.8f * v[x]) + vessel * (0.8f * v[x]);
      out[x] = c;
    }
  }
}

}  // namespace tissuemosaic::synthetic
