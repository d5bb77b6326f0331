#include "OptionNames.h"

#include <map>

namespace tissuemosaic::cli {

std::string optionFor(const std::string& parameter) {
  static const std::map<std::string, std::string> options = {
      {"focalPx", "--focal-px"},
      {"baselineMm", "--baseline-mm"},
      {"cxPx", "--cx-px"},
      {"cyPx", "--cy-px"},
      {"doffsPx", "--doffs-px"},
      {"device", "--device"},
      {"disparityRange", "--min-disparity/--max-disparity"},
      {"calibration", "--calib"},
      {"rightCalibration", "--calib-right"},
      {"extrinsicsCalibration", "--calib-extrinsics"},
      {"modelPath", "--out"},
      {"repeats", "--repeats"},
      {"maxAlignmentRotationSdDeg", "--max-alignment-sd-deg"},
  };
  const auto found = options.find(parameter);
  return found != options.end() ? found->second : std::string();
}

std::string withOptionName(const ParameterError& error) {
  const std::string option = optionFor(error.parameter());
  return option.empty() ? std::string(error.what()) : option + ": " + error.what();
}

}  // namespace tissuemosaic::cli
