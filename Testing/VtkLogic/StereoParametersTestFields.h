#pragma once
// StereoParameters for tests: every field by name, a value set in which every field differs from its default, and
// a comparison of all fields. One list for the parameter-file tests (VtkLogic) and the panel tests (Widgets).
#include "Stereo/StereoParameters.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace tissuemosaic::test {

/// Numeric fields of StereoParameters, besides the method, the search and the disparity range's mode; the lists
/// below must name every one of them.
constexpr std::size_t kStereoParameterNumericFields = 41;
static_assert(sizeof(StereoParameters) ==
                      sizeof(StereoMethod) + sizeof(StereoSearch) + sizeof(DisparityRangeMode) +
                          kStereoParameterNumericFields * sizeof(int) &&
                  sizeof(int) == sizeof(float),
              "a StereoParameters field was added: list it in StereoParametersTestFields.h (and in the panel)");

/// Every numeric field differs from its default (and is exactly representable in the panel's decimals); the
/// method stays the default. The range's mode is WorkingDistance, as the panel leaves it after its working distance
/// fields were edited last.
inline StereoParameters unusualParameters() {
  StereoParameters p;
  p.disparityRangeMode = DisparityRangeMode::WorkingDistance;
  p.minDisparityPx = -7;
  p.maxDisparityPx = 57;
  p.workingDistanceNearMm = 35.5f;
  p.workingDistanceFarMm = 120.0f;
  p.znccWindowPx = 9;
  p.minWindowStdDev = 2.25f;
  p.outlierIterations = 5;
  p.outlierRadiusStartPx = 12;
  p.outlierRadiusStepPx = 6;
  p.outlierSmoothnessPx = 1.75f;
  p.holeRadialRadiusPx = 44;
  p.holeRadialMinLines = 3;
  p.holeDiscRadiusPx = 17;
  p.holeDiscMinValidFraction = 0.35f;
  p.refineIterations = 7;
  p.refineRadiusPx = 11;
  p.refineAlpha = 0.3f;
  p.refineEta = 0.025f;
  p.refineSearchPx = 4;
  p.leftRightMaxDifferencePx = 3;
  p.rangeEndMarginPx = 2;
  p.refineMaxDeviationPx = 1.5f;
  p.holeMaxEdgeDifferencePx = -1.0f;
  p.specularMinGrey = 250.0f;
  p.specularMarginPx = 9;
  p.specularMaxRadiusPx = 15;
  p.specularMinContrastGrey = 35.5f;
  p.specularViewToleranceGrey = 22.5f;
  p.trackingHighlightMarginPx = 11;
  p.censusWidthPx = 7;
  p.censusHeightPx = 5;
  p.censusLambda = 25.0f;
  p.absoluteDifferenceLambda = 12.5f;
  p.armMaxPx = 30;
  p.armLongPx = 15;
  p.armLimitGrey = 18;
  p.armLongLimitGrey = 5;
  p.aggregationIterations = 3;
  p.pathPenaltySmall = 1.25f;
  p.pathPenaltyLarge = 3.5f;
  p.pathEdgeGrey = 12;
  return p;
}

/// Every numeric field by name (the method has no spin box and is compared on its own).
struct StereoParameterFields {
  std::vector<std::pair<const char*, int StereoParameters::*>> ints = {
      {"minDisparityPx", &StereoParameters::minDisparityPx},
      {"maxDisparityPx", &StereoParameters::maxDisparityPx},
      {"znccWindowPx", &StereoParameters::znccWindowPx},
      {"outlierIterations", &StereoParameters::outlierIterations},
      {"outlierRadiusStartPx", &StereoParameters::outlierRadiusStartPx},
      {"outlierRadiusStepPx", &StereoParameters::outlierRadiusStepPx},
      {"holeRadialRadiusPx", &StereoParameters::holeRadialRadiusPx},
      {"holeRadialMinLines", &StereoParameters::holeRadialMinLines},
      {"holeDiscRadiusPx", &StereoParameters::holeDiscRadiusPx},
      {"refineIterations", &StereoParameters::refineIterations},
      {"refineRadiusPx", &StereoParameters::refineRadiusPx},
      {"refineSearchPx", &StereoParameters::refineSearchPx},
      {"leftRightMaxDifferencePx", &StereoParameters::leftRightMaxDifferencePx},
      {"rangeEndMarginPx", &StereoParameters::rangeEndMarginPx},
      {"specularMarginPx", &StereoParameters::specularMarginPx},
      {"specularMaxRadiusPx", &StereoParameters::specularMaxRadiusPx},
      {"trackingHighlightMarginPx", &StereoParameters::trackingHighlightMarginPx},
      {"censusWidthPx", &StereoParameters::censusWidthPx},
      {"censusHeightPx", &StereoParameters::censusHeightPx},
      {"armMaxPx", &StereoParameters::armMaxPx},
      {"armLongPx", &StereoParameters::armLongPx},
      {"armLimitGrey", &StereoParameters::armLimitGrey},
      {"armLongLimitGrey", &StereoParameters::armLongLimitGrey},
      {"aggregationIterations", &StereoParameters::aggregationIterations},
      {"pathEdgeGrey", &StereoParameters::pathEdgeGrey}};
  std::vector<std::pair<const char*, float StereoParameters::*>> reals = {
      {"minWindowStdDev", &StereoParameters::minWindowStdDev},
      {"outlierSmoothnessPx", &StereoParameters::outlierSmoothnessPx},
      {"holeDiscMinValidFraction", &StereoParameters::holeDiscMinValidFraction},
      {"refineAlpha", &StereoParameters::refineAlpha},
      {"refineEta", &StereoParameters::refineEta},
      {"refineMaxDeviationPx", &StereoParameters::refineMaxDeviationPx},
      {"holeMaxEdgeDifferencePx", &StereoParameters::holeMaxEdgeDifferencePx},
      {"specularMinGrey", &StereoParameters::specularMinGrey},
      {"specularMinContrastGrey", &StereoParameters::specularMinContrastGrey},
      {"specularViewToleranceGrey", &StereoParameters::specularViewToleranceGrey},
      {"censusLambda", &StereoParameters::censusLambda},
      {"absoluteDifferenceLambda", &StereoParameters::absoluteDifferenceLambda},
      {"pathPenaltySmall", &StereoParameters::pathPenaltySmall},
      {"pathPenaltyLarge", &StereoParameters::pathPenaltyLarge},
      {"workingDistanceNearMm", &StereoParameters::workingDistanceNearMm},
      {"workingDistanceFarMm", &StereoParameters::workingDistanceFarMm}};
};

/// Every field of a and b equal, the failing ones named.
inline void expectSameParameters(const StereoParameters& a, const StereoParameters& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.search, b.search);  // no control of its own in the panel: the stored struct keeps it
  EXPECT_EQ(a.disparityRangeMode, b.disparityRangeMode);
  const StereoParameterFields fields;
  for (const auto& field : fields.ints) EXPECT_EQ(a.*field.second, b.*field.second) << field.first;
  for (const auto& field : fields.reals) EXPECT_FLOAT_EQ(a.*field.second, b.*field.second) << field.first;
}

}  // namespace tissuemosaic::test
