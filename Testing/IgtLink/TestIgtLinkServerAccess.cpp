// Who the OpenIGTLink server lets in (issue 54): by default only this computer (loopback), at most maxClients at
// once (a further connection is closed at once and counted, the others get every message), and a client that sends
// a header no OpenIGTLink message has is dropped alone. Raw sockets on 127.0.0.1 (FakeIgtlPeer.h).
#include "Core/Error.h"
#include "FakeIgtlPeer.h"
#include "IgtLinkMessageCheck.h"
#include "IgtLinkServer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>

#include <ifaddrs.h>
#include <net/if.h>

namespace tissuemosaic::igtlink {
namespace {

using namespace testing;
using Clock = std::chrono::steady_clock;

/// This machine's IPv4 addresses other than loopback (interfaces that are up).
std::vector<in_addr> nonLoopbackAddresses() {
  std::vector<in_addr> found;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return found;
  for (ifaddrs* a = list; a; a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET || (a->ifa_flags & IFF_LOOPBACK) || !(a->ifa_flags & IFF_UP))
      continue;
    found.push_back(reinterpret_cast<const sockaddr_in*>(a->ifa_addr)->sin_addr);
  }
  freeifaddrs(list);
  return found;
}

sockaddr_in at(in_addr host, int port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr = host;
  return address;
}

template <class Condition>
bool waitFor(Condition condition, double seconds = 5.0) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  while (!condition()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

TEST(IgtLinkServerAccess, ListensOnLoopbackByDefault) {
  IgtLinkServer server(0);
  EXPECT_EQ(server.boundAddress(), "127.0.0.1");
  EXPECT_TRUE(RawSocket::connectTo(loopback(server.port())).valid());
  const std::vector<in_addr> others = nonLoopbackAddresses();
  if (others.empty()) {
    std::cout << "this machine has no address but loopback: the bound address alone is checked\n";
    return;
  }
  for (const in_addr& other : others) {
    EXPECT_FALSE(RawSocket::connectTo(at(other, server.port())).valid())
        << "reachable on " << inet_ntoa(other) << " though bound to loopback";
  }
  // The control: a server told to listen on every interface is reachable there, so the check above can fail.
  IgtLinkServer::Options everywhere;
  everywhere.bindAddress = "0.0.0.0";
  IgtLinkServer open(0, everywhere);
  EXPECT_EQ(open.boundAddress(), "0.0.0.0");
  EXPECT_TRUE(RawSocket::connectTo(at(others.front(), open.port())).valid());
}

TEST(IgtLinkServerAccess, AnAddressNotOfThisComputerIsAClearError) {
  IgtLinkServer::Options options;
  options.bindAddress = "203.0.113.7";  // TEST-NET-3: never a local address
  try {
    IgtLinkServer server(0, options);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("on 203.0.113.7 port 0"), std::string::npos) << e.what();
  }
  options.bindAddress = "not an address";
  EXPECT_THROW(IgtLinkServer(0, options), Error);
  options.bindAddress = "127.0.0.1";
  options.maxClients = 0;
  EXPECT_THROW(IgtLinkServer(0, options), Error);
}

/// Reads `count` messages from a raw client: their types.
std::vector<std::string> readTypes(const RawSocket& client, int count) {
  std::vector<std::string> types;
  for (int i = 0; i < count; ++i) {
    unsigned char bytes[kHeaderBytes];
    if (!client.receiveAll(bytes, sizeof bytes)) break;
    HeaderFields header;
    std::string problem;
    if (!checkHeader(bytes, 1 << 20, header, problem)) break;
    Bytes body(header.bodyBytes);
    if (!client.receiveAll(body.data(), body.size())) break;
    types.push_back(header.type);
  }
  return types;
}

TEST(IgtLinkServerAccess, TheNinthClientIsRefusedWhileEightGetEveryTransform) {
  IgtLinkServer::Options options;
  options.maxClients = 8;
  IgtLinkServer server(0, options);
  std::vector<RawSocket> clients;
  for (int i = 0; i < 8; ++i) {
    clients.push_back(RawSocket::connectTo(loopback(server.port())));
    ASSERT_TRUE(clients.back().valid());
  }
  ASSERT_TRUE(waitFor([&] { return server.clientCount() == 8; })) << server.clientCount();
  RawSocket ninth = RawSocket::connectTo(loopback(server.port()));  // TCP lets it in; the server closes it
  ASSERT_TRUE(ninth.valid());
  EXPECT_TRUE(ninth.closedByPeer(5000)) << "the ninth connection was not closed";
  EXPECT_TRUE(waitFor([&] { return server.refusedConnections() == 1; }));
  EXPECT_EQ(server.counters().refused, 1);
  EXPECT_EQ(server.clientCount(), 8);

  constexpr int kTransforms = 100;
  std::vector<std::future<std::vector<std::string>>> readers;
  for (const RawSocket& client : clients)
    readers.push_back(std::async(std::launch::async, [&client] { return readTypes(client, kTransforms); }));
  for (int i = 0; i < kTransforms; ++i) {
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T(0, 3) = i;
    server.send(packTransform(kCameraTransformName, T, i / 30.0), false);
  }
  for (auto& reader : readers) {
    const std::vector<std::string> types = reader.get();
    EXPECT_EQ(types.size(), static_cast<std::size_t>(kTransforms)) << "a client missed a TRANSFORM";
    for (const std::string& type : types) EXPECT_EQ(type, "TRANSFORM");
  }
  // Counted once the send returned, which may be just after the client has read the bytes.
  EXPECT_TRUE(waitFor([&] { return server.counters().messagesSent == 8 * kTransforms; }))
      << server.counters().messagesSent;

  // A place that frees up is taken again.
  clients.pop_back();
  ASSERT_TRUE(waitFor([&] { return server.clientCount() == 7; }));
  RawSocket again = RawSocket::connectTo(loopback(server.port()));
  ASSERT_TRUE(waitFor([&] { return server.clientCount() == 8; }));
  EXPECT_EQ(server.refusedConnections(), 1);
}

TEST(IgtLinkServerAccess, AClientSendingAnImpossibleHeaderIsDroppedAlone) {
  IgtLinkServer server(0);
  RawSocket bad = RawSocket::connectTo(loopback(server.port()));
  RawSocket good = RawSocket::connectTo(loopback(server.port()));
  ASSERT_TRUE(waitFor([&] { return server.clientCount() == 2; }));
  // A header claiming a 2^62-byte body (read as 64 bits: beyond any message the server reads).
  ASSERT_TRUE(bad.sendAll(header("STATUS", "Hostile", 0, std::uint64_t(1) << 62, 0)));
  EXPECT_TRUE(bad.closedByPeer(5000));
  EXPECT_TRUE(waitFor([&] { return server.counters().badClientMessages == 1 && server.clientCount() == 1; }));
  // Well-formed messages from a client are read and ignored.
  ASSERT_TRUE(good.sendAll(message("STATUS", "Client", 0, Bytes(30, 0))));
  server.send(packTransform(kCameraTransformName, Eigen::Matrix4d::Identity(), 1.0), false);
  EXPECT_EQ(readTypes(good, 1), std::vector<std::string>{"TRANSFORM"});
  EXPECT_EQ(server.clientCount(), 1);
}

}  // namespace
}  // namespace tissuemosaic::igtlink
