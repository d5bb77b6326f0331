#include "StopSignal.h"

#include <chrono>
#include <csignal>
#include <cstring>

namespace tissuemosaic::cli {
namespace {

volatile std::sig_atomic_t stopSignal = 0;

extern "C" void onStopSignal(int signal) {
  stopSignal = signal;
  std::signal(signal, SIG_DFL);  // the next one ends the program
}

}  // namespace

StopOnSignal::StopOnSignal(std::function<void()> onStop) : onStop_(std::move(onStop)) {
  stopSignal = 0;
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  watcher_ = std::thread([this] {
    while (!done_.load()) {
      if (stopSignal != 0) {
        if (onStop_) onStop_();
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
}

StopOnSignal::~StopOnSignal() {
  done_ = true;
  watcher_.join();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

bool StopOnSignal::requested() const { return stopSignal != 0; }

int StopOnSignal::signal() const { return stopSignal; }

void StopOnSignal::throwIfRequested(const std::string& what) const {
  const int number = stopSignal;
  if (number == 0) return;
  throw StoppedBySignal{number, "stopped by signal " + std::to_string(number) + " (" + strsignal(number) + ") " + what +
                                    ": the outputs hold those frames only"};
}

}  // namespace tissuemosaic::cli
