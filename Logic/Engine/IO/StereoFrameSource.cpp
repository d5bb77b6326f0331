#include "IO/StereoFrameSource.h"

#include "Core/Error.h"
#include "Core/PixelFormat.h"
#include "IO/ImageFile.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

namespace tissuemosaic {
namespace {

std::string sizeText(const cv::Size& size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

std::vector<std::filesystem::path> imagesIn(const std::string& folder) {
  const std::filesystem::path path(folder);
  require(std::filesystem::is_directory(path), "frame folder '" + folder + "' does not exist or is not a folder");
  static const std::vector<std::string> extensions = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".ppm", ".pgm"};
  std::vector<std::filesystem::path> frames;
  for (const auto& entry : std::filesystem::directory_iterator(path)) {
    if (!entry.is_regular_file()) continue;
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    if (std::find(extensions.begin(), extensions.end(), extension) != extensions.end()) frames.push_back(entry.path());
  }
  require(!frames.empty(), "frame folder '" + folder + "' holds no image files (.png .jpg .bmp .tif ...)");
  std::sort(frames.begin(), frames.end());
  return frames;
}

class FrameFolderSource : public StereoFrameSource {
public:
  FrameFolderSource(const std::string& leftFolder, const std::string& rightFolder, double fps)
      : left_(imagesIn(leftFolder)), right_(imagesIn(rightFolder)), fps_(fps),
        description_("frames in '" + leftFolder + "' and '" + rightFolder + "'") {
    require(fps > 0 && std::isfinite(fps), "frame rate must be positive");
    require(left_.size() == right_.size(), "'" + leftFolder + "' has " + std::to_string(left_.size()) +
                                               " frames but '" + rightFolder + "' has " + std::to_string(right_.size()));
    size_ = loadImage(left_.front().string()).size();
  }
  bool next(StereoFrame& frame) override {
    if (index_ >= left_.size()) return false;
    const ImagePair pair = loadImagePair(left_[index_].string(), right_[index_].string());
    require(pair.left.size() == size_, "frame '" + left_[index_].string() + "' is " + sizeText(pair.left.size()) +
                                           " but the first frame is " + sizeText(size_));
    frame.index = static_cast<int>(index_);
    frame.timeS = static_cast<double>(index_) / fps_;
    frame.left = toBgr8(pair.left, "frame '" + left_[index_].string() + "'");
    frame.right = toBgr8(pair.right, "frame '" + right_[index_].string() + "'");
    ++index_;
    return true;
  }
  int frameCount() const override { return static_cast<int>(left_.size()); }
  cv::Size frameSize() const override { return size_; }
  std::string description() const override { return description_; }

private:
  std::vector<std::filesystem::path> left_, right_;
  double fps_;
  std::string description_;
  cv::Size size_;
  std::size_t index_ = 0;
};

cv::VideoCapture openVideo(const std::string& path) {
  require(std::filesystem::is_regular_file(path), "cannot open video '" + path + "': file does not exist");
  cv::VideoCapture capture(path);
  require(capture.isOpened(), "cannot open video '" + path + "': not a readable video (corrupt or unsupported codec)");
  return capture;
}

/// Time stamp of the frame just read: the container's, else index / fps (30 when the container has none).
double frameTimeS(cv::VideoCapture& capture, int index) {
  const double ms = capture.get(cv::CAP_PROP_POS_MSEC);
  if (index > 0 && ms > 0) return ms / 1000.0;
  const double fps = capture.get(cv::CAP_PROP_FPS);
  return index / (fps > 0 ? fps : 30.0);
}

class VideoPairSource : public StereoFrameSource {
public:
  VideoPairSource(const std::string& leftVideo, const std::string& rightVideo)
      : left_(openVideo(leftVideo)), right_(openVideo(rightVideo)),
        description_("videos '" + leftVideo + "' and '" + rightVideo + "'") {
    const cv::Size l(static_cast<int>(left_.get(cv::CAP_PROP_FRAME_WIDTH)), static_cast<int>(left_.get(cv::CAP_PROP_FRAME_HEIGHT)));
    const cv::Size r(static_cast<int>(right_.get(cv::CAP_PROP_FRAME_WIDTH)), static_cast<int>(right_.get(cv::CAP_PROP_FRAME_HEIGHT)));
    require(l == r, "the left video is " + sizeText(l) + " but the right one is " + sizeText(r));
    size_ = l;
    const int frames = static_cast<int>(std::min(left_.get(cv::CAP_PROP_FRAME_COUNT), right_.get(cv::CAP_PROP_FRAME_COUNT)));
    frames_ = frames > 0 ? frames : -1;
  }
  bool next(StereoFrame& frame) override {
    cv::Mat left, right;
    if (!left_.read(left) || !right_.read(right) || left.empty() || right.empty()) return false;
    require(left.size() == size_ && right.size() == size_,
            "video frame " + std::to_string(index_) + " has an unexpected size (" + sizeText(left.size()) + ", " +
                sizeText(right.size()) + ")");
    frame.index = index_;
    frame.timeS = frameTimeS(left_, index_);
    frame.left = toBgr8(left, "video frame");
    frame.right = toBgr8(right, "video frame");
    ++index_;
    return true;
  }
  int frameCount() const override { return frames_; }
  cv::Size frameSize() const override { return size_; }
  std::string description() const override { return description_; }

private:
  cv::VideoCapture left_, right_;
  std::string description_;
  cv::Size size_;
  int frames_ = -1;
  int index_ = 0;
};

class SideBySideSource : public StereoFrameSource {
public:
  explicit SideBySideSource(const std::string& video) : capture_(openVideo(video)), description_("side-by-side video '" + video + "'") {
    const int width = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_WIDTH));
    const int height = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_HEIGHT));
    require(width > 0 && width % 2 == 0, "side-by-side video '" + video + "' is " + std::to_string(width) +
                                             " pixels wide: expected an even width (left eye | right eye)");
    size_ = cv::Size(width / 2, height);
    const int frames = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
    frames_ = frames > 0 ? frames : -1;
  }
  bool next(StereoFrame& frame) override {
    cv::Mat both;
    if (!capture_.read(both) || both.empty()) return false;
    require(both.cols == 2 * size_.width && both.rows == size_.height,
            "video frame " + std::to_string(index_) + " has an unexpected size " + sizeText(both.size()));
    frame.index = index_;
    frame.timeS = frameTimeS(capture_, index_);
    frame.left = toBgr8(both(cv::Rect(0, 0, size_.width, size_.height)).clone(), "video frame");
    frame.right = toBgr8(both(cv::Rect(size_.width, 0, size_.width, size_.height)).clone(), "video frame");
    ++index_;
    return true;
  }
  int frameCount() const override { return frames_; }
  cv::Size frameSize() const override { return size_; }
  std::string description() const override { return description_; }

private:
  cv::VideoCapture capture_;
  std::string description_;
  cv::Size size_;
  int frames_ = -1;
  int index_ = 0;
};

}  // namespace

std::unique_ptr<StereoFrameSource> StereoFrameSource::openFrameFolders(const std::string& leftFolder,
                                                                       const std::string& rightFolder, double fps) {
  return std::make_unique<FrameFolderSource>(leftFolder, rightFolder, fps);
}

std::unique_ptr<StereoFrameSource> StereoFrameSource::openVideoPair(const std::string& leftVideo,
                                                                    const std::string& rightVideo) {
  return std::make_unique<VideoPairSource>(leftVideo, rightVideo);
}

std::unique_ptr<StereoFrameSource> StereoFrameSource::openSideBySideVideo(const std::string& video) {
  return std::make_unique<SideBySideSource>(video);
}

}  // namespace tissuemosaic
