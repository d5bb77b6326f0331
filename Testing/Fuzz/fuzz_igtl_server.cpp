// What the OpenIGTLink server (`reconstruct --igtl-port`, the app's OpenIGTLink tab) reads from a client: message
// by message through readClientMessage, as each client's receiver thread reads them, until the stream ends or the
// client would be dropped. A crash, a sanitizer report, a leak or a hang is a finding.
#include "IgtlStream.h"

using namespace tissuemosaic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::IgtlStream stream(data, size);
  const igtlink::ReceiveBytes receive = stream.receiver();
  std::string problem;
  while (igtlink::readClientMessage(receive, problem) == igtlink::ReadOutcome::Message) {
  }
  return 0;
}
