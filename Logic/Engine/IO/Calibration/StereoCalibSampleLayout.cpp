// OpenCV's stereo_calib sample (samples/cpp/stereo_calib.cpp) and the SCARED / SurgT da Vinci data sets: M1 D1 M2 D2
// in intrinsics.yml, R T (and the sample's own R1 R2 P1 P2 Q, not used) in extrinsics.yml, or all in one file.
// No image size: the frames give it.
#include "IO/Calibration/CalibrationLayout.h"

#include "Core/Error.h"
#include "Core/ParameterError.h"

namespace tissuemosaic {

CalibrationLayout stereoCalibSampleLayout() {
  CalibrationLayout layout;
  layout.name = "OpenCV stereo_calib sample / SCARED / SurgT";
  layout.keys = "M1 D1 M2 D2 R T (one file, or intrinsics.yml with its extrinsics file, extrinsics.yml)";
  layout.matches = [](const CalibrationInput& input) { return hasKeys(input.main.root, {"M1"}) && !input.right; };
  layout.read = [](const CalibrationInput& input) {
    const YAML::Node& root = input.main.root;
    // Without R and T the extrinsics file is missing: the error names that input (the command line's
    // --calib-extrinsics, Python's extrinsics=).
    const bool extrinsicsMissing = !root["R"] && !root["T"];
    StereoCalibration c;
    c.K1 = readMatrix(requireKey(root, "M1"), "M1");
    c.D1 = distortionRow(readMatrix(requireKey(root, "D1"), "D1"));
    c.K2 = readMatrix(requireKey(root, "M2"), "M2");
    c.D2 = distortionRow(readMatrix(requireKey(root, "D2"), "D2"));
    try {
      c.R = readMatrix(requireKey(root, "R"), "R");
      c.T = readMatrix(requireKey(root, "T"), "T");
    } catch (const Error& e) {
      if (!extrinsicsMissing) throw;
      throw ParameterError("extrinsicsCalibration",
                           std::string(e.what()) + " (the stereo_calib sample writes R and T to extrinsics.yml: give "
                                                   "that file too)");
    }
    if (c.T.total() == 3) c.T = translationColumn(c.T, "T");
    c.imageSize = optionalImageSize(root);
    return c;
  };
  return layout;
}

}  // namespace tissuemosaic
