#pragma once
/// @file StereoParameters.h
/// @brief Every parameter of the section II stereo matcher, with the paper's defaults, in one validated struct.
/// This is the single source of these values: the command line, the parameter files and the GUI panel all edit
/// this object.
#include <string>

namespace cv {
class FileStorage;
class FileNode;
}  // namespace cv

namespace tissuemosaic {

/// The matcher: the paper's section II (ZNCC, outlier removal and hole filling, Laplacian refinement), or AD-Census
/// (Mei et al. 2011: census + absolute-difference cost, cross-based aggregation, scanline optimisation), an
/// addition for scenes with sharp depth edges (it meets the Middlebury bar that the paper's local method does not;
/// docs/STEREO.md). Both run on the CPU and CUDA.
enum class StereoMethod { Paper, AdCensus };

/// "paper" or "ad-census".
const char* stereoMethodName(StereoMethod method);
/// Throws Error naming the choices for anything else.
StereoMethod parseStereoMethod(const std::string& name);

/// How the disparity range is chosen (docs/STEREO.md, "Disparity range"). The matcher itself always takes
/// minDisparityPx..maxDisparityPx; whoever runs it on a video (the pipeline, the commands, the app's logic) turns the
/// other modes into those two numbers (Stereo/DisparityRangeEstimator.h, Stereo/DisparityRange.h).
enum class DisparityRangeMode {
  Automatic,        ///< from sparse feature matches of the first frames, then following the tissue (the default)
  Fixed,            ///< minDisparityPx..maxDisparityPx as given
  WorkingDistance,  ///< workingDistanceNearMm..FarMm through the rig: d = f B / Z - doffs
};

/// Which (pixel, disparity) cells the paper's method scores (docs/STEREO.md, "Guided search").
enum class StereoSearch {
  Exhaustive,  ///< every candidate of the range at every pixel: section II as written
  Guided,      ///< a half-resolution exhaustive pass gives each pixel a window of candidates; the full range where
               ///< that prior is missing or its winner lies on the window's edge
};

/// "exhaustive" or "guided".
const char* stereoSearchName(StereoSearch search);
/// Throws Error naming the choices for anything else.
StereoSearch parseStereoSearch(const std::string& name);

/// "auto", "fixed" or "working-distance".
const char* disparityRangeModeName(DisparityRangeMode mode);
/// Throws Error naming the choices for anything else.
DisparityRangeMode parseDisparityRangeMode(const std::string& name);

/// The image width (px) the highlight sizes of StereoParameters are given for: the paper's 960x540.
constexpr int kHighlightSizesWidthPx = 960;

struct StereoParameters {
  StereoMethod method = StereoMethod::Paper;
  /// The paper's method only (AD-Census always scores every cell). File key "search".
  StereoSearch search = StereoSearch::Exhaustive;

  /// The disparity range. Automatic by default: a surgeon knows neither disparities nor, often, the distance.
  /// Files: key "disparityRange"; a file that gives minDisparityPx/maxDisparityPx without it means Fixed.
  DisparityRangeMode disparityRangeMode = DisparityRangeMode::Automatic;
  // ZNCC local matching (II.A). Windows use every other pixel (a chessboard that contains the centre).
  int minDisparityPx = -20;           ///< smallest candidate disparity (left x matches right x - d); paper: -20
  int maxDisparityPx = 80;            ///< largest candidate disparity, inclusive; paper: 80
  float workingDistanceNearMm = 30.0f;   ///< WorkingDistance: the nearest tissue, mm from the left rectified camera
  float workingDistanceFarMm = 150.0f;   ///< ... and the farthest
  int znccWindowPx = 11;              ///< odd window side, 3..19
  float minWindowStdDev = 1.0f;       ///< grey-level std below which a window is textureless: no estimate

  // Additions to the paper (set to -1 to switch off).
  int leftRightMaxDifferencePx = 1;   ///< ZNCC winners failing the left-right check by more are dropped
  /// Winners this close to either end of the range (0: on the end candidate itself; -1: off) are dropped: the cost
  /// was still improving toward the end, so the true match most likely lies beyond it (an instrument nearer than the
  /// range that follows the tissue), and the winner is whatever the end resembles. 1 px: the end's neighbour wins
  /// as often where the correlation is flat (docs/STEREO.md, "Surfaces beyond the range").
  int rangeEndMarginPx = 1;
  float refineMaxDeviationPx = 2.0f;  ///< output o_i instead of d_i where they differ by more than this
  float holeMaxEdgeDifferencePx = 2.5f;  ///< radial filling skips lines whose ends differ by more (depth edges)
  // Specular highlights sit on a different surface point in each eye and match consistently but falsely. A
  // highlight seed is near saturation, brighter than its surroundings, and view-dependent (HighlightKernels.h);
  // estimates within specularMarginPx of a seed (left pixel, or its match in the right eye) are removed, and hole
  // filling gives them the surrounding tissue's disparity.
  // The three highlight sizes in px (margin, max. radius, tracking margin) are for images kHighlightSizesWidthPx
  // wide; wider images scale them up with their width (forImageWidth): a highlight covers as much of the view at
  // every resolution.
  float specularMinGrey = 240.0f;          ///< seeds are at least this bright (256: highlight removal off)
  int specularMarginPx = 3;                ///< margin around the seeds, following their outline
  int specularMaxRadiusPx = 48;            ///< a saturated core this far on both sides of a pixel is tissue
  float specularMinContrastGrey = 40.0f;   ///< a seed is brighter than the mean of its surroundings by this much
  float specularViewToleranceGrey = 30.0f; ///< a seed is brighter than the other eye at its surroundings' match
  /// Tracking and fusion leave out the pixels within this (a square) of a left seed: the disparity there is the
  /// tissue's, but a highlight slides over the tissue as the camera moves, so features on it mislead tracking.
  int trackingHighlightMarginPx = 14;

