#include "IO/StereoFrameSource.h"

#include "Core/Error.h"
#include "Core/PixelFormat.h"
#include "IO/ImageFile.h"
#include "IO/LiveVideoCapture.h"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <limits>
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
  require(std::filesystem::file_size(path) > 0, "cannot open video '" + path + "': the file is empty");
  // OpenCV tries every backend and logs each one's failure (assertion text, FFmpeg's and GStreamer's complaints):
  // the error below says it once. Files go to FFmpeg alone where OpenCV has it; FFmpeg's own log is quietened
  // unless the user set OPENCV_FFMPEG_LOGLEVEL (read once, at the first open).
  static const bool quietFfmpeg = [] { return ::setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0) == 0; }();
  (void)quietFfmpeg;
  const cv::utils::logging::LogLevel level = cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  cv::VideoCapture capture;
  try {
    capture.open(path, cv::videoio_registry::hasBackend(cv::CAP_FFMPEG) ? cv::CAP_FFMPEG : cv::CAP_ANY);
  } catch (const cv::Exception&) {
    capture.release();
  }
  cv::utils::logging::setLogLevel(level);
  require(capture.isOpened(), "cannot open video '" + path + "': not a readable video (corrupt or unsupported codec)");
  return capture;
}

/// A size or frame count from the container's header; 0 when the header holds nothing usable. A corrupt header
/// can say -9.2e16 frames, which static_cast<int> would turn into undefined behaviour.
int headerInt(const cv::VideoCapture& capture, int property) {
  const double value = capture.get(property);
  return std::isfinite(value) && value >= 0 && value <= std::numeric_limits<int>::max() ? static_cast<int>(value) : 0;
}

/// Time stamp of the frame just read: the container's, else index / fps (30 when the container has none).
double frameTimeS(cv::VideoCapture& capture, int index) {
  const double ms = capture.get(cv::CAP_PROP_POS_MSEC);
  if (index > 0 && ms > 0) return ms / 1000.0;
  const double fps = capture.get(cv::CAP_PROP_FPS);
  return index / (fps > 0 ? fps : 30.0);
}

/// At the end of a video: its header's frame count must have been read (a truncated or corrupt file ends early), and
/// both videos of a pair must end together.
void requireNotCutShort(const std::string& description, int framesRead, int framesDeclared, bool oneEndedFirst) {
  require(!oneEndedFirst, description + ": one video ended after " + std::to_string(framesRead) +
                              " frames but the other goes on (truncated or corrupt)");
  require(framesDeclared <= 0 || framesRead >= framesDeclared,
          description + ": frame " + std::to_string(framesRead) + " of the " + std::to_string(framesDeclared) +
              " its header declares cannot be read (the file is truncated or corrupt)");
}

