#pragma once
/// @file IgtLinkServer.h
/// @brief An OpenIGTLink server that never holds up its caller: an accept thread, and for every client a sender
/// thread (with a send timeout) and a receiver thread (skips what the client sends, notices it leaving). send()
/// only queues. Ordered messages (TRANSFORM, STATUS) queue per client up to a bound, the oldest dropped beyond it;
/// heavy ones (POLYDATA, IMAGE) keep only the newest unsent one per device name. A client that disconnects,
/// reconnects, stops reading or reads slowly affects nobody else. It listens on one address (loopback unless told
/// otherwise) and lets in at most Options::maxClients clients at once: a further connection is closed at once and
/// counted. What a client sends is read through readClientMessage (IgtLinkMessageReader.h) and discarded.
#include "IgtLinkMessages.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace tissuemosaic::igtlink {

struct IgtLinkServerCounters {
  long long connections = 0;      ///< clients accepted so far
  long long disconnections = 0;   ///< clients gone (closed, or dropped after a send failed or timed out)
  long long messagesSent = 0;     ///< to all clients
  long long messagesDropped = 0;  ///< queued for a client but replaced or pushed out before it could take them
  long long refused = 0;          ///< connections closed at once: maxClients were connected
  long long badClientMessages = 0;  ///< clients dropped for a header no OpenIGTLink message has
};

class IgtLinkServer {
public:
  static constexpr int kSlicerDefaultPort = 18944;

  struct Options {
    int sendTimeoutMs = 1000;          ///< a send that moves no byte for this long drops the client
    std::size_t maxQueuedMessages = 1000;  ///< ordered messages waiting per client (~30 s of TRANSFORMs)
    /// The IPv4 address (or host name) to listen on: loopback, so that only this computer's programs connect.
    /// "0.0.0.0" listens on every interface (docs/OPENIGTLINK.md says what that exposes).
    std::string bindAddress = kLoopback;
    int maxClients = 8;  ///< clients connected at once; further connections are closed at once and counted
  };
  static constexpr const char* kLoopback = "127.0.0.1";

  /// Listens on options.bindAddress, `port` (0: any free port, see port()). Throws Error when the address or the
  /// port cannot be bound or maxClients is below 1.
  explicit IgtLinkServer(int port, Options options);
  explicit IgtLinkServer(int port) : IgtLinkServer(port, Options{}) {}
  ~IgtLinkServer();
  IgtLinkServer(const IgtLinkServer&) = delete;
  IgtLinkServer& operator=(const IgtLinkServer&) = delete;

  int port() const { return port_; }
  /// The address the listening socket is bound to, as the system reports it ("127.0.0.1" by default).
  std::string boundAddress() const;
  /// Connections refused because maxClients were connected (also in counters()).
  long long refusedConnections() const { return refused_.load(); }
  int clientCount() const;
  /// Blocks until a client is connected or timeoutS passed; true when one is.
  bool waitForClient(double timeoutS) const;
  /// Queues `message` for every connected client and returns at once. latestOnly: replaces an unsent message of
  /// the same device name instead of queueing behind it.
  void send(const PackedMessage& message, bool latestOnly);
  /// Waits up to timeoutS for every client's queue to empty (before a clean shutdown); true when they did.
  bool flush(double timeoutS) const;
  IgtLinkServerCounters counters() const;

  struct Client;  ///< one connected client (IgtLinkServer.cpp)

private:
  void acceptLoop();
  void reapClosedClients();

  Options options_;
  int port_ = 0;
  struct Listener;
  std::unique_ptr<Listener> listener_;
  std::thread acceptThread_;
  std::atomic<bool> stop_{false};
  mutable std::mutex clientsMutex_;
  std::vector<std::shared_ptr<Client>> clients_;
  std::atomic<long long> connections_{0}, disconnections_{0};
  std::atomic<long long> sent_{0}, dropped_{0};
  std::atomic<long long> refused_{0}, badClientMessages_{0};
};

}  // namespace tissuemosaic::igtlink
