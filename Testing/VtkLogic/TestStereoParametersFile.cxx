// Parameter files: every field survives a write/read round trip; presets parse; invalid files are refused.
#include "StereoParametersTestFields.h"
#include "vtkTissueMosaicStereoLogic.h"

#include <gtest/gtest.h>

#include <vtkNew.h>

#include <filesystem>
#include <fstream>

using tissuemosaic::StereoParameters;
using tissuemosaic::test::expectSameParameters;
using tissuemosaic::test::unusualParameters;

namespace {

std::string outputPath(const std::string& name) {
  std::filesystem::create_directories(TM_TEST_OUTPUT_DIR);
  return std::string(TM_TEST_OUTPUT_DIR) + "/" + name;
}

}  // namespace

TEST(StereoParametersFile, UnusualParametersDifferInEveryField) {
  // What makes the round trips below cover every row of the stereo table.
  const StereoParameters unusual = unusualParameters(), defaults;
  for (const auto* field : tissuemosaic::test::numericStereoFields()) {
    EXPECT_NE(field->get(unusual), field->get(defaults)) << field->key << ": give it a value in unusualParameters()";
  }
  EXPECT_NO_THROW(unusual.validate());
}

TEST(StereoParametersFile, RoundTripKeepsEveryField) {
  StereoParameters written = unusualParameters();
  written.method = tissuemosaic::StereoMethod::AdCensus;  // the method too
  for (const char* name : {"round-trip.yml", "round-trip.xml"}) {
    vtkNew<vtkTissueMosaicStereoLogic> writer;
    ASSERT_TRUE(writer->SetStereoParameters(written)) << writer->GetLastErrorText();
    const std::string path = outputPath(name);
    ASSERT_TRUE(writer->WriteParametersFile(path)) << writer->GetLastErrorText();

    vtkNew<vtkTissueMosaicStereoLogic> reader;
    ASSERT_TRUE(reader->ReadParametersFile(path)) << reader->GetLastErrorText();
    expectSameParameters(reader->GetStereoParameters(), written);
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
  StereoParameters adCensusDefaults;
  adCensusDefaults.method = tissuemosaic::StereoMethod::AdCensus;
  expectSameParameters(parameters, adCensusDefaults);
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
