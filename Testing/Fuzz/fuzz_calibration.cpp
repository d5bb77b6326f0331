// One calibration file of any layout (OpenCV stereoCalibrate YAML/XML, stereo_calib sample / SCARED / SurgT,
// Kalibr camchain, MATLAB stereoParameters JSON) through readCalibrationFiles, as `--calib FILE` reads it.
#include "FuzzFile.h"
#include "IO/Calibration/CalibrationFile.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile file("calibration.yaml");
  fuzz::quietOpenCv();
  const std::string& path = file.write(data, size);
  fuzz::expectOnlyErrors([&] { readCalibrationFiles(CalibrationFiles{path, "", ""}); });
  return 0;
}
