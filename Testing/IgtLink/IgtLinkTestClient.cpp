// tm-igtl-test-client: an OpenIGTLink client written against the library's own classes (igtl::ClientSocket,
// igtl::MessageHeader, igtl::TransformMessage, ...) that receives everything a server sends until it closes, checks
// every body's CRC, and compares what came with the files the reconstruction wrote:
//   --expect-trajectory T   one TRANSFORM LeftCameraToModel per pose of T (TUM), equal to 1e-3 mm, same time stamps
//   --expect-model-ply M    the last POLYDATA TissueModel has M's vertex count, or --model-budget when M has more
// Misbehaving clients for robustness tests: --read-delay-ms D (sleeps D ms per message), --disconnect-after N (closes
// after N messages, then connects again once when --reconnect is given).
#include "IgtLinkTestReceive.h"
#include "IO/TrajectoryTum.h"

#include <igtlClientSocket.h>
#include <igtlImageMessage.h>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlStatusMessage.h>
#include <igtlTransformMessage.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace {

struct ReceivedTransform {
  std::string name;
  double timeS = 0;
  igtl::Matrix4x4 matrix;
};

struct Received {
  std::vector<ReceivedTransform> transforms;
  std::vector<int> modelPoints;
  bool modelColoursOk = true;
  std::vector<std::string> statuses;  ///< error names in order
  int images = 0, crcFailures = 0, other = 0;
};

