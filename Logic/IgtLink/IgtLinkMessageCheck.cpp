#include "IgtLinkMessageCheck.h"

#include <algorithm>
#include <cstring>

namespace tissuemosaic::igtlink {
namespace {

std::uint64_t bigEndian(const unsigned char* bytes, int count) {
  std::uint64_t value = 0;
  for (int i = 0; i < count; ++i) value = value << 8 | bytes[i];
  return value;
}

/// A fixed-size name field up to its first NUL (it need not have one).
std::string field(const unsigned char* bytes, std::size_t size) {
  const auto* text = reinterpret_cast<const char*>(bytes);
  return std::string(text, std::find(text, text + size, '\0'));
}

/// Bytes per scalar of the protocol's scalar types; 0 for an unknown type.
int scalarBytes(int type) {
  switch (type) {
    case 2: case 3: return 1;     // int8, uint8
    case 4: case 5: return 2;     // int16, uint16
    case 6: case 7: case 10: return 4;  // int32, uint32, float32
    case 11: return 8;            // float64
    default: return 0;
  }
}

std::string triple(const int v[3]) {
  return std::to_string(v[0]) + "x" + std::to_string(v[1]) + "x" + std::to_string(v[2]);
}

}  // namespace

double HeaderFields::timeS() const {
  return static_cast<double>(timeStamp >> 32) + static_cast<double>(timeStamp & 0xffffffffu) / 4294967296.0;
}

bool checkHeader(const unsigned char* bytes, std::uint64_t largestBodyBytes, HeaderFields& header,
                 std::string& problem) {
  header.version = static_cast<std::uint16_t>(bigEndian(bytes, 2));
  header.type = field(bytes + 2, 12);
  header.name = field(bytes + 14, 20);
  header.timeStamp = bigEndian(bytes + 34, 8);
  header.bodyBytes = bigEndian(bytes + 42, 8);
  header.bodyCrc = bigEndian(bytes + 50, 8);
  if (header.bodyBytes > largestBodyBytes) {
    std::string type = header.type;  // printable, as a hostile peer's bytes go into a message
    for (char& c : type) c = c >= 32 && c < 127 ? c : '?';
    problem = "a message of " + std::to_string(header.bodyBytes) + " bytes (at most " +
              std::to_string(largestBodyBytes) + " are read; type '" + type +
              "'): not an OpenIGTLink stream, or a broken one";
    return false;
  }
  return true;
}

bool ImageFields::wholeVolume() const {
  for (int a = 0; a < 3; ++a)
    if (subOffset[a] != 0 || subSize[a] != size[a]) return false;
  return true;
}

ImageCheck checkImageBody(const unsigned char* body, std::uint64_t bodyBytes, ImageFields& image,
                          std::string& problem) {
  image = ImageFields{};
  if (bodyBytes < kImageHeaderBytes) {
    problem = "a body of " + std::to_string(bodyBytes) + " bytes, shorter than the " +
              std::to_string(kImageHeaderBytes) + "-byte image header";
    return ImageCheck::Malformed;
  }
  // Layout (igtl_image.h): version u16, components u8, scalar type u8, endian u8, coordinates u8, size u16[3],
  // matrix f32[12], sub-volume offset u16[3], sub-volume size u16[3]; all big-endian.
  const int version = static_cast<int>(bigEndian(body, 2));
  image.components = body[2];
  image.scalarType = body[3];
  image.endian = body[4];
  image.coordinates = body[5];
  for (int a = 0; a < 3; ++a) {
    image.size[a] = static_cast<int>(bigEndian(body + 6 + 2 * a, 2));
    image.subOffset[a] = static_cast<int>(bigEndian(body + 60 + 2 * a, 2));
    image.subSize[a] = static_cast<int>(bigEndian(body + 66 + 2 * a, 2));
  }
  image.scalarBytes = scalarBytes(image.scalarType);
  auto malformed = [&](const std::string& why) {
    problem = why;
    return ImageCheck::Malformed;
  };
  if (version != 1) return malformed("image header version " + std::to_string(version) + " (1 is known)");
  if (image.scalarBytes == 0) return malformed("unknown scalar type " + std::to_string(image.scalarType));
  if (image.endian != 1 && image.endian != 2) return malformed("unknown endianness " + std::to_string(image.endian));
  if (image.coordinates != 1 && image.coordinates != 2)
    return malformed("unknown coordinate system " + std::to_string(image.coordinates));
  if (image.components == 0) return malformed("0 components per pixel");
  for (int a = 0; a < 3; ++a) {
    if (image.size[a] == 0 || image.subSize[a] == 0)
      return malformed("an empty image (" + triple(image.size) + " pixels, sub-volume " + triple(image.subSize) + ")");
    // In 32 bits: each term is below 2^16.
    if (image.subOffset[a] + image.subSize[a] > image.size[a])
      return malformed("a sub-volume (offset " + triple(image.subOffset) + ", size " + triple(image.subSize) +
                       ") outside the " + triple(image.size) + " image");
  }
  // At most 2^48 pixels x 255 components x 8 bytes < 2^64: no overflow.
  image.pixelBytes = static_cast<std::uint64_t>(image.subSize[0]) * image.subSize[1] * image.subSize[2] *
                     image.components * image.scalarBytes;
  if (bodyBytes - kImageHeaderBytes != image.pixelBytes)
    return malformed(triple(image.subSize) + " pixels of " + std::to_string(image.components) + " x " +
                     std::to_string(image.scalarBytes) + " bytes need " + std::to_string(image.pixelBytes) +
                     " bytes, the body holds " + std::to_string(bodyBytes - kImageHeaderBytes));
  return ImageCheck::Good;
}

}  // namespace tissuemosaic::igtlink
