#pragma once
/// @file IgtLinkMessageCheck.h
/// @brief Checks of received OpenIGTLink bytes before anything else reads them (docs/OPENIGTLINK.md, "What is
/// checked"): the 58-byte message header (its body size as the 64-bit unsigned number it is on the wire), and an
/// IMAGE body (every field of its 72-byte image header against the bytes that came). Plain functions on raw bytes,
/// no socket and no OpenIGTLink class, so that they can be unit-tested and fuzzed (Testing/Fuzz/fuzz_igtl_*).
#include <cstddef>
#include <cstdint>
#include <string>

namespace tissuemosaic::igtlink {

inline constexpr std::size_t kHeaderBytes = 58;       ///< IGTL_HEADER_SIZE
inline constexpr std::size_t kImageHeaderBytes = 72;  ///< IGTL_IMAGE_HEADER_SIZE

/// The fields of a message header, as sent (big-endian on the wire).
struct HeaderFields {
  std::uint16_t version = 0;
  std::string type, name;      ///< up to the first NUL (12 and 20 bytes at most)
  std::uint64_t timeStamp = 0; ///< seconds in the high 32 bits, fraction of a second in the low 32
  std::uint64_t bodyBytes = 0;
  std::uint64_t bodyCrc = 0;
  double timeS() const;
};

/// Reads the kHeaderBytes at `bytes`. False, with `problem` saying why, when the body is larger than
/// largestBodyBytes (no OpenIGTLink stream, or one this reader will not hold in memory).
bool checkHeader(const unsigned char* bytes, std::uint64_t largestBodyBytes, HeaderFields& header,
                 std::string& problem);

/// The fields of an IMAGE body's image header.
struct ImageFields {
  int components = 0, scalarType = 0, scalarBytes = 0, endian = 0, coordinates = 0;
  int size[3] = {0, 0, 0};           ///< the whole volume, pixels
  int subOffset[3] = {0, 0, 0};      ///< the sub-volume this message carries
  int subSize[3] = {0, 0, 0};
  std::uint64_t pixelBytes = 0;      ///< sub-volume pixels x components x scalar bytes
  bool wholeVolume() const;
};

enum class ImageCheck {
  Good,         ///< consistent: pixelBytes of pixels follow the image header
  Malformed,    ///< fields that contradict each other or the body (skip the message)
};

/// Checks the image header at the start of an IMAGE body of bodyBytes bytes (reads min(bodyBytes, 72) bytes at
/// `body`, so it may run before the pixels are received): a body shorter than the image header, an unknown
/// version, scalar type, endianness or coordinate system, an empty volume or sub-volume, a sub-volume not within the
/// volume, or a body with fewer or more bytes than the image header and the sub-volume's pixels are Malformed, with
/// `problem` naming the fields.
ImageCheck checkImageBody(const unsigned char* body, std::uint64_t bodyBytes, ImageFields& image,
                          std::string& problem);

}  // namespace tissuemosaic::igtlink
