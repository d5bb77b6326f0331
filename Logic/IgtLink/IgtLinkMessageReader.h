#pragma once
/// @file IgtLinkMessageReader.h
/// @brief Reads whole OpenIGTLink messages from a byte stream, every field checked against the bytes that came
/// (IgtLinkMessageCheck.h) before anything else reads them: the video client's frames (IgtLinkVideoSource), and what
/// the server reads from its clients (IgtLinkServer). The stream is a function, so that a socket, a test or a fuzz
/// target (Testing/Fuzz/fuzz_igtl_*) can feed it. A bad message is consumed whole and skipped, so that the stream
/// stays in step; only a header whose body size cannot be an OpenIGTLink message's ends it.
#include "IgtLinkMessageCheck.h"

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace tissuemosaic::igtlink {

/// Receives exactly `bytes` bytes into `data`; false when the stream ended first (closed, broken, stopped).
using ReceiveBytes = std::function<bool(void* data, std::size_t bytes)>;

/// Receives `bytes` bytes and throws them away, in pieces of a fixed buffer (a large body costs no memory).
bool discardBytes(const ReceiveBytes& receive, std::uint64_t bytes);

/// Largest body a message may declare (the body size is 64-bit on the wire): beyond it the stream is not read on.
inline constexpr std::uint64_t kLargestMessageBytes = 256ull << 20;
/// Largest IMAGE body the video client holds in memory (7680 x 2160 RGBA, a 4K side-by-side frame, fits).
inline constexpr std::uint64_t kLargestImageBytes = 80ull << 20;

enum class ReadOutcome {
  Message,    ///< a whole message read (the video reader: a frame of one of its streams)
  Skipped,    ///< another type or device name, consumed unread
  CrcFailed,  ///< the body's CRC-64 differs from the header's: skipped
  Malformed,  ///< fields that contradict each other or the body (problem says which): skipped
  Failed,     ///< the stream cannot be read on (problem says why)
  Ended,      ///< the stream ended (closed, or stopped)
};

/// The server's side: one message from a client, its header checked and its body discarded (the server uses
/// nothing a client sends). Message, Failed (a body beyond largestBodyBytes) or Ended.
ReadOutcome readClientMessage(const ReceiveBytes& receive, std::string& problem,
                              std::uint64_t largestBodyBytes = kLargestMessageBytes);

/// The video client's side: IMAGE messages of the named streams, as 8-bit BGR frames.
class IgtLinkVideoReader {
public:
  struct Frame {
    int stream = -1;  ///< index into the names given
    double timeS = 0;
    cv::Mat bgr;
  };
  explicit IgtLinkVideoReader(std::vector<std::string> streamNames)
      : names_(std::move(streamNames)), sizes_(names_.size()) {}

  /// The next message. Message: `frame` holds a frame. A stream's frames keep its first frame's size: an IMAGE of
  /// another size is Malformed and skipped before its pixels are received (memory stays bounded by the first). Failed: an IMAGE of a stream whose format TissueMosaic does
  /// not read (not 8-bit, not 1, 3 or 4 components, not 2D, part of an image), or a message too large to be one.
  ReadOutcome read(const ReceiveBytes& receive, Frame& frame, std::string& problem);

private:
  std::vector<std::string> names_;
  std::vector<cv::Size> sizes_;      ///< per stream: its first frame's size (empty until then)
  std::vector<unsigned char> body_;  ///< reused: its capacity stays at the largest frame's
};

}  // namespace tissuemosaic::igtlink
