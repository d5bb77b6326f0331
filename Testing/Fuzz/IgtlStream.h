#pragma once
/// @file IgtlStream.h
/// @brief What the OpenIGTLink fuzz targets share: the fuzzer's bytes as the stream a socket would deliver, and
/// CRC-64s filled in where the input leaves them 0, so that mutated bodies get past the CRC to the checks behind it
/// (an input with a non-zero CRC keeps it: the CRC-failure path is fuzzed too).
#include "IgtLinkMessageCheck.h"
#include "IgtLinkMessageReader.h"

#include <igtl_util.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace tissuemosaic::fuzz {

class IgtlStream {
public:
  IgtlStream(const std::uint8_t* data, std::size_t size) : bytes_(data, data + size) { signMessages(); }

  /// Exactly `count` bytes, or false at the end (as a socket that closed).
  igtlink::ReceiveBytes receiver() {
    return [this](void* out, std::size_t count) {
      if (count > bytes_.size() - at_) return false;
      if (count == 0) return true;
      std::memcpy(out, bytes_.data() + at_, count);
      at_ += count;
      return true;
    };
  }

private:
  void signMessages() {
    constexpr std::size_t crcAt = 50, sizeAt = 42;
    for (std::size_t at = 0; at + igtlink::kHeaderBytes <= bytes_.size();) {
      std::uint64_t body = 0, crc = 0;
      for (int i = 0; i < 8; ++i) body = body << 8 | bytes_[at + sizeAt + i];
      for (int i = 0; i < 8; ++i) crc = crc << 8 | bytes_[at + crcAt + i];
      const std::size_t start = at + igtlink::kHeaderBytes;
      const std::size_t available = static_cast<std::size_t>(std::min<std::uint64_t>(body, bytes_.size() - start));
      if (crc == 0) {
        crc = crc64(bytes_.data() + start, available, 0);
        for (int i = 7; i >= 0; --i, crc >>= 8) bytes_[at + crcAt + i] = static_cast<std::uint8_t>(crc & 0xff);
      }
      if (body > bytes_.size() - start) break;
      at = start + static_cast<std::size_t>(body);
    }
  }

  std::vector<std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

}  // namespace tissuemosaic::fuzz
