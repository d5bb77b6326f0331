#pragma once
/// @file IgtLinkVideoSource.h
/// @brief Stereo video from an OpenIGTLink server, as a PLUS server sends video (docs/OPENIGTLINK.md): IMAGE
/// messages of two device names (left and right eye, paired by time stamp) or of one side-by-side (or other
/// StereoVideoLayout) stream. A live source: a thread receives at the server's pace and keeps the newest frames;
/// frames the reconstruction was too slow for are dropped and counted. Other messages (PLUS's STATUS keep-alives,
/// TRANSFORMs) are skipped; bodies that fail their CRC are counted and skipped; a malformed message (fields that
/// contradict each other or the bytes that came, IgtLinkMessageCheck.h) is skipped, counted and told through
/// IgtLinkVideoInput::warn; an IMAGE in a format TissueMosaic does not read, or a header declaring an impossible
/// body, ends the input with an Error that says so.
#include "IO/StereoFrameSource.h"

#include <functional>
#include <memory>
#include <string>

namespace tissuemosaic::igtlink {

struct IgtLinkVideoInput {
  std::string host = "localhost";
  int port = 18944;
  std::string leftName, rightName;  ///< two IMAGE streams ...
  std::string packedName;           ///< ... or one with both eyes
  VideoLayout layout = VideoLayout::SideBySide;  ///< of the packed stream
  double pairToleranceS = 0.005;    ///< left and right time stamps this close make a pair
  double connectTimeoutS = 10.0;    ///< connecting, and waiting for the first frame
  /// Told of the first malformed messages skipped (from the receiving thread); may be empty.
  std::function<void(const std::string&)> warn;

  /// "HOST:PORT" (or ":PORT" / "PORT" for localhost). Throws Error for anything else.
  static void parseAddress(const std::string& address, std::string& host, int& port);
};

/// What an OpenIGTLink source skipped (the source openIgtLinkVideo returns implements it: dynamic_cast).
class IgtLinkInputCounters {
public:
  virtual ~IgtLinkInputCounters() = default;
  virtual long long framesFailingCrc() const = 0;
  virtual long long malformedMessages() const = 0;
  virtual std::string lastMalformed() const = 0;  ///< what was wrong with the last one ("" when none)
};

/// Connects and waits for the first frame (its size is frameSize()). Throws Error when the server cannot be reached
/// or sends no frame of the named streams within connectTimeoutS.
std::unique_ptr<StereoFrameSource> openIgtLinkVideo(const IgtLinkVideoInput& input);

}  // namespace tissuemosaic::igtlink
