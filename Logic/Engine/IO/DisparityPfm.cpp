#include "DisparityPfm.h"

#include "AtomicFile.h"
#include "ByteOrder.h"
#include "Core/Error.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace tissuemosaic {
namespace {

void swapBytes(float* values, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    std::uint8_t b[4];
    std::memcpy(b, &values[i], 4);
    std::swap(b[0], b[3]);
    std::swap(b[1], b[2]);
    std::memcpy(&values[i], b, 4);
  }
}

}  // namespace

void writePfm(const std::string& path, const cv::Mat& image) {
  require(!image.empty() && image.type() == CV_32FC1,
          "cannot write PFM '" + path + "': the image must be a non-empty CV_32FC1 map");
  writeStreamAtomically(path, "PFM", [&](std::ostream& file) {
    const bool little = hostIsLittleEndian();
    file << "Pf\n" << image.cols << " " << image.rows << "\n" << (little ? "-1.0" : "1.0") << "\n";
    for (int y = image.rows - 1; y >= 0; --y)  // PFM stores the bottom row first
      file.write(reinterpret_cast<const char*>(image.ptr<float>(y)), static_cast<std::streamsize>(image.cols * sizeof(float)));
  });
}

cv::Mat readPfm(const std::string& path) {
  const std::string context = "cannot read PFM '" + path + "': ";
  std::ifstream file(path, std::ios::binary);
  require(file.good(), context + "file does not exist or is not readable");
  std::string magic;
  file >> magic;
  require(magic == "Pf" || magic == "PF", context + "not a PFM file (it must start with 'Pf' or 'PF')");
  long long width = 0, height = 0;
  double scale = 0;
  file >> width >> height >> scale;
  require(!file.fail(), context + "malformed header (expected width, height and scale)");
  require(width > 0 && height > 0 && width <= (1 << 20) && height <= (1 << 20),
          context + "implausible image size " + std::to_string(width) + "x" + std::to_string(height));
  require(scale != 0 && std::isfinite(scale), context + "the scale in the header must be a non-zero number");
  // Exactly one whitespace character separates the header from the data.
  const int separator = file.get();
  require(separator == '\n' || separator == ' ' || separator == '\r' || separator == '\t',
          context + "malformed header (no whitespace after the scale)");
  if (separator == '\r' && file.peek() == '\n') file.get();  // tolerate CRLF headers written on Windows

  const int channels = magic == "PF" ? 3 : 1;
  // The floats must be in the file before they are allocated: a 20-byte header may declare 2^20 x 2^20 pixels.
  const std::streampos dataStart = file.tellg();
  file.seekg(0, std::ios::end);
  const long long dataBytes = static_cast<long long>(file.tellg() - dataStart);
  file.seekg(dataStart);
  if (dataBytes < width * height * channels * static_cast<long long>(sizeof(float))) {
    throw Error(context + "the file is truncated (" + std::to_string(width) + "x" + std::to_string(height) +
                " floats expected, " + std::to_string(dataBytes) + " bytes found)");
  }
  cv::Mat image(static_cast<int>(height), static_cast<int>(width), CV_MAKETYPE(CV_32F, channels));
  const std::streamsize rowBytes = static_cast<std::streamsize>(width * channels * sizeof(float));
  for (int y = image.rows - 1; y >= 0; --y) {
    file.read(reinterpret_cast<char*>(image.ptr<float>(y)), rowBytes);
    if (file.gcount() != rowBytes) {
      throw Error(context + "the file is truncated (" + std::to_string(width) + "x" + std::to_string(height) +
                  " floats expected)");
    }
  }
  const bool fileLittle = scale < 0;
  if (fileLittle != hostIsLittleEndian()) swapBytes(image.ptr<float>(), image.total() * channels);
  return image;
}

}  // namespace tissuemosaic