class VideoPairSource : public StereoFrameSource {
public:
  VideoPairSource(const std::string& leftVideo, const std::string& rightVideo)
      : left_(openVideo(leftVideo)), right_(openVideo(rightVideo)),
        description_("videos '" + leftVideo + "' and '" + rightVideo + "'") {
    const cv::Size l(headerInt(left_, cv::CAP_PROP_FRAME_WIDTH), headerInt(left_, cv::CAP_PROP_FRAME_HEIGHT));
    const cv::Size r(headerInt(right_, cv::CAP_PROP_FRAME_WIDTH), headerInt(right_, cv::CAP_PROP_FRAME_HEIGHT));
    require(l == r, "the left video is " + sizeText(l) + " but the right one is " + sizeText(r));
    size_ = l;
    // Unequal lengths are refused, as unequal frame folders are: the pairs would not be the same moments.
    const int leftFrames = headerInt(left_, cv::CAP_PROP_FRAME_COUNT);
    const int rightFrames = headerInt(right_, cv::CAP_PROP_FRAME_COUNT);
    require(leftFrames <= 0 || rightFrames <= 0 || leftFrames == rightFrames,
            "the left video '" + leftVideo + "' has " + std::to_string(leftFrames) + " frames but the right video '" +
                rightVideo + "' has " + std::to_string(rightFrames));
    frames_ = leftFrames > 0 ? leftFrames : -1;
  }
  bool next(StereoFrame& frame) override {
    cv::Mat left, right;
    const bool leftRead = left_.read(left) && !left.empty();
    const bool rightRead = right_.read(right) && !right.empty();
    if (!leftRead || !rightRead) {
      requireNotCutShort(description_, index_, frames_, leftRead != rightRead);
      return false;
    }
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

class PackedVideoSource : public StereoFrameSource {
public:
  PackedVideoSource(const std::string& video, VideoLayout layout)
      : capture_(openVideo(video)), layout_(layout),
        description_(std::string(layout == VideoLayout::SideBySide ? "side-by-side" : videoLayoutName(layout)) +
                     " video '" + video + "'") {
    const cv::Size packed(headerInt(capture_, cv::CAP_PROP_FRAME_WIDTH),
                          headerInt(capture_, cv::CAP_PROP_FRAME_HEIGHT));
    try {
      size_ = eyeSizeOf(packed, layout);
    } catch (const Error& e) {
      throw Error("video '" + video + "': " + e.what());
    }
    packedSize_ = packed;
    const int frames = headerInt(capture_, cv::CAP_PROP_FRAME_COUNT);
    frames_ = frames > 0 ? frames : -1;
  }
  bool next(StereoFrame& frame) override {
    cv::Mat packed;
    if (!capture_.read(packed) || packed.empty()) {
      requireNotCutShort(description_, index_, frames_, false);
      return false;
    }
    require(packed.size() == packedSize_,
            "video frame " + std::to_string(index_) + " has an unexpected size " + sizeText(packed.size()));
    frame.index = index_;
    frame.timeS = frameTimeS(capture_, index_);
    cv::Mat left, right;
    unpackStereoFrame(packed, layout_, left, right);
    frame.left = toBgr8(left, "video frame");
    frame.right = toBgr8(right, "video frame");
    ++index_;
    return true;
  }
  int frameCount() const override { return frames_; }
  cv::Size frameSize() const override { return size_; }
  std::string description() const override { return description_; }

private:
  cv::VideoCapture capture_;
  VideoLayout layout_;
  std::string description_;
  cv::Size size_, packedSize_;
  int frames_ = -1;
  int index_ = 0;
};

/// One live 3D video: the newest packed frame each time.
class LivePackedSource : public StereoFrameSource {
public:
  LivePackedSource(const std::string& input, VideoLayout layout) : capture_(input), layout_(layout) {
    size_ = eyeSizeOf(capture_.frameSize(), layout);
  }
  bool next(StereoFrame& frame) override {
    cv::Mat packed;
    if (!capture_.nextNewest(packed, frame.timeS)) return false;
    require(packed.size() == capture_.frameSize(), capture_.description() + " changed its frame size to " +
                                                       sizeText(packed.size()));
    cv::Mat left, right;
    unpackStereoFrame(packed, layout_, left, right);
    frame.index = index_++;
    frame.left = toBgr8(left, "live frame");
    frame.right = toBgr8(right, "live frame");
    return true;
  }
  int frameCount() const override { return -1; }
  cv::Size frameSize() const override { return size_; }
  std::string description() const override {
    return std::string(videoLayoutName(layout_)) + " live video from " + capture_.description();
  }
  bool isLive() const override { return true; }
  long long droppedFrames() const override { return capture_.droppedFrames(); }
  void interrupt() override { capture_.interrupt(); }

private:
  LiveVideoCapture capture_;
  VideoLayout layout_;
  cv::Size size_;
  int index_ = 0;
};

/// Two live inputs: the newest frame of each (both eyes' captures are assumed synchronised, as a stereo capture
/// card's two channels are); the pair's time is the left frame's.
class LivePairSource : public StereoFrameSource {
public:
  LivePairSource(const std::string& left, const std::string& right) : left_(left), right_(right) {
    require(left_.frameSize() == right_.frameSize(), "the left live video is " + sizeText(left_.frameSize()) +
                                                         " but the right one is " + sizeText(right_.frameSize()));
  }
  bool next(StereoFrame& frame) override {
    double rightTimeS = 0;
    cv::Mat left, right;
    if (!left_.nextNewest(left, frame.timeS) || !right_.nextNewest(right, rightTimeS)) return false;
    frame.index = index_++;
    frame.left = toBgr8(left, "live frame");
    frame.right = toBgr8(right, "live frame");
    return true;
  }
  int frameCount() const override { return -1; }
  cv::Size frameSize() const override { return left_.frameSize(); }
  std::string description() const override { return "live videos " + left_.description() + " and " + right_.description(); }
  bool isLive() const override { return true; }
  long long droppedFrames() const override { return std::max(left_.droppedFrames(), right_.droppedFrames()); }
  void interrupt() override {
    left_.interrupt();
    right_.interrupt();
  }

private:
  LiveVideoCapture left_, right_;
  int index_ = 0;
};

bool isLiveInput(const std::string& video) { return videoInputKind(video) != VideoInputKind::File; }

}  // namespace

std::unique_ptr<StereoFrameSource> StereoFrameSource::openFrameFolders(const std::string& leftFolder,
                                                                       const std::string& rightFolder, double fps) {
  return std::make_unique<FrameFolderSource>(leftFolder, rightFolder, fps);
}

std::unique_ptr<StereoFrameSource> StereoFrameSource::openVideoPair(const std::string& leftVideo,
                                                                    const std::string& rightVideo) {
  require(isLiveInput(leftVideo) == isLiveInput(rightVideo),
          "the left and right videos must both be files or both be live (device or pipeline)");
  if (isLiveInput(leftVideo)) return std::make_unique<LivePairSource>(leftVideo, rightVideo);
  return std::make_unique<VideoPairSource>(leftVideo, rightVideo);
}

std::unique_ptr<StereoFrameSource> StereoFrameSource::openStereoVideo(const std::string& video, VideoLayout layout) {
  if (isLiveInput(video)) return std::make_unique<LivePackedSource>(video, layout);
  return std::make_unique<PackedVideoSource>(video, layout);
}

std::unique_ptr<StereoFrameSource> StereoFrameSource::openSideBySideVideo(const std::string& video) {
  return openStereoVideo(video, VideoLayout::SideBySide);
}

}  // namespace tissuemosaic