/// Receives until the server closes (or `limit` messages). False when the connection broke mid-message.
bool receiveAll(igtl::ClientSocket* socket, Received& received, int limit, int delayMs) {
  for (int count = 0; limit < 0 || count < limit; ++count) {
    tissuemosaic::igtlink::testing::ReceivedMessage m;
    if (!tissuemosaic::igtlink::testing::receiveMessage(socket, m)) return true;  // the server closed
    if (!m.message) {
      ++received.other;
      continue;
    }
    if (!m.crcOk) {
      ++received.crcFailures;
      continue;
    }
    if (m.type == "TRANSFORM") {
      ReceivedTransform transform;
      transform.name = m.name;
      transform.timeS = m.timeS;
      static_cast<igtl::TransformMessage*>(m.message.GetPointer())->GetMatrix(transform.matrix);
      received.transforms.push_back(transform);
    } else if (m.type == "POLYDATA" && m.name == "TissueModel") {
      auto* message = static_cast<igtl::PolyDataMessage*>(m.message.GetPointer());
      const int points = message->GetPoints() ? message->GetPoints()->GetNumberOfPoints() : 0;
      received.modelPoints.push_back(points);
      bool colours = false;
      for (int a = 0; a < message->GetNumberOfAttributes(); ++a) {
        igtl::PolyDataAttribute* attribute = message->GetAttribute(a);
        if (std::string(attribute->GetName()) != "Colors") continue;
        colours = m.rgbaAttributes == 1 && attribute->GetNumberOfComponents() == 4 &&
                  static_cast<int>(attribute->GetSize()) == points;
        std::vector<igtlFloat32> values(4 * static_cast<std::size_t>(points));
        if (points > 0) attribute->GetData(values.data());
        for (float v : values) colours = colours && v >= 0 && v <= 1;
      }
      const bool vertices =
          message->GetVertices() && static_cast<int>(message->GetVertices()->GetNumberOfCells()) == points;
      received.modelColoursOk = received.modelColoursOk && colours && vertices;
    } else if (m.type == "STATUS") {
      received.statuses.push_back(static_cast<igtl::StatusMessage*>(m.message.GetPointer())->GetErrorName());
    } else if (m.type == "IMAGE") {
      ++received.images;
    } else {
      ++received.other;
    }
    if (delayMs > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
  }
  return true;
}

igtl::ClientSocket::Pointer connect(const std::string& host, int port, double timeoutS) {
  igtl::ClientSocket::Pointer socket = igtl::ClientSocket::New();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  while (socket->ConnectToServer(host.c_str(), port) != 0) {
    if (std::chrono::steady_clock::now() > deadline) return nullptr;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return socket;
}

long long plyVertexCount(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  for (std::string line; std::getline(file, line) && line.rfind("end_header", 0) != 0;) {
    if (line.rfind("element vertex ", 0) == 0) return std::stoll(line.substr(15));
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> options = {{"host", "localhost"}, {"connect-timeout", "60"},
                                                {"model-budget", "500000"}, {"read-delay-ms", "0"},
                                                {"disconnect-after", "-1"}};
  bool reconnect = false;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--reconnect") {
      reconnect = true;
    } else if (word.rfind("--", 0) == 0 && i + 1 < argc) {
      options[word.substr(2)] = argv[++i];
    } else {
      std::cerr << "tm-igtl-test-client: unexpected '" << word << "'\n";
      return 2;
    }
  }
  if (!options.count("port")) {
    std::cerr << "usage: tm-igtl-test-client --port P [--expect-trajectory T] [--expect-model-ply M] ...\n";
    return 2;
  }
  const int port = std::stoi(options["port"]);
  Received received;
  igtl::ClientSocket::Pointer socket = connect(options["host"], port, std::stod(options["connect-timeout"]));
  if (!socket) {
    std::cerr << "FAIL: no server on port " << port << "\n";
    return 1;
  }
  std::printf("connected to port %d\n", port);
  std::fflush(stdout);
  const int disconnectAfter = std::stoi(options["disconnect-after"]);
  bool whole = receiveAll(socket, received, disconnectAfter, std::stoi(options["read-delay-ms"]));
  socket->CloseSocket();
  if (disconnectAfter >= 0 && reconnect) {
    socket = connect(options["host"], port, 5.0);
    if (socket) whole = receiveAll(socket, received, -1, std::stoi(options["read-delay-ms"]));
  }
  std::printf("received %zu TRANSFORM, %zu POLYDATA TissueModel (last %d points), %zu STATUS, %d IMAGE, %d other; "
              "%d CRC failures\n",
              received.transforms.size(), received.modelPoints.size(),
              received.modelPoints.empty() ? -1 : received.modelPoints.back(), received.statuses.size(),
              received.images, received.other, received.crcFailures);
  bool pass = whole && received.crcFailures == 0;
  if (!whole) std::printf("FAIL: the connection broke in the middle of a message\n");

  if (options.count("expect-trajectory")) {
    const tissuemosaic::Trajectory poses = tissuemosaic::readTumTrajectory(options["expect-trajectory"]);
    double largestMm = 0, largestRotation = 0, largestTimeS = 0;
    bool names = true;
    for (std::size_t i = 0; i < std::min(poses.size(), received.transforms.size()); ++i) {
      const ReceivedTransform& t = received.transforms[i];
      names = names && t.name == "LeftCameraToModel";
      for (int r = 0; r < 3; ++r) {
        largestMm = std::max(largestMm, std::abs(t.matrix[r][3] - poses[i].T_world_camera(r, 3)));
        for (int c = 0; c < 3; ++c)
          largestRotation = std::max(largestRotation, std::abs(t.matrix[r][c] - poses[i].T_world_camera(r, c)));
      }
      largestTimeS = std::max(largestTimeS, std::abs(t.timeS - poses[i].timeS));
    }
    std::printf("trajectory: %zu poses, %zu transforms; largest difference %.2e mm, rotation %.2e, time %.2e s\n",
                poses.size(), received.transforms.size(), largestMm, largestRotation, largestTimeS);
    const bool same = names && poses.size() == received.transforms.size() && largestMm <= 1e-3 &&
                      largestRotation <= 1e-6 && largestTimeS <= 1e-5;
    if (!same) std::printf("FAIL: the transforms are not the trajectory\n");
    pass = pass && same;
  }
  if (options.count("expect-model-ply")) {
    const long long vertices = plyVertexCount(options["expect-model-ply"]);
    const long long expected = std::min(vertices, std::stoll(options["model-budget"]));
    const bool same = !received.modelPoints.empty() && received.modelPoints.back() == expected &&
                      received.modelColoursOk;
    std::printf("model: the file has %lld points; expected %lld in the last POLYDATA; colours %s\n", vertices,
                expected, received.modelColoursOk ? "POINT_RGBA 'Colors' in [0,1]" : "MISSING OR WRONG");
    if (!same) std::printf("FAIL: the last model message does not match the model file\n");
    const bool finished = !received.statuses.empty() && received.statuses.back() == "Finished";
    if (!finished) std::printf("FAIL: the last STATUS is not Finished\n");
    pass = pass && same && finished;
  }
  std::printf("%s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
