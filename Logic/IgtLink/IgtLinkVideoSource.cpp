#include "IgtLinkVideoSource.h"

#include "Core/Error.h"
#include "Core/PixelFormat.h"

#include "IgtLinkMessageReader.h"

#include <igtlClientSocket.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <deque>
#include <mutex>
#include <thread>

#include <netdb.h>
#include <pthread.h>
#include <sys/socket.h>
#include <unistd.h>

namespace tissuemosaic::igtlink {

void IgtLinkVideoInput::parseAddress(const std::string& address, std::string& host, int& port) {
  const std::size_t colon = address.rfind(':');
  const std::string portText = colon == std::string::npos ? address : address.substr(colon + 1);
  host = colon == std::string::npos || colon == 0 ? "localhost" : address.substr(0, colon);
  char* end = nullptr;
  const long value = std::strtol(portText.c_str(), &end, 10);
  require(!portText.empty() && end && *end == '\0' && value > 0 && value <= 65535,
          "OpenIGTLink address '" + address + "' is not HOST:PORT (e.g. localhost:18944)");
  port = static_cast<int>(value);
}

namespace {

constexpr int kReceivePollMs = 200;

/// True when something accepts TCP connections at host:port (the connection is closed at once).
bool serverListening(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return false;
  bool listening = false;
  for (addrinfo* a = found; a && !listening; a = a->ai_next) {
    const int probe = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (probe < 0) continue;
    listening = connect(probe, a->ai_addr, a->ai_addrlen) == 0;
    close(probe);
  }
  freeaddrinfo(found);
  return listening;
}
constexpr std::size_t kFramesKeptPerStream = 8;  ///< enough to pair streams that arrive a few frames apart
constexpr long long kWarningsTold = 5;

struct TimedImage {
  double timeS = 0;
  cv::Mat bgr;
};

class IgtLinkStereoSource : public StereoFrameSource, public IgtLinkInputCounters {
public:
  explicit IgtLinkStereoSource(const IgtLinkVideoInput& input) : input_(input) {
    require(input.packedName.empty() != (input.leftName.empty() && input.rightName.empty()),
            "give either the left and right IMAGE stream names or one packed stream name");
    require(!input.packedName.empty() || (!input.leftName.empty() && !input.rightName.empty()),
            "OpenIGTLink input: give both --igtl-left and --igtl-right");
    description_ = "OpenIGTLink server " + input.host + ":" + std::to_string(input.port) +
                   (input.packedName.empty() ? " IMAGE '" + input.leftName + "' and '" + input.rightName + "'"
                                             : " IMAGE '" + input.packedName + "' (" +
                                                   videoLayoutName(input.layout) + ")");
    socket_ = igtl::ClientSocket::New();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(input.connectTimeoutS);
    // As OpenIGTLinkIO's client: retry every 100 ms while the server is not there yet. Probed first, because
    // 1.11's ConnectToServer prints an error to stderr at every refused attempt.
    while (!serverListening(input.host, input.port) ||
           socket_->ConnectToServer(input.host.c_str(), input.port) != 0) {
      require(std::chrono::steady_clock::now() < deadline,
              "cannot connect to the " + description_ + " within " + cv::format("%g", input.connectTimeoutS) + " s");
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    socket_->SetReceiveTimeout(kReceivePollMs);
    thread_ = std::thread([this] { receiveLoop(); });
    StereoFrame first;
    std::unique_lock<std::mutex> lock(mutex_);
    const bool arrived = changed_.wait_for(lock, std::chrono::duration<double>(input.connectTimeoutS), [&] {
      return ended_ || newestPairLocked(first, false);
    });
    if (!arrived || ended_) {
      lock.unlock();
      interrupt();
      thread_.join();
      const std::string skipped =
          malformed_ > 0 ? " (" + std::to_string(malformed_.load()) + " malformed message(s) skipped, the last: " +
                               lastProblem_ + ")"
                         : "";
      if (!error_.empty()) throw Error(description_ + ": " + error_ + skipped);
      throw Error("no frame of the " + description_ + " came within " + cv::format("%g", input.connectTimeoutS) +
                  " s" + skipped);
    }
    size_ = first.left.size();
  }
  ~IgtLinkStereoSource() override {
    interrupt();
    if (thread_.joinable()) thread_.join();
    socket_->CloseSocket();
  }

  bool next(StereoFrame& frame) override {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return stop_ || ended_ || newestPairLocked(frame, false); });
    if (stop_ || !newestPairLocked(frame, true)) {
      require(error_.empty() || stop_, description_ + ": " + error_);
      return false;
    }
    require(frame.left.size() == size_ && frame.right.size() == size_,
            description_ + " changed its frame size to " + std::to_string(frame.left.cols) + "x" +
                std::to_string(frame.left.rows));
    frame.index = index_++;
    return true;
  }
  int frameCount() const override { return -1; }
  cv::Size frameSize() const override { return size_; }
  std::string description() const override { return description_; }
  bool isLive() const override { return true; }
  long long droppedFrames() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    long long waiting = 0;
    for (const TimedImage& image : streams_[0]) waiting += image.timeS > lastTakenS_;
    return arrived_ - taken_ - waiting;  // left (or packed) frames that arrived and will never be used
  }
  void interrupt() override {
    stop_ = true;
    std::lock_guard<std::mutex> lock(mutex_);
    changed_.notify_all();
  }
  long long framesFailingCrc() const override { return crcFailures_.load(); }
  long long malformedMessages() const override { return malformed_.load(); }
  std::string lastMalformed() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return lastProblem_;
  }

