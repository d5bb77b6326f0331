#include "IO/Datasets/ScaredKeyframe.h"

#include "Core/Error.h"
#include "IO/Calibration/CalibrationDocument.h"

#include <opencv2/videoio.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

namespace tissuemosaic {
namespace {

namespace fs = std::filesystem;

std::string requireFile(const fs::path& path, const std::string& folder, const std::string& what) {
  require(fs::is_regular_file(path), "SCARED key-frame folder '" + folder + "': " + what + " '" + path.string() +
                                         "' is missing");
  return path.string();
}

/// The pose files in frame order (their names carry the frame number with leading zeros).
std::vector<fs::path> poseFiles(const fs::path& folder) {
  std::vector<fs::path> files;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame_data", 0) == 0 && entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

Eigen::Matrix4d readCameraPose(const fs::path& file) {
  try {
    const YAML::Node document = YAML::LoadFile(file.string());  // JSON is YAML
    const cv::Mat pose = readMatrix(document, "camera-pose", 4, 4);
    Eigen::Matrix4d T;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) T(r, c) = pose.at<double>(r, c);
    }
    return T;
  } catch (const YAML::Exception& error) {
    throw Error("SCARED pose file '" + file.string() + "' is not readable JSON: " + error.what());
  } catch (const Error& error) {
    throw Error("SCARED pose file '" + file.string() + "': " + error.what());
  }
}

}  // namespace

ScaredKeyframe readScaredKeyframe(const std::string& folderText) {
  const fs::path folder(folderText);
  require(fs::is_directory(folder), "SCARED key-frame folder '" + folderText + "' does not exist");
  ScaredKeyframe keyframe;
  keyframe.calibration = requireFile(folder / "endoscope_calibration.yaml", folderText, "the calibration");
  keyframe.video = requireFile(folder / "data" / "rgb.mp4", folderText, "the video");
  // Extracted into data/frame_data/ or straight into data/, as the archive's own paths have it.
  fs::path posesFolder = folder / "data" / "frame_data";
  std::vector<fs::path> files = poseFiles(posesFolder);
  if (files.empty()) {
    posesFolder = folder / "data";
    files = poseFiles(posesFolder);
  }
  if (files.empty()) {
    keyframe.posesNote = fs::exists(folder / "data" / "frame_data.tar.gz")
                             ? "no poses: data/frame_data.tar.gz is not extracted (tar -xzf frame_data.tar.gz -C data)"
                             : "no poses: the folder has no data/frame_data";
    return keyframe;
  }
  cv::VideoCapture capture(keyframe.video);
  double fps = capture.isOpened() ? capture.get(cv::CAP_PROP_FPS) : 0;
  if (!(fps > 0)) fps = 25;  // SCARED's videos are 25 frames per second
  for (std::size_t i = 0; i < files.size(); ++i) {
    TimedPose pose;
    pose.timeS = static_cast<double>(i) / fps;
    pose.T_world_camera = readCameraPose(files[i]);
    keyframe.poses.push_back(pose);
  }
  keyframe.posesNote = std::to_string(files.size()) + " poses from " + posesFolder.string();
  return keyframe;
}

}  // namespace tissuemosaic
