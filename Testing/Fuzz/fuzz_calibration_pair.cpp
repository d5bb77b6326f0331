// The two-file calibration layouts: the stereo_calib sample's intrinsics.yml + extrinsics.yml (`--calib A
// --calib-extrinsics B`) and ROS camera_info per eye (`--calib LEFT --calib-right RIGHT`), then the same two files
// in either order through the app's multiple selection (roles told by content). The input is the first file, a
// line "---8<---", then the second file; its first byte picks extrinsics (odd, as '%' of "%YAML") or right eye (even).
#include "FuzzFile.h"
#include "IO/Calibration/CalibrationFile.h"

#include <string_view>

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static fuzz::FuzzFile first("calibration-left.yaml"), second("calibration-right.yaml");
  fuzz::quietOpenCv();
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view separator = "\n---8<---\n";
  const std::size_t at = bytes.find(separator);
  const std::string_view a = bytes.substr(0, at);
  const std::string_view b = at == std::string_view::npos ? std::string_view() : bytes.substr(at + separator.size());
  const std::string& pathA = first.write(reinterpret_cast<const std::uint8_t*>(a.data()), a.size());
  const std::string& pathB = second.write(reinterpret_cast<const std::uint8_t*>(b.data()), b.size());
  const bool extrinsics = size > 0 && data[0] % 2 == 1;
  fuzz::expectOnlyErrors([&] {
    readCalibrationFiles(extrinsics ? CalibrationFiles{pathA, pathB, ""} : CalibrationFiles{pathA, "", pathB});
  });
  fuzz::expectOnlyErrors([&] { readCalibrationFiles(std::vector<std::string>{pathB, pathA}); });
  return 0;
}
