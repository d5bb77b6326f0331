// What the OpenIGTLink video client (`reconstruct --igtl-input`) receives from a server, message by message through
// IgtLinkVideoReader as IgtLinkVideoSource's thread reads them: headers, IMAGEs of its two streams (named "Left" and
// "Right"), and whatever else a server sends (STATUS keep-alives, TRANSFORMs), until the stream ends or cannot be
// read on. Any outcome is fine; a crash, a sanitizer report, a leak or a hang is a finding.
#include "IgtlStream.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::IgtlStream stream(data, size);
  const igtlink::ReceiveBytes receive = stream.receiver();
  igtlink::IgtLinkVideoReader reader({"Left", "Right"});
  for (;;) {  // every read takes at least a header's 58 bytes: the loop ends
    igtlink::IgtLinkVideoReader::Frame frame;
    std::string problem;
    const igtlink::ReadOutcome outcome = reader.read(receive, frame, problem);
    if (outcome == igtlink::ReadOutcome::Ended || outcome == igtlink::ReadOutcome::Failed) break;
    if (outcome == igtlink::ReadOutcome::Message && (frame.bgr.type() != CV_8UC3 || frame.bgr.empty())) __builtin_trap();
  }
  return 0;
}
