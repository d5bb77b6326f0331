#include "IO/Datasets/HamlynRectified.h"

#include "Core/Error.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

namespace tissuemosaic {
namespace {

namespace fs = std::filesystem;

/// The folder that holds image01: the one given, or its doubled rectifiedNN/rectifiedNN.
fs::path sequenceFolder(const fs::path& folder) {
  if (fs::is_directory(folder / "image01")) return folder;
  const fs::path doubled = folder / folder.filename();
  if (fs::is_directory(doubled / "image01")) return doubled;
  return folder;
}

}  // namespace

HamlynRectified readHamlynRectified(const std::string& folderText) {
  fs::path given(folderText);
  if (given.filename().empty()) given = given.parent_path();  // a trailing slash
  require(fs::is_directory(given), "Hamlyn folder '" + folderText + "' does not exist");
  const fs::path folder = sequenceFolder(given);
  HamlynRectified sequence;
  sequence.leftFolder = (folder / "image01").string();
  sequence.rightFolder = (folder / "image02").string();
  for (const std::string& part : {sequence.leftFolder, sequence.rightFolder}) {
    require(fs::is_directory(part), "Hamlyn folder '" + folderText + "': the frame folder '" + part + "' is missing "
                                    "(image01 holds the left frames, image02 the right ones)");
  }
  const fs::path intrinsicsPath = folder / "intrinsics.txt";
  std::ifstream file(intrinsicsPath);
  require(file.good(), "Hamlyn folder '" + folderText + "': '" + intrinsicsPath.string() + "' is missing");
  std::vector<double> values;
  std::string word;
  while (file >> word) {
    char* end = nullptr;
    const double value = std::strtod(word.c_str(), &end);
    require(end != word.c_str() && *end == '\0' && std::isfinite(value),
            "'" + intrinsicsPath.string() + "': '" + word + "' is not a number (expected a 3x3 or 3x4 camera matrix)");
    values.push_back(value);
  }
  require(values.size() == 9 || values.size() == 12,
          "'" + intrinsicsPath.string() + "' holds " + std::to_string(values.size()) +
              " numbers: expected a 3x3 or 3x4 camera matrix (9 or 12)");
  const int columns = values.size() == 9 ? 3 : 4;
  sequence.focalPx = values[0];
  sequence.cxPx = values[2];
  sequence.cyPx = values[columns + 2];
  require(sequence.focalPx > 0 && sequence.cxPx > 0 && sequence.cyPx > 0,
          "'" + intrinsicsPath.string() + "': the focal length and principal point must be positive");
  if (columns == 4 && values[3] != 0) sequence.baselineMm = std::abs(values[3]) / sequence.focalPx;
  return sequence;
}

}  // namespace tissuemosaic
