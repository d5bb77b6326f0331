#pragma once
/// @file SyntheticLighting.h
/// @brief The looks of the synthetic scope's light. "standard" (the default) is SyntheticRenderer's own Lambert +
/// Blinn-Phong: small white highlight discs on darker tissue. "realistic" is what real endoscope frames show:
/// - the light at the scope tip with inverse-square fall-off and an exposure that drives the nearest, frontal, pale
///   tissue near and into saturation (large bright diffuse areas);
/// - wet tissue: a thin fluid film mirrors the light guide (a disc at the tip; Schlick Fresnel of water), so a
///   highlight is where the surface normal lies within the guide's angular size of the bisector of the directions to
///   the light and to the eye: a saturated plateau with a soft rim, on a different surface point for each eye (the
///   bisectors of the two eyes differ by about baseline / (2 distance), as much as the plateau is wide). The film
///   lies on a micro-relief of folds (bump mapping: normals only, the geometry and its ground truth are unchanged),
///   so the highlights break into clusters of glints;
/// - the film's cover varies over the tissue (wetness), so some areas glisten and others do not;
/// - sensor clipping: whatever reaches full well reads exactly 255, without noise.
/// The ground truth of both looks includes a highlight mask: pixels the specular reflection brightens by at least
/// kHighlightMinGrey grey levels.
#include <opencv2/core.hpp>

#include <cstdint>
#include <string>

namespace tissuemosaic::synthetic {

enum class SyntheticLighting { Standard, Realistic };

/// "standard" or "realistic".
const char* syntheticLightingName(SyntheticLighting lighting);
/// Throws Error naming the choices for anything else.
SyntheticLighting parseSyntheticLighting(const std::string& name);

/// A pixel is a highlight in the ground truth where the specular reflection raises its 8-bit grey level (OpenCV's
/// BGR to grey weights, before noise) by at least this much.
constexpr double kHighlightMinGrey = 10.0;

/// A surface point's linear radiance, its diffuse part per channel (BGR) and its specular part (white light, the
/// same in every channel) apart, so that the renderer can tell highlights from tissue.
struct SurfaceRadiance {
  cv::Vec3d diffuse{0, 0, 0};
  double specular = 0;
};

struct RealisticLightingParameters {
  double exposure = 5.5;           ///< camera gain on the diffuse light at the reference distance
  double ambient = 0.05;           ///< share of the diffuse light that reaches every point (scattering)
  double filmReflectance = 0.02;   ///< Fresnel reflectance of the wet film at normal incidence (water)
  double lightRadiusMm = 5.0;      ///< radius of the light guide's disc, whose mirror image a highlight is
  double lightRadiance = 20.0;     ///< the guide's radiance, in units where exposed white paper reads about 1
  double rimDeg = 0.5;             ///< softness of a highlight's rim (the film's residual roughness), degrees
  double microSlope = 0.12;        ///< RMS slope of the micro-relief that breaks the highlights into glints
  double microScaleMm = 10.0;      ///< size of the micro-relief's largest folds (two finer octaves below it)
  double minWetness = 0.15;        ///< the film's cover ranges from this to 1 over the tissue
  double glossyRelief = 0.15;      ///< share of the micro-relief's slope left on the glossy (smooth) patches
};

class TissueTexture;

/// Realistic lighting for one scene: the parameters and the wet-tissue maps (micro-relief slopes and wetness over the
/// texture's domain of the world XY plane, sampled bilinearly like TissueTexture). The texture's smooth capsule
/// patches are glossy: fully wet, and the film evens out most of their micro-relief, so their highlights are larger,
/// coherent lobes on weak texture (where they mislead matching most). Deterministic from the seed.
class RealisticLighting {
public:
  RealisticLighting(const TissueTexture& texture, uint32_t seed, const RealisticLightingParameters& parameters = {});

  /// Radiance of the surface point `pointMm` (world), whose height-field gradient is `gradient`, with albedo
  /// `albedo` (linear BGR), lit from `lightMm` and seen from `eyeMm`; `lightReferenceMm` is the distance at which
  /// the exposure holds. Inverse-square fall-off from the light. materialXYMm: where the wet-tissue maps are read
  /// (the tissue's rest XY where it has slid, TissueSurface::materialXYMm); null: the point's own XY.
  SurfaceRadiance shade(const cv::Vec3d& pointMm, const cv::Vec2d& gradient, const cv::Vec3f& albedo,
                        const cv::Vec3d& lightMm, const cv::Vec3d& eyeMm, double lightReferenceMm,
                        const cv::Vec2d* materialXYMm = nullptr) const;

  const RealisticLightingParameters& parameters() const { return parameters_; }

private:
  /// Micro-relief gradient (dh/dx, dh/dy) and wetness at world (x, y) mm; outside the domain the border is repeated.
  cv::Vec3f sample(double xMm, double yMm) const;

  RealisticLightingParameters parameters_;
  cv::Rect2d domainMm_;
  double texelMm_;
  cv::Mat maps_;  ///< CV_32FC3: micro dh/dx, micro dh/dy, wetness
};

}  // namespace tissuemosaic::synthetic
