#include "IO/Calibration/CalibrationFile.h"

#include "Core/Error.h"
#include "Core/ParameterError.h"
#include "IO/Calibration/CalibrationLayout.h"

#include <opencv2/core.hpp>

namespace tissuemosaic {
namespace {

const std::vector<CalibrationLayout>& layouts() {
  static const std::vector<CalibrationLayout> all = {openCvStereoCalibrateLayout(), stereoCalibSampleLayout(),
                                                     rosCameraInfoLayout(), kalibrLayout(),
                                                     matlabStereoParametersLayout(), stereoMisIniLayout()};
  return all;
}

std::string describe(const CalibrationFiles& files) {
  std::string text = "'" + files.calib + "'";
  if (!files.extrinsics.empty()) text += " with extrinsics '" + files.extrinsics + "'";
  if (!files.right.empty()) text += " with right eye '" + files.right + "'";
  return text;
}

CalibrationDocument loadDocument(const std::string& path) {
  try {
    return CalibrationDocument::load(path);
  } catch (const Error& e) {
    throw Error("cannot read stereo calibration '" + path + "': " + e.what());
  }
}

}  // namespace

std::string calibrationLayoutsText() {
  std::string text;
  for (const CalibrationLayout& layout : layouts()) text += "  " + layout.name + ": " + layout.keys + "\n";
  return text;
}

CalibrationFileContent readCalibrationFiles(const CalibrationFiles& files) {
  CalibrationInput input{loadDocument(files.calib), std::nullopt};
  if (!files.right.empty()) input.right = loadDocument(files.right);
  const std::string context = "cannot read stereo calibration " + describe(files) + ": ";
  try {
    if (!files.extrinsics.empty()) input.main.merge(loadDocument(files.extrinsics));
    for (const CalibrationLayout& layout : layouts()) {
      if (!layout.matches(input)) continue;
      CalibrationFileContent content{layout.read(input), layout.name};
      content.calibration.validate();
      return content;
    }
  } catch (const ParameterError& e) {  // one input missing or wrong: keep which, for the front end to name it
    throw ParameterError(e.parameter(), context + e.what());
  } catch (const Error& e) {
    throw Error(context + e.what());
  } catch (const cv::Exception& e) {
    throw Error(context + e.err);
  } catch (const YAML::Exception& e) {  // a node of another kind than the layout reads (found by fuzz_calibration)
    throw Error(context + "a value has an unexpected form (" + e.what() + ")");
  }
  std::string keys;
  for (const auto& entry : input.main.root) keys += (keys.empty() ? "" : " ") + keyText(entry.first);
  throw Error(context + "no known layout matches its keys (" + keys + ")" +
              (input.right ? " with a second, right-eye file" : "") + ". Layouts understood:\n" +
              calibrationLayoutsText());
}

CalibrationFileContent readCalibrationFiles(const std::vector<std::string>& paths) {
  require(paths.size() == 1 || paths.size() == 2, "give one or two calibration files, not " +
                                                      std::to_string(paths.size()));
  if (paths.size() == 1) return readCalibrationFiles(CalibrationFiles{paths[0], "", ""});
  const CalibrationDocument a = loadDocument(paths[0]), b = loadDocument(paths[1]);
  auto extrinsicsOnly = [](const CalibrationDocument& d) { return hasKeys(d.root, {"R", "T"}) && !d.root["M1"] && !d.root["K1"]; };
  auto rosLeft = [](const CalibrationDocument& d) {
    if (!hasKeys(d.root, {"projection_matrix"})) return false;
    try {
      return readMatrix(d.root, "projection_matrix", 3, 4).at<double>(0, 3) == 0;
    } catch (const Error&) {
      return false;
    }
  };
  if (extrinsicsOnly(b)) return readCalibrationFiles(CalibrationFiles{paths[0], paths[1], ""});
  if (extrinsicsOnly(a)) return readCalibrationFiles(CalibrationFiles{paths[1], paths[0], ""});
  if (rosLeft(b) && !rosLeft(a)) return readCalibrationFiles(CalibrationFiles{paths[1], "", paths[0]});
  return readCalibrationFiles(CalibrationFiles{paths[0], "", paths[1]});
}

StereoCalibration readStereoCalibration(const std::string& path) {
  return readCalibrationFiles(CalibrationFiles{path, "", ""}).calibration;
}

void writeStereoCalibration(const StereoCalibration& calibration, const std::string& path) {
  calibration.validate();
  require(calibration.rectification.empty(),
          "cannot write stereo calibration '" + path +
              "': it has its own rectification (ROS camera_info), which the stereoCalibrate layout cannot hold");
  require(!calibration.imageSize.empty(),
          "cannot write stereo calibration '" + path + "': its image size is not known");
  cv::FileStorage storage;
  try {
    storage.open(path, cv::FileStorage::WRITE);
  } catch (const cv::Exception& e) {
    throw Error("cannot write stereo calibration '" + path + "': " + e.err);
  }
  require(storage.isOpened(), "cannot write stereo calibration '" + path +
                                  "': the folder does not exist or is not writable (use a .yml, .yaml or .xml name)");
  storage << "imageSize" << calibration.imageSize;
  storage << "K1" << calibration.K1 << "D1" << calibration.D1 << "K2" << calibration.K2 << "D2" << calibration.D2
          << "R" << calibration.R << "T" << calibration.T;
  storage.release();
}

}  // namespace tissuemosaic
