// The raw-byte checks of received OpenIGTLink messages (IgtLinkMessageCheck.h), on bytes built by hand: each field
// against the bytes that came, and a good message next to each bad one (so that a check refusing everything fails).
#include "FakeIgtlPeer.h"
#include "IgtLinkMessageCheck.h"
#include "IgtLinkMessageReader.h"

#include <gtest/gtest.h>

namespace tissuemosaic::igtlink {
namespace {

using namespace testing;

/// The bytes of `stream` from `at` on, as a socket would give them (at moves on; false past the end).
ReceiveBytes receiveFrom(const Bytes& stream, std::size_t& at) {
  return [&stream, &at](void* data, std::size_t bytes) {
    if (bytes > stream.size() - at) return false;
    std::memcpy(data, stream.data() + at, bytes);
    at += bytes;
    return true;
  };
}

TEST(IgtLinkMessageCheck, HeaderFieldsAndTheBodySizeAs64Bits) {
  const Bytes bytes = header("IMAGE", "Video", 12.5, (std::uint64_t(1) << 32) + 5, 0x0123456789abcdefull);
  HeaderFields h;
  std::string problem;
  ASSERT_TRUE(checkHeader(bytes.data(), ~std::uint64_t(0), h, problem)) << problem;
  EXPECT_EQ(h.version, 1);
  EXPECT_EQ(h.type, "IMAGE");
  EXPECT_EQ(h.name, "Video");
  EXPECT_DOUBLE_EQ(h.timeS(), 12.5);
  EXPECT_EQ(h.bodyBytes, 4294967301ull) << "not truncated to 32 bits";
  EXPECT_EQ(h.bodyCrc, 0x0123456789abcdefull);
  EXPECT_FALSE(checkHeader(bytes.data(), kLargestMessageBytes, h, problem));
  EXPECT_NE(problem.find("a message of 4294967301 bytes (at most 268435456 are read; type 'IMAGE')"), std::string::npos) << problem;
  const Bytes huge = header("STATUS", "", 0, std::uint64_t(1) << 62, 0);
  EXPECT_FALSE(checkHeader(huge.data(), kLargestMessageBytes, h, problem));
  EXPECT_NE(problem.find("4611686018427387904"), std::string::npos) << problem;
  // Names that fill their whole field (no NUL) end at the field.
  const Bytes full = header("ABCDEFGHIJKLMN", "01234567890123456789XYZ", 0, 0, 0);
  ASSERT_TRUE(checkHeader(full.data(), 0, h, problem));
  EXPECT_EQ(h.type, "ABCDEFGHIJKL");
  EXPECT_EQ(h.name, "01234567890123456789");
}

ImageCheck check(const Bytes& body, std::string& problem) {
  ImageFields fields;
  return checkImageBody(body.data(), body.size(), fields, problem);
}

TEST(IgtLinkMessageCheck, ImageSizeTimesComponentsTimesScalarBytesMustBeTheBody) {
  std::string problem;
  ImageHeader h;
  h.size[0] = 4;
  h.size[1] = 2;
  EXPECT_EQ(check(imageBody(h, Bytes(4 * 2 * 3)), problem), ImageCheck::Good) << problem;
  EXPECT_EQ(check(imageBody(h, Bytes(4 * 2 * 3 - 1)), problem), ImageCheck::Malformed);
  EXPECT_EQ(check(imageBody(h, Bytes(4 * 2 * 3 + 1)), problem), ImageCheck::Malformed);
  h.scalarType = 11;  // float64: 8 bytes a component
  EXPECT_EQ(check(imageBody(h, Bytes(4 * 2 * 3 * 8)), problem), ImageCheck::Good) << problem;
  h.size[0] = h.size[1] = h.size[2] = 65535;  // the largest volume: no overflow in the product
  h.components = 255;
  EXPECT_EQ(check(imageBody(h, Bytes(64)), problem), ImageCheck::Malformed);
  // 65535^3 pixels x 255 components x 8 bytes, exactly (below 2^64).
  EXPECT_NE(problem.find("need 574182667690965000 bytes, the body holds 64"), std::string::npos) << problem;
}

TEST(IgtLinkMessageCheck, SubVolumeWithinTheVolume) {
  std::string problem;
  ImageHeader h;
  h.size[0] = 10;
  h.size[1] = 10;
  h.subOffset[0] = 6;
  h.subSize[0] = 4;  // columns 6..9: at the edge, inside
  h.subSize[1] = 10;
  ImageFields fields;
  const Bytes inside = imageBody(h, Bytes(4 * 10 * 3));
  ASSERT_EQ(checkImageBody(inside.data(), inside.size(), fields, problem), ImageCheck::Good) << problem;
  EXPECT_FALSE(fields.wholeVolume());
  h.subOffset[0] = 7;  // columns 7..10: one outside
  EXPECT_EQ(check(imageBody(h, Bytes(4 * 10 * 3)), problem), ImageCheck::Malformed);
  EXPECT_NE(problem.find("outside the 10x10x1 image"), std::string::npos) << problem;
  h.subOffset[0] = 65535;  // offset + size beyond 16 bits
  EXPECT_EQ(check(imageBody(h, Bytes(4 * 10 * 3)), problem), ImageCheck::Malformed);
}

TEST(IgtLinkMessageCheck, ShortBodiesAndUnknownFieldValues) {
  std::string problem;
  for (std::size_t bytes : {0, 1, 40, 71}) {
    const Bytes body(bytes, 0);
    EXPECT_EQ(check(body, problem), ImageCheck::Malformed) << bytes;
    EXPECT_NE(problem.find("shorter than the 72-byte image header"), std::string::npos) << problem;
  }
  const auto malformedWith = [&](auto change, const std::string& reason) {
    ImageHeader h;
    h.size[0] = h.size[1] = 2;
    change(h);
    EXPECT_EQ(check(imageBody(h, Bytes(2 * 2 * 3)), problem), ImageCheck::Malformed) << reason;
    EXPECT_NE(problem.find(reason), std::string::npos) << problem;
  };
  malformedWith([](ImageHeader& h) { h.version = 2; }, "image header version 2");
  malformedWith([](ImageHeader& h) { h.scalarType = 12; }, "unknown scalar type 12");
  malformedWith([](ImageHeader& h) { h.endian = 3; }, "unknown endianness 3");
  malformedWith([](ImageHeader& h) { h.coordinates = 0; }, "unknown coordinate system 0");
  malformedWith([](ImageHeader& h) { h.components = 0; }, "0 components");
  malformedWith([](ImageHeader& h) { h.size[2] = 0; }, "an empty image");
}

TEST(IgtLinkMessageCheck, ReaderSkipsAMalformedImageWholeAndReadsTheNext) {
  // The stream stays in step: the bad message is consumed to its declared end.
  ImageHeader bad;
  bad.size[0] = bad.size[1] = 65535;
  ImageHeader good;
  good.size[0] = 4;
  good.size[1] = 2;
  Bytes stream = message("IMAGE", "Video", 1.0, imageBody(bad, Bytes(64, 9)));
  const Bytes next = message("IMAGE", "Video", 2.0, imageBody(good, Bytes(4 * 2 * 3, 200)));
  stream.insert(stream.end(), next.begin(), next.end());
  std::size_t at = 0;
  const ReceiveBytes receive = receiveFrom(stream, at);
  IgtLinkVideoReader reader({"Video"});
  IgtLinkVideoReader::Frame frame;
  std::string problem;
  EXPECT_EQ(reader.read(receive, frame, problem), ReadOutcome::Malformed);
  ASSERT_EQ(reader.read(receive, frame, problem), ReadOutcome::Message) << problem;
  EXPECT_EQ(frame.bgr.size(), cv::Size(4, 2));
  EXPECT_DOUBLE_EQ(frame.timeS, 2.0);
  EXPECT_EQ(reader.read(receive, frame, problem), ReadOutcome::Ended);
}

TEST(IgtLinkMessageCheck, ReaderSkipsFramesOfAnotherSizeThanTheStreamsFirst) {
  // Memory stays bounded by the first frame: a larger one is refused before its pixels are received.
  const auto frameOf = [](int width, int height, double timeS) {
    ImageHeader h;
    h.size[0] = width;
    h.size[1] = height;
    return message("IMAGE", "Video", timeS, imageBody(h, Bytes(static_cast<std::size_t>(width) * height * 3, 7)));
  };
  Bytes stream;
  for (const Bytes& m : {frameOf(4, 2, 1.0), frameOf(400, 300, 2.0), frameOf(4, 2, 3.0)})
    stream.insert(stream.end(), m.begin(), m.end());
  std::size_t at = 0;
  const ReceiveBytes receive = receiveFrom(stream, at);
  IgtLinkVideoReader reader({"Video"});
  IgtLinkVideoReader::Frame frame;
  std::string problem;
  ASSERT_EQ(reader.read(receive, frame, problem), ReadOutcome::Message) << problem;
  EXPECT_EQ(reader.read(receive, frame, problem), ReadOutcome::Malformed);
  EXPECT_NE(problem.find("a 400x300x1 image in a stream of 4x2 frames"), std::string::npos) << problem;
  ASSERT_EQ(reader.read(receive, frame, problem), ReadOutcome::Message) << problem;
  EXPECT_DOUBLE_EQ(frame.timeS, 3.0);
}

}  // namespace
}  // namespace tissuemosaic::igtlink
