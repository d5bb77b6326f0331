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

}  // namespace tissuemosaic
