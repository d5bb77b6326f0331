#include "IgtLinkServer.h"

#include "Core/Error.h"

#include <igtlMessageHeader.h>
#include <igtlServerSocket.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>

#include <csignal>
#include <pthread.h>
#include <sys/socket.h>

namespace tissuemosaic::igtlink {
namespace {

/// OpenIGTLink 1.11 sends without MSG_NOSIGNAL: a send to a closed peer raises SIGPIPE, which would end the whole
/// program. Blocked in the socket threads, it is discarded and the send fails with EPIPE instead.
void blockSigpipeInThisThread() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

constexpr int kAcceptPollMs = 200;
constexpr int kReceivePollMs = 200;
constexpr std::size_t kSendPieceBytes = 256 * 1024;
constexpr int kLargestClientMessageBytes = 64 << 20;  ///< beyond: not an OpenIGTLink stream, the client is dropped

/// OpenIGTLink's ServerSocket::CreateServer binds without SO_REUSEADDR (its guard, VTK_HAVE_SO_REUSEADDR, is a VTK
/// macro that OpenIGTLink never defines on Linux). A server that closed its clients leaves their connections in
/// TCP's TIME_WAIT for a minute, and until then a new server on the same port (the next scan, or the app's server
/// turned off and on) was refused as "in use". With SO_REUSEADDR the port is free again at once; a port another
/// server listens on is still refused.
class ReusableServerSocket : public igtl::ServerSocket {
 public:
  typedef ReusableServerSocket Self;
  typedef igtl::SmartPointer<Self> Pointer;
  igtlNewMacro(Self);

  /// Listens on `port` (0: any free port). False when the port cannot be bound.
  bool listenOn(int port) {
    CloseSocket();
    m_SocketDescriptor = CreateSocket();
    if (m_SocketDescriptor < 0) return false;
    const int reuse = 1;
    if (setsockopt(m_SocketDescriptor, SOL_SOCKET, SO_REUSEADDR, &reuse, sizeof reuse) != 0 ||
        BindSocket(m_SocketDescriptor, port) != 0 || Listen(m_SocketDescriptor) != 0) {
      CloseSocket();
      return false;
    }
    return true;
  }
};
}  // namespace

struct IgtLinkServer::Listener {
  ReusableServerSocket::Pointer socket = ReusableServerSocket::New();
};

struct IgtLinkServer::Client {
  igtl::ClientSocket::Pointer socket;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<PackedMessage> ordered;
  std::map<std::string, PackedMessage> latest;  ///< by device name
  bool sending = false;                        ///< a message is on its way (flush waits for it)
  std::atomic<bool> closed{false};
  std::thread sender, receiver;

