// Parameters files are strict (issue 32): a misspelt node or key is an error naming it and the nearest known name;
// an empty file says so. Every key the structs write is accepted back.
#include "Core/Error.h"
#include "ErrorText.h"
#include "Reconstruction/ReconstructionParameters.h"
#include "Stereo/StereoParameters.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

namespace tissuemosaic {
namespace {

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/ParameterFiles";
  std::filesystem::create_directories(folder);
  std::ofstream(folder + "/" + name) << text;
  return folder + "/" + name;
}

TEST(ParameterFiles, MisspeltKeysAndNodesAreNamedWithTheNearestKnownName) {
  const std::string header = "%YAML:1.0\n---\n";
  EXPECT_EQ(errorOf([&] { ReconstructionParameters::parse(header + "stereo:\n   znccWindw: 9\n"); }),
            "cannot parse parameters: unknown key 'znccWindw' in node 'stereo' (did you mean 'znccWindowPx'?)");
  EXPECT_EQ(errorOf([&] { ReconstructionParameters::parse(header + "fusoin:\n   maxPoints: 5\n"); }),
            "cannot parse parameters: unknown node 'fusoin' (did you mean 'fusion'?)");
  const std::string far = errorOf([&] { ReconstructionParameters::parse(header + "colour:\n   red: 1\n"); });
  EXPECT_NE(far.find("unknown node 'colour' (known nodes: "), std::string::npos) << far;
  EXPECT_NE(far.find("stereo"), std::string::npos) << far;
  // The file readers say which file.
  const std::string typo = writeFile("typo.yml", header + "tracking:\n   minInliers: 10\nstereo:\n   maxDisparityPxx: 9\n");
  EXPECT_NE(errorOf([&] { ReconstructionParameters::readFile(typo); })
                .find("parameters file '" + typo + "': unknown key 'maxDisparityPxx' in node 'stereo' (did you mean "
                      "'maxDisparityPx'?)"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { StereoParameters::readFile(typo); }).find("unknown key 'maxDisparityPxx'"), std::string::npos);
}

TEST(ParameterFiles, EveryWrittenKeyReadsBackAndEmptyFilesAreNamed) {
  const std::string path = std::string(TM_TEST_OUTPUT_DIR) + "/ParameterFiles-all.yml";
  ReconstructionParameters written;
  written.stereo.znccWindowPx = 9;
  written.writeFile(path);
  EXPECT_EQ(ReconstructionParameters::readFile(path).stereo.znccWindowPx, 9);
  EXPECT_EQ(StereoParameters::readFile(path).znccWindowPx, 9);
  const std::string empty = writeFile("empty.yml", "");
  EXPECT_EQ(errorOf([&] { ReconstructionParameters::readFile(empty); }),
            "cannot read parameters file '" + empty +
                "': the file is empty (it should hold nodes such as 'stereo:' or 'tracking:', see Resources/Presets)");
  EXPECT_NE(errorOf([&] { StereoParameters::readFile(empty); }).find("the file is empty"), std::string::npos);
  const std::string blank = writeFile("blank.yml", "%YAML:1.0\n---\n# nothing\n");
  EXPECT_NE(errorOf([&] { ReconstructionParameters::readFile(blank); }).find("holds no parameter node"),
            std::string::npos);
}

// Found by fuzz_params (Testing/Fuzz/corpus/fuzz_params/crash-*): OpenCV's YAML parser lets an empty key out as
// std::length_error, which is not an Error (the CLI printed "basic_string::_M_create").
TEST(ParameterFiles, YamlWithOrWithoutItsHeaderXmlAndJsonAreRead) {
  // A file is read once and OpenCV parses its text from memory, where it tells YAML by the "%YAML" line alone.
  const std::string yamlBody = "# a comment first\nstereo:\n  znccWindowPx: 9\ntracking:\n  keyFrameMinInliers: 40\n";
  const std::map<std::string, std::string> texts = {
      {"plain.yml", yamlBody},
      {"header.yml", "%YAML:1.0\n---\n" + yamlBody},
      {"document.yaml", "---\n" + yamlBody},
      {"params.xml", "<?xml version=\"1.0\"?>\n<opencv_storage><stereo><znccWindowPx>9</znccWindowPx></stereo>"
                     "<tracking><keyFrameMinInliers>40</keyFrameMinInliers></tracking></opencv_storage>\n"},
      {"params.json", "{\"stereo\": {\"znccWindowPx\": 9}, \"tracking\": {\"keyFrameMinInliers\": 40}}\n"}};
  for (const auto& [name, text] : texts) {
    const ReconstructionParameters fromFile = ReconstructionParameters::readFile(writeFile(name, text));
    EXPECT_EQ(fromFile.stereo.znccWindowPx, 9) << name;
    EXPECT_EQ(fromFile.tracking.keyFrameMinInliers, 40) << name;
    EXPECT_EQ(StereoParameters::readFile(writeFile(name, text)).znccWindowPx, 9) << name;
    EXPECT_EQ(ReconstructionParameters::parse(text).stereo.znccWindowPx, 9) << name;
  }
  EXPECT_NE(errorOf([] { ReconstructionParameters::parse(" \n"); }).find("cannot parse parameters: the text is empty"),
            std::string::npos);
}

TEST(ParameterFiles, ParserFailuresOtherThanCvExceptionAreErrors) {
  const std::string text = "%YAML:1.0\n---\nstereo:\n   minDisparityPx: -20\n   :\n   refineAlpha: 0.1\n";
  const std::string path = writeFile("empty-key.yml", text);
  EXPECT_NE(errorOf([&] { ReconstructionParameters::readFile(path); })
                .find("cannot read parameters file '" + path + "': not a valid YAML/XML file"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { ReconstructionParameters::parse(text); }).find("not valid YAML/XML"), std::string::npos);
}

// Found by fuzz_params (corpus/fuzz_params/timeout-6a984fd7*, 272 bytes, minimised to this): OpenCV 4.6's YAML
// parser never returned, so `stereo --params` hung. yaml-cpp reads the text first.
TEST(ParameterFiles, TextsThatHangOpenCvsParserAreErrors) {
  // The second is a valid YAML map for yaml-cpp (the "-~--" line continues a scalar) but still hung OpenCV; so did
  // the third's "-." lines and the fourth's NUL byte (fuzz_params, corpus/fuzz_params/timeout-*).
  for (const std::string text :
       {std::string("%YAML:1.0\n L:0\n-a--\n"), std::string("%YAML:1.0\n---\n# A\n   ransacConfidence: 0.\n-~--\n"),
        std::string("%YAML:1.0\n   outlierSmoothness: xP.52nul\n-.\n-.\n# Faster and cas|er and co:1-0-\n"),
        std::string("%YAML:1.0\nstereo:\n   Y\x06\0L: 1.0\n", 27),
        // A carriage return without a line feed ("-\r--", and "-\r" before other text, looped), and a second
        // directive line ("%YAt(" looped once the header was put before a text without one):
        // corpus/fuzz_params/timeout-8b10*, timeout-0fc1*, timeout-4cdf*.
        std::string("%YAML:1.0\n---\nstereo:\n  a: 5\r\r0\n-\r--\r\r0\n"),
        std::string("%YAML:1.0\n   censusLambda\xd2\xb5ongL:1.0\n-0\n-\r\xd3\xf5\xdc\xdf" "AD-Cead of the paper"),
        std::string("%YAt( mieets the\n# a comment\n  armLongLimitGrey: 30.\n-1-\n"),
        // A second document, and a sequence item left of the mapping (corpus/fuzz_params/timeout-f45d*, -b182*).
        std::string("%YAML:1.0\n key and more:1.0\n---\n- Arey: 20\n"),
        std::string("%YAML:1.0\n   abs\xff\xff-armL%YAMLmitGrey: 20\n-0\n- the\n")}) {
    const std::string path = writeFile("hangs-opencv.yml", text);
    EXPECT_NE(errorOf([&] { ReconstructionParameters::readFile(path); }).find("cannot read parameters file '" + path + "': "),
              std::string::npos);
    EXPECT_NE(errorOf([&] { ReconstructionParameters::parse(text); }).find("cannot parse parameters: "), std::string::npos);
  }
  EXPECT_NE(errorOf([&] { ReconstructionParameters::parse(std::string("stereo:\n  a\0b: 1\n", 16)); })
                .find("not a valid YAML/XML file (line 2 holds a control byte)"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { ReconstructionParameters::parse("stereo:\n  a: 1\n%TAG ! x\n"); })
                .find("line 3 is a directive: only a first line '%YAML:1.0' is taken"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { ReconstructionParameters::parse("stereo:\n  znccWindowPx: 9\n---\ntracking: {}\n"); })
                .find("line 3 starts a second document"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { ReconstructionParameters::parse("  stereo:\n    znccWindowPx: 9\ntracking: {}\n"); })
                .find("line 3 is indented less than the first key"),
            std::string::npos);
  // Windows line ends count as one: the line named is the file's own.
  EXPECT_NE(errorOf([&] { ReconstructionParameters::parse("stereo:\r\n  a: 1\r\n-x\r\n"); }).find("line 3 starts"),
            std::string::npos);
  const std::string negative = writeFile("negative.yml", "%YAML:1.0\nstereo:\n  minDisparityPx: -.5e1\n");
  EXPECT_NE(errorOf([&] { ReconstructionParameters::readFile(negative); }).find("minDisparityPx"), std::string::npos)
      << "a number such as -.5e1 is read, and refused only for its value (not an integer)";
  const std::string broken = writeFile("broken.yml", "%YAML:1.0\n---\nstereo: [1, 2\n");
  EXPECT_NE(errorOf([&] { ReconstructionParameters::readFile(broken); }).find("not a valid YAML/XML file ("), std::string::npos);
}

}  // namespace
}  // namespace tissuemosaic
