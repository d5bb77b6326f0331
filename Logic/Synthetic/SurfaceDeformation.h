#pragma once
/// @file SurfaceDeformation.h
/// @brief What moves the tissue of the in-vivo scans (SyntheticInVivo.h) beyond the breathing's swell: more swells
/// along world Z (the pulsation, the instruments' dents) and a lateral slide (the breathing's sideways part).
///
/// The slide is defined by its inverse, so that the deformed tissue stays an exact height field: the tissue point
/// now above world (x, y) is the material point that rested at q = (x, y) - s w(x, y), with s the slide vector (mm)
/// and w a SurfaceSwell's weight. The map is one to one while |s| max|grad w| < 1 (SyntheticInVivoOptions checks a
/// wide margin). Swells are painted on q (material coordinates), so the texture, the swells and the rest relief move
/// together.
#include "SurfaceSwell.h"

#include <opencv2/core.hpp>

#include <vector>

namespace tissuemosaic::synthetic {

/// A lateral displacement of the tissue: displacementMm (world XY) where shape's weight is 1, none where it is 0.
struct SurfaceSlide {
  SurfaceSwell shape;               ///< only its weight is used (amplitudeMm ignored)
  cv::Vec2d displacementMm{0, 0};
  bool active() const { return displacementMm[0] != 0 || displacementMm[1] != 0; }
};

struct SurfaceDeformation {
  std::vector<SurfaceSwell> swells;  ///< along world Z, on material coordinates; amplitude 0: none
  SurfaceSlide slide;
};

}  // namespace tissuemosaic::synthetic
