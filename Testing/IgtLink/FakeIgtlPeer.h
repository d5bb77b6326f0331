#pragma once
/// @file FakeIgtlPeer.h
/// @brief Test helpers on plain POSIX sockets, 127.0.0.1 only: a fake PLUS server and raw clients that send any bytes
/// (the OpenIGTLink classes cannot send a malformed message), and the OpenIGTLink message bytes they send, built by
/// hand: header (58 bytes) and IMAGE body (72-byte image header + pixels), big-endian, any field any value.
#include <igtl_util.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tissuemosaic::igtlink::testing {

using Bytes = std::vector<unsigned char>;

inline void putBigEndian(Bytes& out, std::uint64_t value, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<unsigned char>(value >> (8 * i)));
}

/// A message header; bodyBytes and crc as given (they need not match any body).
inline Bytes header(const std::string& type, const std::string& name, double timeS, std::uint64_t bodyBytes,
                    std::uint64_t crc) {
  Bytes out;
  putBigEndian(out, 1, 2);
  for (std::size_t i = 0; i < 12; ++i) out.push_back(i < type.size() ? type[i] : 0);
  for (std::size_t i = 0; i < 20; ++i) out.push_back(i < name.size() ? name[i] : 0);
  const auto seconds = static_cast<std::uint64_t>(timeS);
  putBigEndian(out, seconds << 32 | static_cast<std::uint64_t>((timeS - seconds) * 4294967296.0), 8);
  putBigEndian(out, bodyBytes, 8);
  putBigEndian(out, crc, 8);
  return out;
}

inline std::uint64_t crcOf(Bytes body) { return crc64(body.data(), body.size(), 0); }

/// A whole message: the header with the body's true size and CRC, then the body.
inline Bytes message(const std::string& type, const std::string& name, double timeS, const Bytes& body) {
  Bytes out = header(type, name, timeS, body.size(), crcOf(body));
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

struct ImageHeader {
  int version = 1, components = 3, scalarType = 3 /*uint8*/, endian = 1, coordinates = 2;
  int size[3] = {320, 240, 1};
  int subOffset[3] = {0, 0, 0};
  int subSize[3] = {-1, -1, -1};  ///< -1: the whole size
};

/// An IMAGE body: the image header, then `pixels`.
inline Bytes imageBody(const ImageHeader& h, const Bytes& pixels) {
  Bytes out;
  putBigEndian(out, h.version, 2);
  for (int v : {h.components, h.scalarType, h.endian, h.coordinates}) out.push_back(static_cast<unsigned char>(v));
  for (int a = 0; a < 3; ++a) putBigEndian(out, h.size[a], 2);
  const float matrix[12] = {1, 0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0};
  for (float f : matrix) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    putBigEndian(out, bits, 4);
  }
  for (int a = 0; a < 3; ++a) putBigEndian(out, h.subOffset[a], 2);
  for (int a = 0; a < 3; ++a) putBigEndian(out, h.subSize[a] < 0 ? h.size[a] : h.subSize[a], 2);
  out.insert(out.end(), pixels.begin(), pixels.end());
  return out;
}

inline sockaddr_in loopback(int port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return address;
}

/// A connected TCP socket (closed with the object).
class RawSocket {
public:
  explicit RawSocket(int fd = -1) : fd_(fd) {}
  RawSocket(RawSocket&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  RawSocket& operator=(RawSocket&& other) noexcept {
    std::swap(fd_, other.fd_);
    return *this;
  }
  ~RawSocket() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool valid() const { return fd_ >= 0; }
  int fd() const { return fd_; }

  /// Connects to address within timeoutMs; invalid when refused or timed out.
  static RawSocket connectTo(const sockaddr_in& address, int timeoutMs = 3000) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
    if (fd < 0) return RawSocket();
    RawSocket socket(fd);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      if (errno != EINPROGRESS) return RawSocket();
      pollfd p{fd, POLLOUT, 0};
      int error = 0;
      socklen_t length = sizeof error;
      if (::poll(&p, 1, timeoutMs) != 1 || ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) != 0 || error != 0)
        return RawSocket();
    }
    ::fcntl(fd, F_SETFL, 0);  // blocking again: reads below wait with poll
    return socket;
  }

  bool sendAll(const Bytes& bytes) const {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) return false;
      sent += static_cast<std::size_t>(n);
    }
    return true;
  }
  /// Exactly `bytes` bytes, each wait at most timeoutMs; false on a close, an error or a timeout.
  bool receiveAll(unsigned char* data, std::size_t bytes, int timeoutMs = 10000) const {
    std::size_t got = 0;
    while (got < bytes) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, timeoutMs) != 1) return false;
      const ssize_t n = ::recv(fd_, data + got, bytes - got, 0);
      if (n <= 0) return false;
      got += static_cast<std::size_t>(n);
    }
    return true;
  }
  /// True when the peer closed the connection within timeoutMs (bytes that come first are read and ignored).
  bool closedByPeer(int timeoutMs) const {
    unsigned char sink[4096];
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, timeoutMs) != 1) return false;
      const ssize_t n = ::recv(fd_, sink, sizeof sink, 0);
      if (n <= 0) return true;
    }
  }

private:
  int fd_ = -1;
};

/// A server on 127.0.0.1 (any free port) that accepts one client at a time.
class FakeServer {
public:
  FakeServer() : listener_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in address = loopback(0);
    socklen_t length = sizeof address;
    if (!listener_.valid() || ::bind(listener_.fd(), reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listener_.fd(), 16) != 0 ||
        ::getsockname(listener_.fd(), reinterpret_cast<sockaddr*>(&address), &length) != 0)
      return;
    port_ = ntohs(address.sin_port);
  }
  int port() const { return port_; }
  /// The next client, waiting at most timeoutMs (invalid when none came).
  RawSocket accept(int timeoutMs = 10000) {
    for (;;) {
      pollfd p{listener_.fd(), POLLIN, 0};
      if (::poll(&p, 1, timeoutMs) != 1) return RawSocket();
      // The video source first probes the port (connects and closes at once): skip connections already closed.
      RawSocket client(::accept(listener_.fd(), nullptr, nullptr));
      pollfd q{client.fd(), POLLIN, 0};
      if (::poll(&q, 1, 150) == 1) {
        char byte;
        if (::recv(client.fd(), &byte, 1, MSG_PEEK) == 0) continue;
      }
      return client;
    }
  }

private:
  RawSocket listener_;
  int port_ = 0;
};

}  // namespace tissuemosaic::igtlink::testing
