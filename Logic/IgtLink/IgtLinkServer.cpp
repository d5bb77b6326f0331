#include "IgtLinkServer.h"

#include "IgtLinkMessageReader.h"

#include "Core/Error.h"

#include <igtlMessageHeader.h>
#include <igtlServerSocket.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>

#include <arpa/inet.h>
#include <csignal>
#include <netdb.h>
#include <netinet/in.h>
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
constexpr std::uint64_t kLargestClientMessageBytes = 64 << 20;  ///< beyond: not an OpenIGTLink stream, dropped

/// The IPv4 address `host` names (a dotted address or a name such as localhost). False when it names none.
bool resolveIpv4(const std::string& host, sockaddr_in& address) {
  addrinfo hints{};
  hints.ai_family = AF_INET;  // 1.11's ServerSocket makes IPv4 sockets
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (host.empty() || getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || !found) return false;
  address = *reinterpret_cast<const sockaddr_in*>(found->ai_addr);
  freeaddrinfo(found);
  return true;
}

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

  /// Listens on `address`:`port` (0: any free port). False when it cannot be bound. 1.11's BindSocket binds every
  /// interface, hence bind() here.
  bool listenOn(sockaddr_in address, int port) {
    CloseSocket();
    m_SocketDescriptor = CreateSocket();
    if (m_SocketDescriptor < 0) return false;
    const int reuse = 1;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    if (setsockopt(m_SocketDescriptor, SOL_SOCKET, SO_REUSEADDR, &reuse, sizeof reuse) != 0 ||
        bind(m_SocketDescriptor, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
        Listen(m_SocketDescriptor) != 0) {
      CloseSocket();
      return false;
    }
    return true;
  }
  int descriptor() const { return m_SocketDescriptor; }
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
  require(options.maxClients >= 1, "the OpenIGTLink server needs room for at least 1 client");
  sockaddr_in address{};
  require(resolveIpv4(options.bindAddress, address),
          "cannot start the OpenIGTLink server on '" + options.bindAddress + "': not an IPv4 address of this computer");
  require(listener_->socket->listenOn(address, port),
          "cannot start the OpenIGTLink server on " + options.bindAddress + " port " + std::to_string(port) +
              ": the port is in use (another server, or Slicer in server mode?), the address is not this "
              "computer's, or it is not allowed");
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
    if (clientCount() >= options_.maxClients) {  // closed at once: a flood of connections costs no threads
      socket->CloseSocket();
      ++refused_;
      continue;
    }
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
    client->receiver = std::thread([this, c] {
      blockSigpipeInThisThread();
      // Clients may send STATUS, GET_* or their own data: none of it is used, but reading it keeps their sends
      // from blocking and tells when they leave. A header no OpenIGTLink message has drops the client.
      const ReceiveBytes receive = [c](void* data, std::size_t bytes) {
        return receiveExactly(*c, data, static_cast<int>(bytes));
      };
      std::string problem;
      ReadOutcome outcome;
      while ((outcome = readClientMessage(receive, problem, kLargestClientMessageBytes)) == ReadOutcome::Message) {
      }
      badClientMessages_ += outcome == ReadOutcome::Failed;
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
  return {connections_.load(), disconnections_.load(), sent_.load(), dropped_.load(), refused_.load(),
          badClientMessages_.load()};
}

std::string IgtLinkServer::boundAddress() const {
  sockaddr_in address{};
  socklen_t length = sizeof address;
  char text[INET_ADDRSTRLEN] = "";
  if (getsockname(listener_->socket->descriptor(), reinterpret_cast<sockaddr*>(&address), &length) != 0 ||
      !inet_ntop(AF_INET, &address.sin_addr, text, sizeof text))
    return "";
  return text;
}

}  // namespace tissuemosaic::igtlink
