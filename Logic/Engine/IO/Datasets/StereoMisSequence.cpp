#include "IO/Datasets/StereoMisSequence.h"

#include "Core/Error.h"

#include <algorithm>
#include <filesystem>
#include <vector>

namespace tissuemosaic {

StereoMisSequence findStereoMisSequence(const std::string& folderOrVideo) {
  namespace fs = std::filesystem;
  const fs::path given(folderOrVideo);
  require(fs::exists(given), "StereoMIS sequence '" + folderOrVideo + "' does not exist");
  StereoMisSequence sequence;
  fs::path folder = given;
  if (fs::is_directory(given)) {
    std::vector<std::string> videos;
    for (const fs::directory_entry& entry : fs::directory_iterator(given)) {
      std::string extension = entry.path().extension().string();
      std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
      if (entry.is_regular_file() && (extension == ".mp4" || extension == ".avi" || extension == ".mkv" ||
                                      extension == ".mov")) {
        videos.push_back(entry.path().string());
      }
    }
    require(!videos.empty(), "StereoMIS folder '" + folderOrVideo + "' holds no video (.mp4, .avi, .mkv, .mov)");
    std::sort(videos.begin(), videos.end());
    // The message is built only when it is needed: it names a second video.
    if (videos.size() != 1) {
      throw Error("StereoMIS folder '" + folderOrVideo + "' holds " + std::to_string(videos.size()) + " videos (" +
                  videos[0] + ", " + videos[1] + "...): give the one to read");
    }
    sequence.video = videos.front();
  } else {
    sequence.video = given.string();
    folder = given.parent_path().empty() ? fs::path(".") : given.parent_path();
  }
  sequence.calibration = (folder / "StereoCalibration.ini").string();
  require(fs::is_regular_file(sequence.calibration),
          "StereoMIS sequence '" + folderOrVideo + "': '" + sequence.calibration + "' is missing");
  return sequence;
}

}  // namespace tissuemosaic
