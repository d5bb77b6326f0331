#include "IgtLinkMessageReader.h"

#include <igtl_util.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>

namespace tissuemosaic::igtlink {

bool discardBytes(const ReceiveBytes& receive, std::uint64_t bytes) {
  unsigned char piece[64 * 1024];
  while (bytes > 0) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, sizeof piece));
    if (!receive(piece, n)) return false;
    bytes -= n;
  }
  return true;
}

ReadOutcome readClientMessage(const ReceiveBytes& receive, std::string& problem, std::uint64_t largestBodyBytes) {
  unsigned char bytes[kHeaderBytes];
  if (!receive(bytes, sizeof bytes)) return ReadOutcome::Ended;
  HeaderFields header;
  if (!checkHeader(bytes, largestBodyBytes, header, problem)) return ReadOutcome::Failed;
  return discardBytes(receive, header.bodyBytes) ? ReadOutcome::Message : ReadOutcome::Ended;
}

ReadOutcome IgtLinkVideoReader::read(const ReceiveBytes& receive, Frame& frame, std::string& problem) {
  unsigned char headerBytes[kHeaderBytes];
  if (!receive(headerBytes, sizeof headerBytes)) return ReadOutcome::Ended;
  HeaderFields header;
  if (!checkHeader(headerBytes, kLargestMessageBytes, header, problem)) return ReadOutcome::Failed;
  const auto named = std::find(names_.begin(), names_.end(), header.name);
  if (header.type != "IMAGE" || header.name.empty() || named == names_.end()) {  // keep-alives, transforms, others
    return discardBytes(receive, header.bodyBytes) ? ReadOutcome::Skipped : ReadOutcome::Ended;
  }
  const std::string what = "IMAGE '" + header.name + "': ";
  auto skip = [&](std::uint64_t received, const std::string& why) {
    problem = what + why;
    return discardBytes(receive, header.bodyBytes - received) ? ReadOutcome::Malformed : ReadOutcome::Ended;
  };
  if (header.bodyBytes > kLargestImageBytes) {
    return skip(0, "a body of " + std::to_string(header.bodyBytes) + " bytes, more than the " +
                       std::to_string(kLargestImageBytes) + " a frame may have");
  }
  // The image header first: the pixels are only received (and memory only taken) for a consistent one.
  const std::size_t headerPart = static_cast<std::size_t>(std::min<std::uint64_t>(header.bodyBytes, kImageHeaderBytes));
  body_.resize(headerPart);
  if (headerPart > 0 && !receive(body_.data(), headerPart)) return ReadOutcome::Ended;
  ImageFields image;
  std::string why;
  if (checkImageBody(body_.data(), header.bodyBytes, image, why) != ImageCheck::Good) return skip(headerPart, why);
  const std::size_t stream = static_cast<std::size_t>(named - names_.begin());
  const cv::Size size(image.size[0], image.size[1]);
  if (!sizes_[stream].empty() && (size != sizes_[stream] || image.size[2] != 1)) {
    return skip(headerPart, "a " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                                "x" + std::to_string(image.size[2]) + " image in a stream of " +
                                std::to_string(sizes_[stream].width) + "x" + std::to_string(sizes_[stream].height) +
                                " frames");
  }
  // Grown as the pixels come, so that a body declared but never sent takes no memory.
  const auto bodyBytes = static_cast<std::size_t>(header.bodyBytes);
  for (std::size_t have = headerPart; have < bodyBytes;) {
    const std::size_t piece = std::min<std::size_t>(bodyBytes - have, 1 << 20);
    body_.resize(have + piece);
    if (!receive(body_.data() + have, piece)) return ReadOutcome::Ended;
    have += piece;
  }
  if (crc64(body_.data(), body_.size(), 0) != header.bodyCrc) {
    problem = what + "its body fails its CRC-64";
    return ReadOutcome::CrcFailed;
  }
  // Well formed, but not what a video reader takes: PLUS sends video as whole 2D 8-bit frames of 1 or 3 components.
  if (image.size[2] != 1) {
    problem = what + "not a 2D image (" + std::to_string(image.size[0]) + "x" + std::to_string(image.size[1]) + "x" +
              std::to_string(image.size[2]) + ")";
    return ReadOutcome::Failed;
  }
  if (image.scalarType != 3 || (image.components != 1 && image.components != 3 && image.components != 4)) {
    problem = what + "pixels must be 8-bit with 1, 3 or 4 components";
    return ReadOutcome::Failed;
  }
  if (!image.wholeVolume()) {
    problem = what + "a part of an image (sub-volume at " + std::to_string(image.subOffset[0]) + "," +
              std::to_string(image.subOffset[1]) + "): whole frames are needed";
    return ReadOutcome::Failed;
  }
  const cv::Mat pixels(image.size[1], image.size[0], CV_8UC(image.components), body_.data() + kImageHeaderBytes);
  static const int conversions[] = {0, cv::COLOR_GRAY2BGR, 0, cv::COLOR_RGB2BGR, cv::COLOR_RGBA2BGR};
  cv::cvtColor(pixels, frame.bgr, conversions[image.components]);
  sizes_[stream] = size;
  frame.stream = static_cast<int>(stream);
  frame.timeS = header.timeS();
  return ReadOutcome::Message;
}

}  // namespace tissuemosaic::igtlink