  // Iterative outlier removal and hole filling (II.B).
  int outlierIterations = 3;          ///< removal + filling rounds
  int outlierRadiusStartPx = 10;      ///< r of the first round
  int outlierRadiusStepPx = 10;       ///< r grows by this each round
  float outlierSmoothnessPx = 2.5f;   ///< largest disparity step between neighbours along a smooth ray
  int holeRadialRadiusPx = 50;        ///< radial filling: search distance along each of the 8 rays
  int holeRadialMinLines = 2;         ///< radial filling: opposite-ray pairs that must both hit a value
  int holeDiscRadiusPx = 20;          ///< disc filling: neighbourhood radius
  float holeDiscMinValidFraction = 0.5f;  ///< disc filling: share of the neighbourhood that must be valid

  // Improved Laplacian refinement (II.C).
  int refineIterations = 3;           ///< smoothing + re-selection rounds (the paper does not state it; 1: mean
                                      ///< error 0.171 px on the synthetic pair, 2: 0.159, 3: 0.155, 4: 0.152)
  int refineRadiusPx = 15;            ///< smoothing neighbourhood radius
  float refineAlpha = 0.1f;           ///< Vollmer's alpha, in [0, 1]
  float refineEta = 0.01f;            ///< weight of the smoothness cost against 1/ZNCC
  int refineSearchPx = 5;             ///< o_i is re-selected within d_i +- this

  // AD-Census (method ad-census; Mei et al.'s values, grey levels for their colour distances). The disparity range,
  // leftRightMaxDifferencePx and the specular masking above apply to it too.
  int censusWidthPx = 9;              ///< census window, odd; width x height - 1 <= 64 bits
  int censusHeightPx = 7;
  float censusLambda = 30.0f;         ///< robust census cost 1 - exp(-hamming / lambda)
  float absoluteDifferenceLambda = 10.0f;  ///< robust grey cost 1 - exp(-|IL - IR| / lambda)
  int armMaxPx = 34;                  ///< cross arms: longest reach (L1)
  int armLongPx = 17;                 ///< beyond this reach (L2) the stricter armLongLimitGrey applies
  int armLimitGrey = 20;              ///< an arm stops at a grey step of this much (tau1)
  int armLongLimitGrey = 6;           ///< ... and, beyond armLongPx, at this difference from its anchor (tau2)
  int aggregationIterations = 2;      ///< cross-based aggregation rounds (2 measured as good as Mei's 4)
  float pathPenaltySmall = 1.0f;      ///< scanline optimisation P1 (pi1), cost units
  float pathPenaltyLarge = 3.0f;      ///< P2 (pi2); both shrink by 4 across one image's edge, by 10 across both
  int pathEdgeGrey = 15;              ///< a grey step of this much is an edge for the penalties (tau_SO)

  int disparityCount() const { return maxDisparityPx - minDisparityPx + 1; }
  /// Mode Fixed with this range (not validated here).
  void setFixedDisparityRange(int minPx, int maxPx) {
    disparityRangeMode = DisparityRangeMode::Fixed;
    minDisparityPx = minPx;
    maxDisparityPx = maxPx;
  }
  int znccRadiusPx() const { return znccWindowPx / 2; }
  /// The parameters the matcher uses on images widthPx wide: the highlight sizes times widthPx / kHighlightSizesWidthPx
  /// (rounded) where that is more than 1, else as they are. At 1920x1080 the 48 px radius would class most of the
  /// scope light's highlights as bright tissue, and their mirror images, matched behind the tissue, were fused.
  StereoParameters forImageWidth(int widthPx) const;

  /// Throws Error naming the first parameter that is out of range.
  void validate() const;

  /// Writes the parameters under the node name "stereo".
  void write(cv::FileStorage& storage) const;
  /// Reads the parameters from a "stereo" node; keys that are missing keep their defaults, keys of the wrong type
  /// are an error. Validates the result.
  static StereoParameters read(const cv::FileNode& stereoNode);

  /// Reads the "stereo" node of a YAML/XML parameters file (Error when the file is missing or unreadable).
  static StereoParameters readFile(const std::string& path);
  /// Writes a parameters file holding the "stereo" node.
  void writeFile(const std::string& path) const;
};

/// Throws Error when no disparity of a fixed range can match inside frames widthPx wide (it would give 0 % density):
/// the command line and the Python module check it before any work.
void requireDisparityRangeMeetsImage(const StereoParameters& parameters, int widthPx);

}  // namespace tissuemosaic
