#include "ImageFile.h"

#include "ByteOrder.h"

#include "Core/Error.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <optional>
#include <string>
#include <vector>

namespace tissuemosaic {
namespace {

std::string sizeText(const cv::Mat& image) { return std::to_string(image.cols) + "x" + std::to_string(image.rows); }

using Bytes = std::vector<std::uint8_t>;

bool isJpeg(const Bytes& bytes) { return bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF; }

/// libjpeg decodes a truncated JPEG into a partly grey image with only a warning on stderr ("Premature end of JPEG
/// file"), which OpenCV does not report: a complete JPEG ends with the end-of-image marker FF D9 (trailing padding of
/// zero bytes or line ends tolerated).
bool jpegHasEndMarker(const Bytes& bytes) {
  std::size_t end = bytes.size();
  while (end > 0 && (bytes[end - 1] == 0x00 || bytes[end - 1] == '\n' || bytes[end - 1] == '\r')) --end;
  return end >= 4 && bytes[end - 2] == 0xFF && bytes[end - 1] == 0xD9;
}

struct PixelSize {
  std::uint64_t width = 0, height = 0;
};

std::uint32_t bigEndian(const Bytes& bytes, std::size_t at, int count) {
  return unsignedFromBytes(bytes.data() + at, count, true);
}

std::int32_t littleEndianInt32(const Bytes& bytes, std::size_t at) {
  return static_cast<std::int32_t>(unsignedFromBytes(bytes.data() + at, 4, false));
}

/// The size a PNG, JPEG or BMP header declares (before any pixel is decoded), when it can be found. (A BMP declaring
/// 790 megapixels made OpenCV allocate 2.4 GB before finding the data missing: fuzz_image.)
std::optional<PixelSize> declaredSize(const Bytes& bytes) {
  if (bytes.size() >= 26 && bytes[0] == 'B' && bytes[1] == 'M') {
    // BITMAPINFOHEADER: width and height (negative: rows top-down) at bytes 18 and 22.
    const std::int64_t width = littleEndianInt32(bytes, 18), height = littleEndianInt32(bytes, 22);
    return PixelSize{static_cast<std::uint64_t>(width < 0 ? -width : width),
                     static_cast<std::uint64_t>(height < 0 ? -height : height)};
  }
  static const std::uint8_t pngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (bytes.size() >= 24 && std::equal(pngSignature, pngSignature + 8, bytes.begin())) {
    if (std::string(bytes.begin() + 12, bytes.begin() + 16) != "IHDR") return std::nullopt;  // corrupt: decoder says
    return PixelSize{bigEndian(bytes, 16, 4), bigEndian(bytes, 20, 4)};
  }
  if (!isJpeg(bytes)) return std::nullopt;
  for (std::size_t at = 2; at + 9 < bytes.size();) {  // markers up to the first start-of-frame
    if (bytes[at] != 0xFF) return std::nullopt;
    const std::uint8_t marker = bytes[at + 1];
    if (marker == 0xFF) {
      ++at;
      continue;
    }
    const bool startOfFrame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (startOfFrame) return PixelSize{bigEndian(bytes, at + 7, 2), bigEndian(bytes, at + 5, 2)};
    at += 2 + bigEndian(bytes, at + 2, 2);
  }
  return std::nullopt;
}

}  // namespace

cv::Mat loadImage(const std::string& path, int flags) {
  const std::string context = "cannot read image '" + path + "': ";
  std::error_code ec;
  require(std::filesystem::exists(path, ec), context + "file does not exist");
  require(!std::filesystem::is_directory(path, ec), context + "it is a folder, not a file");
  std::ifstream file(path, std::ios::binary);
  require(file.good(), context + "the file is not readable");
  const Bytes bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (const std::optional<PixelSize> size = declaredSize(bytes)) {
    require(size->width * size->height <= kMaxImagePixels,
            context + "its header declares " + std::to_string(size->width) + "x" + std::to_string(size->height) +
                " pixels, more than the " + std::to_string(kMaxImagePixels / 1000000) + " megapixels a frame may have");
  }
  require(!isJpeg(bytes) || jpegHasEndMarker(bytes), context + "the JPEG file is truncated (no end-of-image marker)");
  cv::Mat image;
  try {
    image = cv::imdecode(bytes, flags);
  } catch (const cv::Exception&) {
    image.release();  // some decoders throw on corrupt data instead of returning empty
  } catch (const std::bad_alloc&) {
    throw Error(context + "not enough memory to decode it");
  }
  require(!image.empty(), context + "the file is not a readable image (corrupt or unsupported format)");
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
