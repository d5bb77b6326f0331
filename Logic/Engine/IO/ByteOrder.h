#pragma once
/// @file ByteOrder.h
/// @brief Byte order of this machine, for the binary file formats (PFM, PLY).
#include <cstdint>
#include <cstring>

namespace tissuemosaic {

inline bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// The unsigned integer stored in `count` (1 to 4) bytes from `bytes`: most significant byte first (big-endian, as
/// PNG and JPEG headers) or last (little-endian, as BMP headers).
inline std::uint32_t unsignedFromBytes(const std::uint8_t* bytes, int count, bool bigEndian) {
  std::uint32_t value = 0;
  for (int i = 0; i < count; ++i) value = value << 8 | bytes[bigEndian ? i : count - 1 - i];
  return value;
}

}  // namespace tissuemosaic
