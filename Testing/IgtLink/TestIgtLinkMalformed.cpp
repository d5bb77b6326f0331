// Video from a hostile or broken PLUS server (issue 54): a fake server on plain sockets (FakeIgtlPeer.h) sends one
// malformed message, then good 320x240 side-by-side frames, to the OpenIGTLink video source. Each case: no crash; a
// malformed message is skipped, counted and told, and the good frames come; a message that cannot be read on ends
// the input with an Error that names it.
#include "Core/Error.h"
#include "FakeIgtlPeer.h"
#include "IgtLinkVideoSource.h"

#include <gtest/gtest.h>

#include <future>
#include <mutex>
#include <random>

namespace tissuemosaic::igtlink {
namespace {

using namespace testing;

Bytes goodPixels(int index) {
  Bytes pixels(320 * 240 * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<unsigned char>(i * 7 + index);
  return pixels;
}
Bytes goodFrame(int index) { return message("IMAGE", "Video", 10.0 + index / 30.0, imageBody({}, goodPixels(index))); }

struct Outcome {
  bool opened = false;
  std::string error;               ///< when the input ended with an Error
  cv::Size eye;                    ///< of the first frame
  long long malformed = 0, crcFailures = 0;
  std::string lastMalformed;
  std::vector<std::string> warnings;
};

/// Sends `bad` and then three good frames to a side-by-side source reading stream "Video".
Outcome feed(const Bytes& bad) {
  FakeServer server;
  EXPECT_GT(server.port(), 0);
  IgtLinkVideoInput input;
  input.host = "127.0.0.1";
  input.port = server.port();
  input.packedName = "Video";
  input.connectTimeoutS = 5;
  std::mutex warned;
  Outcome outcome;
  input.warn = [&](const std::string& warning) {
    std::lock_guard<std::mutex> lock(warned);
    outcome.warnings.push_back(warning);
  };
  std::future<std::unique_ptr<StereoFrameSource>> opening =
      std::async(std::launch::async, [&] { return openIgtLinkVideo(input); });
  RawSocket client = server.accept();
  EXPECT_TRUE(client.valid());
  client.sendAll(bad);
  for (int i = 0; i < 3; ++i) client.sendAll(goodFrame(i));
  try {
    std::unique_ptr<StereoFrameSource> source = opening.get();
    outcome.opened = true;
    StereoFrame frame;
    EXPECT_TRUE(source->next(frame));
    outcome.eye = frame.left.size();
    const auto* counters = dynamic_cast<const IgtLinkInputCounters*>(source.get());
    EXPECT_NE(counters, nullptr);
    outcome.malformed = counters->malformedMessages();
    outcome.crcFailures = counters->framesFailingCrc();
    outcome.lastMalformed = counters->lastMalformed();
  } catch (const Error& e) {
    outcome.error = e.what();
  }
  return outcome;
}

void expectSkipped(const Outcome& o, const std::string& reason) {
  ASSERT_TRUE(o.opened) << o.error;
  EXPECT_EQ(o.eye, cv::Size(160, 240)) << "the good side-by-side frames after the bad message came";
  EXPECT_EQ(o.malformed, 1);
  EXPECT_NE(o.lastMalformed.find(reason), std::string::npos) << o.lastMalformed;
  ASSERT_EQ(o.warnings.size(), 1u);
  EXPECT_NE(o.warnings[0].find(reason), std::string::npos) << o.warnings[0];
}

void expectError(const Outcome& o, const std::string& reason) {
  EXPECT_FALSE(o.opened);
  EXPECT_NE(o.error.find(reason), std::string::npos) << o.error;
}

TEST(IgtLinkMalformedInput, GoodFramesAloneAreReadWithNothingSkipped) {
  const Outcome o = feed({});
  ASSERT_TRUE(o.opened) << o.error;
  EXPECT_EQ(o.eye, cv::Size(160, 240));
  EXPECT_EQ(o.malformed, 0);
  EXPECT_TRUE(o.warnings.empty());
}

TEST(IgtLinkMalformedInput, HugeImageWithFewPixelBytesIsSkipped) {
  // Was a segmentation fault: 65535 x 65535 pixels claimed, 64 bytes sent.
  ImageHeader h;
  h.size[0] = h.size[1] = 65535;
  expectSkipped(feed(message("IMAGE", "Video", 1.0, imageBody(h, Bytes(64, 1)))),
                "need 12884508675 bytes, the body holds 64");
}

TEST(IgtLinkMalformedInput, BodyShorterThanTheImageHeaderIsSkipped) {
  // Was an abort: a 40-byte body.
  expectSkipped(feed(message("IMAGE", "Video", 1.0, Bytes(40, 3))),
                "a body of 40 bytes, shorter than the 72-byte image header");
}

TEST(IgtLinkMalformedInput, BodySizeIsReadAs64BitsAndAnImpossibleOneEndsTheInput) {
  // Was "a message of 1862270976 bytes": the size read as int.
  expectError(feed(header("IMAGE", "Video", 1.0, std::uint64_t(1) << 62, 0)), "of 4611686018427387904 bytes");
  expectError(feed(header("STATUS", "Keepalive", 1.0, (std::uint64_t(1) << 32) + 5, 0)),
              "a message of 4294967301 bytes (at most 268435456 are read; type 'STATUS')");
}

TEST(IgtLinkMalformedInput, SubVolumeOutsideTheImageIsSkipped) {
  ImageHeader h;
  h.subOffset[0] = 300;
  h.subSize[0] = 40;  // columns 300..339 of a 320-column image
  expectSkipped(feed(message("IMAGE", "Video", 1.0, imageBody(h, Bytes(40 * 240 * 3, 0)))),
                "a sub-volume (offset 300x0x0, size 40x240x1) outside the 320x240x1 image");
}

TEST(IgtLinkMalformedInput, EmptyImageAndUnknownScalarTypeAreSkipped) {
  ImageHeader empty;
  empty.size[0] = empty.size[1] = 0;
  expectSkipped(feed(message("IMAGE", "Video", 1.0, imageBody(empty, {}))), "an empty image (0x0x1 pixels");
  ImageHeader unknown;
  unknown.scalarType = 9;
  expectSkipped(feed(message("IMAGE", "Video", 1.0, imageBody(unknown, goodPixels(0)))), "unknown scalar type 9");
}

TEST(IgtLinkMalformedInput, BodyFailingItsCrcIsSkippedAndCounted) {
  Bytes bad = goodFrame(0);
  bad.back() ^= 0xff;
  const Outcome o = feed(bad);
  ASSERT_TRUE(o.opened) << o.error;
  EXPECT_EQ(o.crcFailures, 1);
  EXPECT_EQ(o.malformed, 0);
}

TEST(IgtLinkMalformedInput, FormatsTheReaderDoesNotTakeEndTheInputClearly) {
  ImageHeader floats;
  floats.scalarType = 10;
  expectError(feed(message("IMAGE", "Video", 1.0, imageBody(floats, Bytes(320 * 240 * 3 * 4, 0)))),
              "pixels must be 8-bit with 1, 3 or 4 components");
  ImageHeader five;
  five.components = 5;
  expectError(feed(message("IMAGE", "Video", 1.0, imageBody(five, Bytes(320 * 240 * 5, 0)))),
              "pixels must be 8-bit with 1, 3 or 4 components");
  ImageHeader depth;
  depth.size[2] = 3;
  expectError(feed(message("IMAGE", "Video", 1.0, imageBody(depth, Bytes(320 * 240 * 3 * 3, 0)))),
              "not a 2D image (320x240x3)");
  ImageHeader part;  // a sub-volume within the image: valid, but not a whole frame
  part.subSize[1] = 120;
  expectError(feed(message("IMAGE", "Video", 1.0, imageBody(part, Bytes(320 * 120 * 3, 0)))), "whole frames");
}

TEST(IgtLinkMalformedInput, RandomBytesNeverCrash) {
  std::mt19937 random(54);
  for (int trial = 0; trial < 3; ++trial) {
    Bytes noise(2000);
    for (unsigned char& b : noise) b = static_cast<unsigned char>(random());
    const Outcome o = feed(noise);
    // 58 random bytes declare a body of ~2^63 bytes: the input ends naming it.
    expectError(o, "not an OpenIGTLink stream");
  }
}

TEST(IgtLinkMalformedInput, OtherMessagesAreSkippedWithoutHoldingTheirBodies) {
  // A 3 MB message of another device, then the frames: read through and skipped, not malformed.
  const Outcome o = feed(message("IMAGE", "Other", 1.0, Bytes(3 << 20, 5)));
  ASSERT_TRUE(o.opened) << o.error;
  EXPECT_EQ(o.malformed, 0);
  EXPECT_EQ(o.eye, cv::Size(160, 240));
}

}  // namespace
}  // namespace tissuemosaic::igtlink
