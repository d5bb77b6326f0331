#pragma once
/// @file SubPixelKernels.h
/// @brief The sub-pixel match refinement written once for both backends: one translation-only inverse-compositional
/// Lucas-Kanade per match (see SubPixelMatch.h), run by parallelFor on the CPU or CUDA.
#include "Core/HostDevice.h"

#include <cmath>
#include <cstdint>

namespace tissuemosaic::subpixel {

constexpr int kMaxHalfWindowPx = 7;                             ///< local template storage bound
constexpr int kMaxTemplateSide = 2 * kMaxHalfWindowPx + 1;      ///< the window's side
constexpr int kIterations = 10;
constexpr float kConvergedStep2Px2 = 1e-4f;                     ///< squared step below which LK has converged

/// One match to refine: a pixel in the reference image and the starting pixel in the image (indices into the
/// uploaded image stack).
struct Query {
  int referenceImage;
  int image;
  float fromX, fromY;
  float toX, toY;
};

struct Answer {
  float x, y;  ///< refined pixel (the start when not locked)
  int locked;  ///< 1: converged within the shift limit
};

/// Bilinear sample of an 8-bit image at (x, y); the caller keeps (x, y) at least one pixel inside.
TM_HOST_DEVICE TM_FORCE_INLINE float sampleBilinear(const uint8_t* image, int width, float x, float y) {
  const float fx = floorf(x), fy = floorf(y);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const float a = x - fx, b = y - fy;
  const uint8_t* p = image + static_cast<int64_t>(y0) * width + x0;
  const float top = p[0] * (1.0f - a) + p[1] * a;
  const float bottom = p[width] * (1.0f - a) + p[width + 1] * a;
  return top * (1.0f - b) + bottom * b;
}

/// Both gradient directions must be present (a corner-like window), else the shift along an edge is free.
TM_HOST_DEVICE TM_FORCE_INLINE bool textured(double hxx, double hxy, double hyy, int n) {
  const double det = hxx * hyy - hxy * hxy, trace = hxx + hyy;
  return det > 1e-3 * trace * trace && trace >= n * n * 4.0;
}

/// The Gauss-Newton step (H^-1 b) of the translation.
TM_HOST_DEVICE TM_FORCE_INLINE void solveStep(double hxx, double hxy, double hyy, double bx, double by, double& stepX,
                                              double& stepY) {
  const double det = hxx * hyy - hxy * hxy;
  stepX = (hyy * bx - hxy * by) / det;
  stepY = (hxx * by - hxy * bx) / det;
}

/// The template value and its central-difference gradients at window pixel (x, y) (0-based) of a window whose
/// top-left pixel is at (originX, originY): the same samples whichever backend or loop asks.
TM_HOST_DEVICE TM_FORCE_INLINE void templateAt(const uint8_t* reference, int width, float originX, float originY, int x,
                                               int y, float& value, float& dx, float& dy) {
  value = sampleBilinear(reference, width, originX + x, originY + y);
  dx = 0.5f * (sampleBilinear(reference, width, originX + (x + 1), originY + y) -
               sampleBilinear(reference, width, originX + (x - 1), originY + y));
  dy = 0.5f * (sampleBilinear(reference, width, originX + x, originY + (y + 1)) -
               sampleBilinear(reference, width, originX + x, originY + (y - 1)));
}

/// One LK per match, sequentially over the window: the CPU's form (CUDA runs a warp per match, OrbBackendCuda.cu,
/// with the same helpers; only the order of the window sums differs).
struct LucasKanadeRefine {
  const uint8_t* const* images;  ///< the call's width * height 8-bit images, contiguous rows
  int width, height;
  const Query* queries;
  Answer* answers;
  int halfWindowPx;
  float maxShiftPx;

  TM_HOST_DEVICE bool inside(float x, float y, float margin) const {
    return x >= margin && y >= margin && x < width - margin && y < height - margin;
  }

  TM_HOST_DEVICE void operator()(int64_t index) const {
    const Query q = queries[index];
    Answer& answer = answers[index];
    answer.x = q.toX;
    answer.y = q.toY;
    answer.locked = 0;
    const int n = 2 * halfWindowPx + 1;
    const float margin = static_cast<float>(halfWindowPx + 2) + maxShiftPx;
    if (!inside(q.fromX, q.fromY, margin) || !inside(q.toX, q.toY, margin)) return;
    const uint8_t* reference = images[q.referenceImage];
    const uint8_t* image = images[q.image];
    const float originX = q.fromX - halfWindowPx, originY = q.fromY - halfWindowPx;
    float templ[kMaxTemplateSide * kMaxTemplateSide], gx[kMaxTemplateSide * kMaxTemplateSide],
        gy[kMaxTemplateSide * kMaxTemplateSide];
    double hxx = 0, hxy = 0, hyy = 0;
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const int k = y * n + x;
        templateAt(reference, width, originX, originY, x, y, templ[k], gx[k], gy[k]);
        hxx += gx[k] * gx[k];
        hxy += gx[k] * gy[k];
        hyy += gy[k] * gy[k];
      }
    }
    if (!textured(hxx, hxy, hyy, n)) return;
    float px = q.toX, py = q.toY;
    for (int iteration = 0; iteration < kIterations; ++iteration) {
      const float windowX = px - halfWindowPx, windowY = py - halfWindowPx;
      double bx = 0, by = 0;
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const int k = y * n + x;
          const float e = sampleBilinear(image, width, windowX + x, windowY + y) - templ[k];
          bx += gx[k] * e;
          by += gy[k] * e;
        }
      }
      double stepX = 0, stepY = 0;
      solveStep(hxx, hxy, hyy, bx, by, stepX, stepY);
      if (update(q, stepX, stepY, margin, px, py, answer)) return;
    }
  }

  /// Applies a step; true when the refinement has ended (locked, or left the image or the shift limit).
  TM_HOST_DEVICE bool update(const Query& q, double stepX, double stepY, float margin, float& px, float& py,
                             Answer& answer) const {
    px -= static_cast<float>(stepX);
    py -= static_cast<float>(stepY);
    const float shiftX = px - q.toX, shiftY = py - q.toY;
    if (!inside(px, py, margin) || shiftX * shiftX + shiftY * shiftY > maxShiftPx * maxShiftPx) return true;
    if (stepX * stepX + stepY * stepY < kConvergedStep2Px2) {
      answer.x = px;
      answer.y = py;
      answer.locked = 1;
      return true;
    }
    return false;
  }
};

}  // namespace tissuemosaic::subpixel
