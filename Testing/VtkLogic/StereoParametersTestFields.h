#pragma once
// StereoParameters for tests: a value set in which every field differs from its default, and a comparison of all
// fields, both over the stereo table's rows. For the parameter-file tests (VtkLogic) and the panel tests (Widgets).
#include "Stereo/StereoParameterTable.h"

#include <gtest/gtest.h>

#include <vector>

namespace tissuemosaic::test {

/// Every numeric field differs from its default (and is exactly representable in the panel's decimals; a row
/// without its value here fails UnusualParametersDifferInEveryField); the method stays the default. The range's
/// mode is WorkingDistance, as the panel leaves it after its working distance fields were edited last.
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

/// The numeric rows of the stereo table (the method and the range's mode are choices, with combo boxes).
inline std::vector<const parameters::Field<StereoParameters>*> numericStereoFields() {
  std::vector<const parameters::Field<StereoParameters>*> rows;
  for (const auto& field : stereoParameterTable().fields()) {
    if (field.kind != parameters::FieldKind::Choice) rows.push_back(&field);
  }
  return rows;
}

/// Every field of a and b equal (the table's rows), the failing ones named.
inline void expectSameParameters(const StereoParameters& a, const StereoParameters& b) {
  for (const auto& field : stereoParameterTable().fields()) {
    if (field.kind == parameters::FieldKind::Float) {
      EXPECT_FLOAT_EQ(static_cast<float>(field.get(a)), static_cast<float>(field.get(b))) << field.key;
    } else {
      EXPECT_EQ(field.get(a), field.get(b)) << field.key;
    }
  }
}

}  // namespace tissuemosaic::test
