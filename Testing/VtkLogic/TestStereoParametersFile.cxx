// Parameter files: every field survives a write/read round trip; presets parse; invalid files are refused.
#include "vtkTissueMosaicStereoLogic.h"

#include <gtest/gtest.h>

#include <vtkNew.h>

#include <filesystem>
#include <fstream>

using tissuemosaic::StereoParameters;

namespace {

std::string outputPath(const std::string& name) {
  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  return std::string(TM_TEST_OUTPUT_DIR) + "/" + name;
}

void expectSameParameters(const StereoParameters& a, const StereoParameters& b) {
  EXPECT_EQ(a.minDisparityPx, b.minDisparityPx);
  EXPECT_EQ(a.maxDisparityPx, b.maxDisparityPx);
  EXPECT_EQ(a.znccWindowPx, b.znccWindowPx);
  EXPECT_FLOAT_EQ(a.minWindowStdDev, b.minWindowStdDev);
  EXPECT_EQ(a.outlierIterations, b.outlierIterations);
  EXPECT_EQ(a.outlierRadiusStartPx, b.outlierRadiusStartPx);
  EXPECT_EQ(a.outlierRadiusStepPx, b.outlierRadiusStepPx);
  EXPECT_FLOAT_EQ(a.outlierSmoothnessPx, b.outlierSmoothnessPx);
  EXPECT_EQ(a.holeRadialRadiusPx, b.holeRadialRadiusPx);
  EXPECT_EQ(a.holeRadialMinLines, b.holeRadialMinLines);
  EXPECT_EQ(a.holeDiscRadiusPx, b.holeDiscRadiusPx);
  EXPECT_FLOAT_EQ(a.holeDiscMinValidFraction, b.holeDiscMinValidFraction);
  EXPECT_EQ(a.refineIterations, b.refineIterations);
  EXPECT_EQ(a.refineRadiusPx, b.refineRadiusPx);
  EXPECT_FLOAT_EQ(a.refineAlpha, b.refineAlpha);
  EXPECT_FLOAT_EQ(a.refineEta, b.refineEta);
  EXPECT_EQ(a.refineSearchPx, b.refineSearchPx);
}

/// Every field differs from the default.
StereoParameters unusualParameters() {
  StereoParameters p;
  p.minDisparityPx = -7;
  p.maxDisparityPx = 57;
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
  return p;
}

}  // namespace

TEST(StereoParametersFile, RoundTripKeepsEveryField) {
  for (const char* name : {"round-trip.yml", "round-trip.xml"}) {
    vtkNew<vtkTissueMosaicStereoLogic> writer;
    ASSERT_TRUE(writer->SetStereoParameters(unusualParameters())) << writer->GetLastErrorText();
    const std::string path = outputPath(name);
    ASSERT_TRUE(writer->WriteParametersFile(path)) << writer->GetLastErrorText();

    vtkNew<vtkTissueMosaicStereoLogic> reader;
    ASSERT_TRUE(reader->ReadParametersFile(path)) << reader->GetLastErrorText();
    expectSameParameters(reader->GetStereoParameters(), unusualParameters());
  }
}

TEST(StereoParametersFile, PaperDefaultsPresetIsTheStructDefault) {
  StereoParameters parameters = unusualParameters();
  std::string errorText;
  ASSERT_TRUE(vtkTissueMosaicStereoLogic::ReadStereoParametersFile(TM_PRESETS_DIR "/paper-defaults.yml", parameters,
                                                                   errorText))
      << errorText;
  expectSameParameters(parameters, StereoParameters{});

  ASSERT_TRUE(
      vtkTissueMosaicStereoLogic::ReadStereoParametersFile(TM_PRESETS_DIR "/fast.yml", parameters, errorText))
      << errorText;
  EXPECT_LT(parameters.znccWindowPx, StereoParameters{}.znccWindowPx);
  EXPECT_LT(parameters.refineIterations, StereoParameters{}.refineIterations);

  // The AD-Census preset: that method with Mei et al.'s values, which are the struct's defaults.
  parameters = unusualParameters();
  ASSERT_TRUE(
      vtkTissueMosaicStereoLogic::ReadStereoParametersFile(TM_PRESETS_DIR "/ad-census.yml", parameters, errorText))
      << errorText;
  EXPECT_EQ(parameters.method, tissuemosaic::StereoMethod::AdCensus);
  const StereoParameters defaults;
  EXPECT_EQ(parameters.minDisparityPx, defaults.minDisparityPx);
  EXPECT_EQ(parameters.maxDisparityPx, defaults.maxDisparityPx);
  EXPECT_EQ(parameters.censusWidthPx, defaults.censusWidthPx);
  EXPECT_EQ(parameters.censusHeightPx, defaults.censusHeightPx);
  EXPECT_EQ(parameters.armMaxPx, defaults.armMaxPx);
  EXPECT_EQ(parameters.aggregationIterations, defaults.aggregationIterations);
  EXPECT_FLOAT_EQ(parameters.pathPenaltyLarge, defaults.pathPenaltyLarge);
}

TEST(StereoParametersFile, ParsesTextInMemoryAndKeepsDefaultsForMissingKeys) {
  StereoParameters parameters;
  std::string errorText;
  ASSERT_TRUE(vtkTissueMosaicStereoLogic::ParseStereoParameters(
      "%YAML:1.0\n---\nstereo:\n   maxDisparityPx: 40\n   refineEta: 0.02\n", parameters, errorText))
      << errorText;
  EXPECT_EQ(parameters.maxDisparityPx, 40);
  EXPECT_FLOAT_EQ(parameters.refineEta, 0.02f);
  EXPECT_EQ(parameters.minDisparityPx, -20);
  EXPECT_EQ(parameters.znccWindowPx, 11);
}

TEST(StereoParametersFile, InvalidOrMissingFilesAreRefused) {
  vtkNew<vtkTissueMosaicStereoLogic> logic;
  ASSERT_TRUE(logic->SetStereoParameters(unusualParameters()));

  const std::string inverted = outputPath("inverted.yml");
  std::ofstream(inverted) << "%YAML:1.0\n---\nstereo:\n   minDisparityPx: 50\n   maxDisparityPx: 10\n";
  EXPECT_FALSE(logic->ReadParametersFile(inverted));
  EXPECT_NE(logic->GetLastErrorText().find("inverted"), std::string::npos) << logic->GetLastErrorText();

  const std::string wrongType = outputPath("wrong-type.yml");
  std::ofstream(wrongType) << "%YAML:1.0\n---\nstereo:\n   znccWindowPx: 7.5\n";
  EXPECT_FALSE(logic->ReadParametersFile(wrongType));
  EXPECT_NE(logic->GetLastErrorText().find("znccWindowPx"), std::string::npos) << logic->GetLastErrorText();

  const std::string missing = outputPath("does-not-exist.yml");
  EXPECT_FALSE(logic->ReadParametersFile(missing));
  EXPECT_NE(logic->GetLastErrorText().find(missing), std::string::npos) << logic->GetLastErrorText();

  expectSameParameters(logic->GetStereoParameters(), unusualParameters());
}