  bool idle() {
    std::lock_guard<std::mutex> lock(mutex);
    return closed || (ordered.empty() && latest.empty() && !sending);
  }
  void close() {
    closed = true;
    std::lock_guard<std::mutex> lock(mutex);
    changed.notify_all();
  }
};

namespace {
/// Receives exactly `length` bytes in pieces (the socket's receive timeout bounds each wait), giving up when the
/// client closes or is closed: a plain readFully receive would not notice a shutdown.
bool receiveExactly(IgtLinkServer::Client& client, void* data, int length) {
  auto* bytes = static_cast<unsigned char*>(data);
  int total = 0;
  while (total < length) {
    if (client.closed) return false;
    const int n = client.socket->Receive(bytes + total, length - total, 0);
    if (n == 0) return false;  // the peer closed, or an error
    if (n > 0) total += n;     // n < 0: the receive timeout passed with nothing
  }
  return true;
}
}  // namespace

IgtLinkServer::IgtLinkServer(int port, Options options) : options_(options), listener_(std::make_unique<Listener>()) {
  require(port >= 0 && port <= 65535, "OpenIGTLink port " + std::to_string(port) + " is not in 0..65535");
  require(listener_->socket->listenOn(port),
          "cannot start the OpenIGTLink server on port " + std::to_string(port) +
              ": the port is in use (another server, or Slicer in server mode?) or not allowed");
  port_ = listener_->socket->GetServerPort();
  acceptThread_ = std::thread([this] { acceptLoop(); });
}

IgtLinkServer::~IgtLinkServer() {
  stop_ = true;
  if (acceptThread_.joinable()) acceptThread_.join();
  std::vector<std::shared_ptr<Client>> clients;
  {
    std::lock_guard<std::mutex> lock(clientsMutex_);
    clients.swap(clients_);
  }
  for (auto& client : clients) client->close();
  for (auto& client : clients) {
    if (client->sender.joinable()) client->sender.join();
    if (client->receiver.joinable()) client->receiver.join();
    client->socket->CloseSocket();
  }
  listener_->socket->CloseSocket();
}

void IgtLinkServer::acceptLoop() {
  blockSigpipeInThisThread();
  while (!stop_) {
    igtl::ClientSocket::Pointer socket = listener_->socket->WaitForConnection(kAcceptPollMs);
    reapClosedClients();
    if (!socket || !socket->GetConnected()) continue;
    socket->SetSendTimeout(options_.sendTimeoutMs);
    socket->SetReceiveTimeout(kReceivePollMs);
    auto client = std::make_shared<Client>();
    client->socket = socket;
    Client* c = client.get();
    client->sender = std::thread([this, c] {
      blockSigpipeInThisThread();
      for (;;) {
        PackedMessage message;
        {
          std::unique_lock<std::mutex> lock(c->mutex);
          c->sending = false;
          c->changed.notify_all();
          c->changed.wait(lock, [c] { return c->closed || !c->ordered.empty() || !c->latest.empty(); });
          if (c->closed) return;
          if (!c->ordered.empty()) {
            message = std::move(c->ordered.front());
            c->ordered.pop_front();
          } else {
            message = std::move(c->latest.begin()->second);
            c->latest.erase(c->latest.begin());
          }
          c->sending = true;
        }
        // In pieces, so that a shutdown waits for one piece at most, not for a slow client to take 15 MB.
        for (std::size_t offset = 0; offset < message.size(); offset += kSendPieceBytes) {
          const int piece = static_cast<int>(std::min(kSendPieceBytes, message.size() - offset));
          if (c->closed || c->socket->Send(message.bytes->data() + offset, piece) == 0) {
            c->close();  // closed by the peer, no progress within the send timeout, or shutting down
            return;
          }
        }
        ++sent_;
      }
    });
    client->receiver = std::thread([c] {
      blockSigpipeInThisThread();
      // Clients may send STATUS, GET_* or their own data: none of it is used, but reading it keeps their sends
      // from blocking and tells when they leave.
      igtl::MessageHeader::Pointer header = igtl::MessageHeader::New();
      std::vector<unsigned char> body;
      for (;;) {
        header->InitPack();  // sizes the buffer for one header
        if (!receiveExactly(*c, header->GetPackPointer(), header->GetPackSize())) break;
        header->Unpack();
        if (header->GetBodySizeToRead() < 0 || header->GetBodySizeToRead() > kLargestClientMessageBytes) break;
        body.resize(static_cast<std::size_t>(header->GetBodySizeToRead()));
        if (!body.empty() && !receiveExactly(*c, body.data(), static_cast<int>(body.size()))) break;
      }
      c->close();
    });
    {
      std::lock_guard<std::mutex> lock(clientsMutex_);
      clients_.push_back(std::move(client));
    }
    ++connections_;
  }
}

void IgtLinkServer::reapClosedClients() {
  std::vector<std::shared_ptr<Client>> closed;
  {
    std::lock_guard<std::mutex> lock(clientsMutex_);
    for (auto it = clients_.begin(); it != clients_.end();) {
      if ((*it)->closed) {
        closed.push_back(*it);
        it = clients_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (auto& client : closed) {
    client->close();
    if (client->sender.joinable()) client->sender.join();
    if (client->receiver.joinable()) client->receiver.join();
    client->socket->CloseSocket();
    ++disconnections_;
  }
}

int IgtLinkServer::clientCount() const {
  std::lock_guard<std::mutex> lock(clientsMutex_);
  int open = 0;
  for (const auto& client : clients_) open += !client->closed;
  return open;
}

bool IgtLinkServer::waitForClient(double timeoutS) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  while (clientCount() == 0) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

void IgtLinkServer::send(const PackedMessage& message, bool latestOnly) {
  require(message.bytes != nullptr, "an OpenIGTLink message must be packed before it is sent");
  std::lock_guard<std::mutex> lock(clientsMutex_);
  for (const auto& client : clients_) {
    if (client->closed) continue;
    std::lock_guard<std::mutex> clientLock(client->mutex);
    if (latestOnly) {
      auto [it, inserted] = client->latest.insert_or_assign(message.deviceName, message);
      if (!inserted) ++dropped_;
    } else {
      client->ordered.push_back(message);
      if (client->ordered.size() > options_.maxQueuedMessages) {
        client->ordered.pop_front();
        ++dropped_;
      }
    }
    client->changed.notify_all();
  }
}

bool IgtLinkServer::flush(double timeoutS) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutS);
  for (;;) {
    bool idle = true;
    {
      std::lock_guard<std::mutex> lock(clientsMutex_);
      for (const auto& client : clients_) idle = idle && client->idle();
    }
    if (idle) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

IgtLinkServerCounters IgtLinkServer::counters() const {
  return {connections_.load(), disconnections_.load(), sent_.load(), dropped_.load()};
}

}  // namespace tissuemosaic::igtlink
