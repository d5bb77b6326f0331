// Writing a synthetic pair to files: kept apart from the renderer so that programs which only render (the GPU
// tests and benchmarks) do not link OpenCV's image codecs.
#include "SyntheticStereoScene.h"

#include "Core/Error.h"
#include "IO/DisparityPfm.h"
#include "IO/Calibration/CalibrationFile.h"

#include <opencv2/imgcodecs.hpp>

#include <filesystem>

namespace tissuemosaic::synthetic {

std::vector<std::string> writeSyntheticStereoPair(const SyntheticStereoPair& pair, const std::string& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  require(std::filesystem::is_directory(directory), "cannot create output folder '" + directory + "'");
  const std::filesystem::path folder(directory);
  std::vector<std::string> written;
  const auto image = [&](const char* name, const cv::Mat& pixels) {
    const std::string path = (folder / name).string();
    bool ok = false;
    try {
      ok = cv::imwrite(path, pixels);
    } catch (const cv::Exception&) {
    }
    require(ok, "cannot write image '" + path + "'");
    written.push_back(path);
  };
  image("left.png", pair.leftRectified);
  image("right.png", pair.rightRectified);
  image("left_raw.png", pair.leftRaw);
  image("right_raw.png", pair.rightRaw);
  const std::string rig = (folder / "rig.yml").string();
  writeStereoCalibration(pair.calibration, rig);
  written.push_back(rig);
  for (const auto& [name, map] : {std::pair<const char*, const cv::Mat&>{"disparity.pfm", pair.disparityPx},
                                  std::pair<const char*, const cv::Mat&>{"depth_mm.pfm", pair.depthMm}}) {
    const std::string path = (folder / name).string();
    writePfm(path, map);
    written.push_back(path);
  }
  std::filesystem::create_directories(folder / "groundtruth", error);
  require(std::filesystem::is_directory(folder / "groundtruth"),
          "cannot create output folder '" + (folder / "groundtruth").string() + "'");
  image("groundtruth/highlight_mask_left.png", pair.highlightMaskLeft);
  return written;
}


}  // namespace tissuemosaic::synthetic
