#include "ImageFile.h"

#include "Core/Error.h"


#include <filesystem>

namespace tissuemosaic {
namespace {
std::string sizeText(const cv::Mat& image) { return std::to_string(image.cols) + "x" + std::to_string(image.rows); }
}  // namespace

cv::Mat loadImage(const std::string& path, int flags) {
  std::error_code ec;
  require(std::filesystem::exists(path, ec), "cannot read image '" + path + "': file does not exist");
  require(!std::filesystem::is_directory(path, ec), "cannot read image '" + path + "': it is a folder, not a file");
  cv::Mat image;
  try {
    image = cv::imread(path, flags);
  } catch (const cv::Exception&) {
    image.release();  // some decoders throw on corrupt data instead of returning empty
  }
  require(!image.empty(), "cannot read image '" + path + "': the file is not a readable image (corrupt or unsupported format)");
  return image;
}

ImagePair loadImagePair(const std::string& leftPath, const std::string& rightPath, int flags) {
  ImagePair pair{loadImage(leftPath, flags), loadImage(rightPath, flags)};
  require(pair.left.size() == pair.right.size(),
          "the stereo images differ in size: left '" + leftPath + "' is " + sizeText(pair.left) + " but right '" +
              rightPath + "' is " + sizeText(pair.right));
  return pair;
}

}  // namespace tissuemosaic
