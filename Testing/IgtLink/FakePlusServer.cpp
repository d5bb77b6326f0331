// tm-igtl-fake-plus: a hostile or broken PLUS server for `reconstruct --igtl-input` (issue 54), on plain sockets
// (FakeIgtlPeer.h), 127.0.0.1 only. Writes its port to PORT_FILE, waits for the client, sends one malformed message
// of the case named, then the stereo frames of LEFT_DIR and RIGHT_DIR side by side as IMAGE "Video" (RGB, 30 per
// second), and closes.
//   tm-igtl-fake-plus PORT_FILE CASE LEFT_DIR RIGHT_DIR
#include "FakeIgtlPeer.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <thread>

using namespace tissuemosaic::igtlink::testing;

namespace {

Bytes pixelsOf(const cv::Mat& rgb) { return Bytes(rgb.data, rgb.data + rgb.total() * rgb.elemSize()); }

/// The malformed message of each case (the table, and more).
Bytes badMessage(const std::string& name, const cv::Size& frame) {
  ImageHeader h;
  h.size[0] = frame.width;
  h.size[1] = frame.height;
  const Bytes rgbPixels(static_cast<std::size_t>(frame.area()) * 3, 128);
  if (name == "none") return {};
  if (name == "huge_claim") {  // 65535 x 65535 pixels claimed, 64 bytes sent
    h.size[0] = h.size[1] = 65535;
    return message("IMAGE", "Video", 0.5, imageBody(h, Bytes(64, 1)));
  }
  if (name == "short_body") return message("IMAGE", "Video", 0.5, Bytes(40, 1));
  if (name == "body_2_pow_62") return header("IMAGE", "Video", 0.5, std::uint64_t(1) << 62, 0);
  if (name == "subvolume_outside") {
    h.subOffset[0] = frame.width - 10;
    h.subSize[0] = 20;
    return message("IMAGE", "Video", 0.5, imageBody(h, Bytes(20 * frame.height * 3, 1)));
  }
  if (name == "zero_size") {
    h.size[0] = h.size[1] = 0;
    return message("IMAGE", "Video", 0.5, imageBody(h, {}));
  }
  if (name == "bad_crc") {
    Bytes m = message("IMAGE", "Video", 0.5, imageBody(h, rgbPixels));
    m.back() ^= 0x5a;
    return m;
  }
  if (name == "float_pixels") {
    h.scalarType = 10;
    return message("IMAGE", "Video", 0.5, imageBody(h, Bytes(rgbPixels.size() * 4, 0)));
  }
  if (name == "larger_frame") {  // well formed, 2000 x 1500, after the first good frame (sent before it)
    h.size[0] = 2000;
    h.size[1] = 1500;
    return message("IMAGE", "Video", 0.9, imageBody(h, Bytes(2000 * 1500 * 3, 128)));
  }
  if (name == "random_bytes") {
    std::mt19937 random(54);
    Bytes noise(4096);
    for (unsigned char& b : noise) b = static_cast<unsigned char>(random());
    return noise;
  }
  throw std::runtime_error("unknown case '" + name + "'");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: tm-igtl-fake-plus PORT_FILE CASE LEFT_DIR RIGHT_DIR\n";
    return 2;
  }
  std::vector<std::filesystem::path> lefts, rights;
  for (const auto& e : std::filesystem::directory_iterator(argv[3])) lefts.push_back(e.path());
  for (const auto& e : std::filesystem::directory_iterator(argv[4])) rights.push_back(e.path());
  std::sort(lefts.begin(), lefts.end());
  std::sort(rights.begin(), rights.end());
  if (lefts.empty() || lefts.size() != rights.size()) {
    std::cerr << "tm-igtl-fake-plus: no frames, or unequal counts\n";
    return 2;
  }
  FakeServer server;
  {
    std::ofstream(std::string(argv[1]) + ".tmp") << server.port() << "\n";
    std::filesystem::rename(std::string(argv[1]) + ".tmp", argv[1]);  // whole, so a reader never sees half
  }
  RawSocket client = server.accept(60000);
  if (!client.valid()) {
    std::cerr << "tm-igtl-fake-plus: no client came\n";
    return 1;
  }
  cv::Mat sbs;
  cv::hconcat(cv::imread(lefts[0].string()), cv::imread(rights[0].string()), sbs);
  const Bytes bad = badMessage(argv[2], sbs.size());
  if (std::string(argv[2]) == "larger_frame") {  // a first frame fixes the stream's size
    cv::Mat rgb;
    cv::cvtColor(sbs, rgb, cv::COLOR_BGR2RGB);
    ImageHeader h;
    h.size[0] = rgb.cols;
    h.size[1] = rgb.rows;
    client.sendAll(message("IMAGE", "Video", 0.8, imageBody(h, pixelsOf(rgb))));
  }
  if (!bad.empty()) client.sendAll(bad);
  // PLUS sends keep-alives between frames.
  client.sendAll(message("STATUS", "Keepalive", 0.6, Bytes(30, 0)));
  int sent = 0;
  for (std::size_t i = 0; i < lefts.size(); ++i) {
    cv::Mat rgb;
    cv::hconcat(cv::imread(lefts[i].string()), cv::imread(rights[i].string()), sbs);
    cv::cvtColor(sbs, rgb, cv::COLOR_BGR2RGB);
    ImageHeader h;
    h.size[0] = rgb.cols;
    h.size[1] = rgb.rows;
    if (!client.sendAll(message("IMAGE", "Video", 1.0 + i / 30.0, imageBody(h, pixelsOf(rgb))))) break;
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
  }
  std::cout << "tm-igtl-fake-plus: case " << argv[2] << ", " << sent << " frames sent\n";
  return 0;
}