private:
  /// The newest complete stereo frame newer than the last one taken (take: mark it and everything older taken,
  /// counting the untaken older ones as dropped). Under mutex_.
  bool newestPairLocked(StereoFrame& frame, bool take) {
    if (!input_.packedName.empty()) {
      auto& stream = streams_[0];
      if (stream.empty() || stream.back().timeS <= lastTakenS_) return false;
      unpackStereoFrame(stream.back().bgr, input_.layout, frame.left, frame.right);
      frame.timeS = stream.back().timeS;
      if (take) takeUpTo(frame.timeS);
      return true;
    }
    // Newest left frame that has a right frame within the tolerance.
    for (auto left = streams_[0].rbegin(); left != streams_[0].rend(); ++left) {
      if (left->timeS <= lastTakenS_) break;
      for (const TimedImage& right : streams_[1]) {
        if (std::abs(right.timeS - left->timeS) > input_.pairToleranceS) continue;
        frame.left = left->bgr;
        frame.right = right.bgr;
        frame.timeS = left->timeS;
        if (take) takeUpTo(frame.timeS);
        return true;
      }
    }
    return false;
  }
  void takeUpTo(double timeS) {
    for (auto& stream : streams_) {
      while (!stream.empty() && stream.front().timeS <= timeS + input_.pairToleranceS) stream.pop_front();
    }
    lastTakenS_ = timeS;
    ++taken_;
  }

  bool receiveExactly(void* data, int length) {
    auto* bytes = static_cast<unsigned char*>(data);
    int total = 0;
    while (total < length) {
      if (stop_) return false;
      const int n = socket_->Receive(bytes + total, length - total, 0);
      if (n == 0) return false;
      if (n > 0) total += n;
    }
    return true;
  }

  void receiveLoop() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    IgtLinkVideoReader reader(input_.packedName.empty() ? std::vector<std::string>{input_.leftName, input_.rightName}
                                                        : std::vector<std::string>{input_.packedName});
    const ReceiveBytes receive = [this](void* data, std::size_t bytes) {
      return receiveExactly(data, static_cast<int>(bytes));
    };
    std::string error;
    while (!stop_) {
      IgtLinkVideoReader::Frame frame;
      std::string problem;
      const ReadOutcome outcome = reader.read(receive, frame, problem);
      if (outcome == ReadOutcome::Ended) break;
      if (outcome == ReadOutcome::Failed) {
        error = problem;
        break;
      }
      if (outcome == ReadOutcome::CrcFailed) ++crcFailures_;
      if (outcome == ReadOutcome::Malformed) {
        const long long count = ++malformed_;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          lastProblem_ = problem;
        }
        // The first few are told at once, the rest only counted (a broken sender would flood the log).
        if (input_.warn && count <= kWarningsTold) {
          input_.warn("OpenIGTLink input: skipped a malformed message: " + problem +
                      (count == kWarningsTold ? " (further ones are only counted)" : ""));
        }
      }
      if (outcome != ReadOutcome::Message) continue;
      TimedImage timed{frame.timeS, std::move(frame.bgr)};
      std::lock_guard<std::mutex> lock(mutex_);
      auto& frames = streams_[frame.stream];
      if (!frames.empty() && timed.timeS <= frames.back().timeS) continue;  // out of order: keep time monotonic
      frames.push_back(std::move(timed));
      arrived_ += frame.stream == 0;
      if (frames.size() > kFramesKeptPerStream) frames.pop_front();
      changed_.notify_all();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ended_ = true;
    error_ = error;
    changed_.notify_all();
  }

  IgtLinkVideoInput input_;
  std::string description_;
  igtl::ClientSocket::Pointer socket_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<TimedImage> streams_[2];
  long long arrived_ = 0, taken_ = 0;
  double lastTakenS_ = -1e300;
  bool ended_ = false;
  std::string error_;
  std::atomic<bool> stop_{false};
  std::atomic<long long> crcFailures_{0}, malformed_{0};
  std::string lastProblem_;
  cv::Size size_;
  int index_ = 0;
};

}  // namespace

std::unique_ptr<StereoFrameSource> openIgtLinkVideo(const IgtLinkVideoInput& input) {
  return std::make_unique<IgtLinkStereoSource>(input);
}

}  // namespace tissuemosaic::igtlink
