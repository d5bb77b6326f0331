#include "Stereo/StereoParameterTable.h"

namespace tissuemosaic {

const parameters::Table<StereoParameters>& stereoParameterTable() {
  using parameters::choice;
  using parameters::number;
  using P = StereoParameters;
  // Limits: what the kernels take (exact int32 ZNCC up to 19x19; arms of at most 127 px keep window counts in 16
  // bits). Docs: the panel's tooltips.
  static const parameters::Table<P> table("stereo", "stereo", {
    choice("method", &P::method, {StereoMethod::Paper, StereoMethod::AdCensus}, stereoMethodName,
           "The matcher: the paper's section II (ZNCC, outlier removal and hole filling, improved Laplacian "
           "refinement), or AD-Census (Mei et al. 2011) for scenes with sharp depth edges (docs/STEREO.md)."),
    choice("search", &P::search, {StereoSearch::Exhaustive, StereoSearch::Guided}, stereoSearchName,
           "Which (pixel, disparity) cells are scored: exhaustive (every candidate, section II as written) or guided "
           "(a half-resolution pass gives each pixel a window; the full range where that prior fails; docs/STEREO.md)."),
    choice("disparityRange", &P::disparityRangeMode,
           {DisparityRangeMode::Automatic, DisparityRangeMode::Fixed, DisparityRangeMode::WorkingDistance},
           disparityRangeModeName,
           "How the candidate disparities are chosen: auto (from the video, following the tissue), fixed "
           "(min..max disparity) or working-distance (near..far mm through the calibration)."),
    number("minDisparityPx", &P::minDisparityPx, -1000, 1000, "px",
           "Smallest candidate disparity (a left pixel x matches right pixel x - d) of a fixed range; editing it fixes "
           "the range. Paper IV: candidates from -20 to 80 px. Must not exceed the max disparity; at most 1024 "
           "candidates."),
    number("maxDisparityPx", &P::maxDisparityPx, -1000, 1000, "px",
           "Largest candidate disparity of a fixed range, inclusive; editing it fixes the range. Paper IV: 80 px "
           "(range -20..80). The matching cost grows with the number of candidates."),
    number("workingDistanceNearMm", &P::workingDistanceNearMm, 1, 10000, "mm",
           "The nearest tissue, in mm from the scope (along its axis); editing it sets the range from the working "
           "distance, through the calibration: d = f B / Z - doffs."),
    number("workingDistanceFarMm", &P::workingDistanceFarMm, 1, 10000, "mm",
           "The farthest tissue, in mm from the scope; editing it sets the range from the working distance."),
    number("znccWindowPx", &P::znccWindowPx, 3, 19, "px",
           "Side of the square ZNCC matching window, odd. Paper II.A: 11x11, using every other pixel (a chessboard)."),
    number("minWindowStdDev", &P::minWindowStdDev, 0, 100, "grey",
           "Grey-level standard deviation below which a window counts as textureless and gets no ZNCC estimate "
           "(an engine safeguard; not in the paper)."),
    number("leftRightMaxDifferencePx", &P::leftRightMaxDifferencePx, -1, 1000, "px",
           "Winners whose right-view winner disagrees by more than this are dropped (occlusions, fattened depth "
           "edges). -1 switches the check off. An addition to the paper."),
    number("refineMaxDeviationPx", &P::refineMaxDeviationPx, -1, 1000, "px",
           "Where the smoothed d_i and the re-selected o_i differ by more, the output is o_i (a depth edge, where a "
           "neighbourhood average is meaningless). -1 switches it off. An addition to the paper."),
    number("rangeEndMarginPx", &P::rangeEndMarginPx, -1, 100, "px",
           "Winners this close to either end of the disparity range are dropped: their match most likely lies beyond "
           "it (an instrument nearer than the tissue the range follows). 0 drops the end candidates only; -1 switches "
           "it off. An addition to the paper."),
    number("holeMaxEdgeDifferencePx", &P::holeMaxEdgeDifferencePx, -1, 1000, "px",
           "Radial filling ignores a line whose two ends differ by more than this plus 0.25 px per pixel of its length "
           "(it crosses a depth edge). -1 switches it off. An addition to the paper."),
    number("specularMinGrey", &P::specularMinGrey, 1, 256, "grey",
           "Grey level from which a pixel may be a specular highlight, which sits on a different surface point in "
           "each eye and matches consistently but falsely. 256 switches highlight removal off. An addition to the "
           "paper."),
    number("specularMarginPx", &P::specularMarginPx, 0, 20, "px",
           "Estimates within this distance of a highlight (the left pixel, or its match in the right eye) that "
           "disagree with the tissue around it are removed and refilled from that tissue. The margin follows the "
           "highlight's outline. For 960 px wide images: wider ones scale it with their width. An addition to the "
           "paper."),
    number("specularMaxRadiusPx", &P::specularMaxRadiusPx, 1, 100, "px",
           "A saturated area reaching this far on both sides of a pixel (along a row or column) is bright tissue, not "
           "a highlight. Surroundings are sampled just beyond the bright spot and its matching windows. For 960 px "
           "wide images: wider ones scale it with their width."),
    number("specularMinContrastGrey", &P::specularMinContrastGrey, 0, 255, "grey",
           "A highlight is brighter than the mean of its surroundings by at least this many grey levels (by half the "
           "headroom to 255 on bright tissue); bright tissue is about as bright as its surroundings."),
    number("specularViewToleranceGrey", &P::specularViewToleranceGrey, 0, 255, "grey",
           "A highlight is view-dependent: at its surroundings' disparity the other eye is darker by more than this "
           "(or the highlight matched elsewhere). Bright diffuse tissue looks alike to both eyes and keeps its "
           "estimates."),
    number("trackingHighlightMarginPx", &P::trackingHighlightMarginPx, 0, 50, "px",
           "Tracking and fusion leave out the pixels within this distance (a square) of a highlight in the left "
           "image. The stereo output keeps the refilled tissue depth there, but a highlight slides over the tissue as "
           "the camera moves, so features on it would mislead tracking. For 960 px wide images: wider ones scale it "
           "with their width. An addition to the paper."),
    number("outlierIterations", &P::outlierIterations, 0, 10, "",
           "Rounds of outlier removal alternating with hole filling. Paper II.B: 3."),
    number("outlierRadiusStartPx", &P::outlierRadiusStartPx, 1, 200, "px",
           "Initial detection radius r: a pixel is an outlier when none of its 8 radial directions changes smoothly "
           "within r. Paper II.B: 10 px."),
    number("outlierRadiusStepPx", &P::outlierRadiusStepPx, 0, 200, "px",
           "Growth of r per round, so that removed disparities can be filled and later rounds keep inliers. "
           "Paper II.B: 10 px."),
    number("outlierSmoothnessPx", &P::outlierSmoothnessPx, 0, 100, "px",
           "Largest disparity difference between neighbouring points along a smooth radial direction. "
           "Paper II.B: 2.5."),
    number("holeRadialRadiusPx", &P::holeRadialRadiusPx, 0, 500, "px",
           "Hole filling, first method: search distance along the pixel's 8 radial directions. Paper II.B: 50 px."),
    number("holeRadialMinLines", &P::holeRadialMinLines, 1, 4, "",
           "Hole filling, first method: opposite direction pairs that must both reach a valid disparity before "
           "interpolating (the paper's 'sufficient number of neighbouring points')."),
    number("holeDiscRadiusPx", &P::holeDiscRadiusPx, 0, 200, "px",
           "Hole filling, second method: radius of the neighbourhood searched around the pixel. Paper II.B: 20 px."),
    number("holeDiscMinValidFraction", &P::holeDiscMinValidFraction, 0, 1, "",
           "Hole filling, second method: share of the neighbourhood that must have a valid disparity before "
           "interpolating (the paper's 'sufficient number')."),
    number("refineIterations", &P::refineIterations, 0, 100, "",
           "Rounds of improved Laplacian smoothing, each followed by re-selection of the discrete disparity o_i. "
           "The paper does not state the number."),
    number("refineRadiusPx", &P::refineRadiusPx, 1, 200, "px",
           "Neighbourhood radius of the Laplacian smoothing of the discrete disparities o_j (design default 15 px)."),
    number("refineAlpha", &P::refineAlpha, 0, 1, "",
           "Vollmer's weight in b_i = d_i(k) - alpha o_i - (1 - alpha) d_i(k-1), which keeps the surface from "
           "shrinking. Paper II.C: 0.1, in [0, 1]."),
    number("refineEta", &P::refineEta, 0, 100, "",
           "Weight of the smoothness cost (o - d_i)^2 against the ZNCC cost 1/ZNCC when re-selecting o_i. "
           "Paper II.C: 0.01 with an 11x11 window."),
    number("refineSearchPx", &P::refineSearchPx, 0, 50, "px",
           "o_i is re-selected within [d_i - s, d_i + s] minimising 1/ZNCC + eta (o - d_i)^2. Paper II.C: 5 px."),
    number("censusWidthPx", &P::censusWidthPx, 1, 15, "px",
           "Census window width, odd; width x height - 1 may not exceed 64 bits. Mei et al.: 9."),
    number("censusHeightPx", &P::censusHeightPx, 1, 15, "px", "Census window height, odd. Mei et al.: 7."),
    number("censusLambda", &P::censusLambda, 0.01, 1000, "",
           "Census cost 1 - exp(-Hamming distance / lambda). Mei et al.: 30."),
    number("absoluteDifferenceLambda", &P::absoluteDifferenceLambda, 0.01, 1000, "",
           "Grey cost 1 - exp(-|I_L - I_R| / lambda). Mei et al.: 10 (on colour)."),
    number("armMaxPx", &P::armMaxPx, 0, 127, "px",
           "Longest reach of a pixel's cross arms, the support region of the cost aggregation. Mei et al.: 34."),
    number("armLongPx", &P::armLongPx, 0, 127, "px",
           "Beyond this reach an arm must also stay within the stricter grey limit tau2. Mei et al.: 17; at most L1."),
    number("armLimitGrey", &P::armLimitGrey, 1, 256, "grey",
           "An arm stops at a grey step of this much from its anchor or from its predecessor. Mei et al.: 20."),
    number("armLongLimitGrey", &P::armLongLimitGrey, 1, 256, "grey",
           "Beyond L2 an arm stops at this grey difference from its anchor. Mei et al.: 6."),
    number("aggregationIterations", &P::aggregationIterations, 0, 8, "",
           "Rounds of cross-based aggregation, alternating horizontal-first and vertical-first. 2 scored as well as "
           "Mei et al.'s 4."),
    number("pathPenaltySmall", &P::pathPenaltySmall, 0, 100, "",
           "Scanline optimisation: penalty of a 1 px disparity change, in cost units (census + grey cost <= 2). "
           "Divided by 4 across an edge in one image, by 10 across both. Mei et al.: 1."),
    number("pathPenaltyLarge", &P::pathPenaltyLarge, 0, 100, "",
           "Penalty of a larger disparity change; at least P1. Mei et al.: 3."),
    number("pathEdgeGrey", &P::pathEdgeGrey, 1, 256, "grey",
           "A grey step of this much along a scanline path is an edge: the path penalties shrink there. Mei et al.: "
           "15."),
  });
  return table;
}

}  // namespace tissuemosaic
